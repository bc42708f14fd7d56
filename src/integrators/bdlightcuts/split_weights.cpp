#include "integrators/bdlightcuts/split_weights.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace ml {

float lobe_spread(float m) {
    if (!(m > 0)) return kInfinity;
    return 1.f / std::sqrt(kPi * m);
}

float split_weight(const SplitWeightOptions& o, float prefix, float mtd, float d, float mu) {
    float w = 1.f;
    if (o.energy) w = std::min(w, 1.f - prefix);
    if (o.clamp && mtd > 0) w = std::min(w, o.c_clamp / mtd);
    if (o.diffuse && d > 0) w = std::min(w, o.c_d / d);
    if (o.variance) w = std::min(w, mu - prefix);
    return std::isnan(w) ? 0.f : std::max(0.f, w);
}

float emission_weight(const SplitWeightOptions& o, float prefix) {
    return o.energy ? std::max(0.f, 1.f - prefix) : 1.f;
}

float vsp_weight_bound(const SplitWeightOptions& o, float prefix, float pending_mt, float dj_max,
                       float pending_mu, float mu) {
    if (pending_mt >= 0) {
        float mtd = pending_mt > 0 ? pending_mt * dj_max : 0.f;
        prefix += split_weight(o, prefix, mtd, dj_max, pending_mu);
    }
    // What the energy and variance weights leave for split j.
    float w = 1.f;
    if (o.energy) w = std::min(w, 1.f - prefix);
    if (o.variance) w = std::min(w, mu - prefix);
    return std::max(0.f, w);
}

float remainder_weight(const SplitWeightOptions& o, float prefix, float pending_mt, float d,
                       float pending_mu) {
    float w = 0.f;
    if (pending_mt >= 0)
        w = split_weight(o, prefix, pending_mt > 0 ? pending_mt * d : 0.f, d, pending_mu);
    // 1 - prefix - w_J, subtracted in this order: where the energy weight sets w_J = 1 - prefix,
    // r is 0 exactly.
    return std::max(0.f, (1.f - prefix) - w);
}

bool remainder_vanishes(const SplitWeightOptions& o, float prefix, float pending_mt, float d_max,
                        float pending_mu) {
    // r grows with D_{J+1} (w_J falls as M T D and D grow): at most its value at d_max.
    constexpr float kRounding = 1e-6f;
    return remainder_weight(o, prefix, pending_mt, d_max, pending_mu) <= kRounding;
}

}  // namespace ml
