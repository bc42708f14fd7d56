// Sampling one light of a light-tree cluster in proportion to its importance at a shading point
// (Yuksel 2019, "Stochastic Lightcuts"): from the cluster's node down, each step takes a child
// with probability proportional to the child's importance at x, and the probabilities multiply
// to the pmf of the light reached. The light's exact contribution over that pmf is an unbiased
// estimate of the cluster's sum, whatever the lights' colours.
//
// A node's importance (cluster_importance) is its lights' summed selection weight (the
// luminance of their intensities, light_tree.h) times the emitters' cosine or falloff bound
// towards x, times the receiver's cosine bound towards the node, over a squared distance that
// stays finite inside the node's box: the distance to the box's centre, but at least half its
// diagonal (a single light: its own distance). The two cosine bounds are those of Lightcuts'
// error bounds (bounds.h): zero only where no light of the node can give x any light, so no light
// that contributes is ever given probability 0, which is what makes the estimate unbiased.
#pragma once

#include <cstdint>

#include "core/math.h"
#include "manylight/light_tree.h"

namespace ml {

// Where a cluster is seen from: the shading point, the normal the receiver's cosine is taken
// about (the shading normal, facing the viewer) and whether the surface also transmits (both
// sides of the normal count).
struct ClusterView {
    Vec3 x;
    Vec3 n;
    bool two_sided = false;
};

float cluster_importance(const LightTreeNode& node, const ClusterView& view);

// The probability of descending from `node` to its first child (-1: neither child has any
// importance); the one formula the sampler and the pmf share (light_bvh.h).
float first_child_probability(const LightTree& tree, const LightTreeNode& node,
                              const ClusterView& view);

struct ClusterSample {
    int32_t light = -1;  // index into the point lights; -1: nothing below the node can be seen
    float pmf = 0;       // probability of that light, given the descent from the cluster's node
};

// One light below node `from` for u uniform in [0, 1) (a leaf: its light, pmf 1).
ClusterSample sample_cluster(const LightTree& tree, int32_t from, const ClusterView& view, float u);

}  // namespace ml
