// Cluster representatives, for the light tree (Lightcuts) and the gather tree (Multidimensional
// Lightcuts): a cluster's members are picked with probability proportional to a scalar
// selection weight w_i, and the representative's own value v_rep, times the cluster's weight W
// over its own, stands for the cluster. Its expectation is the cluster's exact sum in every
// channel, whatever the members' colours:
//   E[v_rep W / w_rep] = sum_i (w_i / W) v_i (W / w_i) = sum_i v_i,
// summed over the members with w_i > 0, which are all those that can give light: a member
// weighs 0 only when each of its channels is 0. (Scaling each channel by the cluster's strength
// over the representative's in that channel, as before, is unbiased only when the members share
// one colour: a pure red representative of a red and green cluster gave 0 green.)
#pragma once

#include <algorithm>

#include "core/color.h"

namespace ml {

// The weight a cluster member is picked in proportion to: its luminance, or (where every
// non-zero channel underflows the luminance to 0) its largest channel; 0 only for black.
// Members' values are never negative.
inline float selection_weight(const RGB& v) {
    float l = v.luminance();
    if (l > 0) return l;
    float m = v.max_component();
    return m > 0 ? m : 0.f;
}

// The factor W / w_rep that makes a representative of weight w_rep stand for its cluster of
// weight W (0 for a representative that cannot have been picked).
inline float representative_scale(float cluster_weight, float rep_weight) {
    return rep_weight > 0 ? cluster_weight / rep_weight : 0.f;
}

}  // namespace ml
