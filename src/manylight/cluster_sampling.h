// Sampling one light of a light-tree cluster in proportion to its importance at a shading point
// (Yuksel 2019, "Stochastic Lightcuts"): from the cluster's node down, each step takes a child
// with probability proportional to the child's importance at x, and the probabilities multiply
// to the pmf of the light reached. The light's exact contribution over that pmf is an unbiased
// estimate of the cluster's sum, whatever the lights' colours.
//
// A node's importance is that of the light BVH (lights/light_bounds.h, Conty Estevez & Kulla
// 2018, as Yuksel's): the lights' summed selection weight (the luminance of their intensities,
// light_tree.h), times the emitters' cosine bound towards x and the receiver's cosine bound
// towards the node, both over the box's bounding sphere, over the squared distance to the box's
// centre kept at least the sphere's squared radius. The cosine bounds are conservative: zero
// only where no light of the node can give x any light, so no light that contributes is ever
// given probability 0, which is what makes the estimate unbiased. Directional lights (no
// position) use the cone of their directions and the receiver's cosine bound of bounds.h. Spot
// lights (omni lights with a cone) bound their emission as pbrt-v4's SpotLight does (theta_o the
// inner cone, theta_e the falloff band), unioned up the tree: a cluster of spots aimed away from
// x has no importance there (the light tree's own omni cones, which Lightcuts' bounds read, stay
// the whole sphere).
//
// What a descent reads of each node is kept in a 64-byte node of its own, children side by side
// as in the tree, so that a step reads two adjacent cache lines and not the tree's large nodes.
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"
#include "lights/light_bounds.h"
#include "manylight/light_tree.h"

namespace ml {

// Where a cluster is seen from: the shading point, the shading normal facing the viewer, and
// whether the surface also transmits (both sides of the normal count; only directional lights
// tell the sides apart). A zero normal: a point in a medium, with no receiver cosine.
struct ClusterView {
    Vec3 x;
    Vec3 n;
    bool two_sided = false;
};

struct ClusterSample {
    int32_t light = -1;  // index into the point lights; -1: nothing below the node can be seen
    float pmf = 0;       // probability of that light, given the descent from the cluster's node
};

class ClusterSampler {
public:
    ClusterSampler() = default;
    // Keeps a pointer to `tree` (its directional nodes), which must outlive the sampler; `lights`
    // are the tree's lights (the cones of spot lights among them).
    ClusterSampler(const LightTree& tree, const std::vector<PointLight>& lights);

    // The importance of node i (an index of the tree) at the view.
    float importance(int32_t i, const ClusterView& view) const;
    // The probability of descending from node i to its first child (-1: neither child has any
    // importance); the one formula sample() and any pmf share.
    float first_child_probability(int32_t i, const ClusterView& view) const;
    // One light below node `from` for u uniform in [0, 1) (a leaf: its light, pmf 1).
    ClusterSample sample(int32_t from, const ClusterView& view, float u) const;

private:
    struct alignas(64) Node {
        ImportanceBounds bounds;
        int32_t children[2] = {-1, -1};
        int32_t light = -1;
        bool directional = false;
    };
    static_assert(sizeof(Node) == 64);
    std::vector<Node> m_nodes;
    const LightTree* m_tree = nullptr;
};

}  // namespace ml
