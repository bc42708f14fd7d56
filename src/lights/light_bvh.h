// A bounding-volume hierarchy over light bounds (light_bounds.h), built once, for choosing one
// light in proportion to its importance at a shading point (Conty Estevez & Kulla 2018; pbrt-v4's
// BVHLightSampler): from the root, each step goes to a child with probability proportional to
// the child's importance at the point. pmf() walks the same path down to an item and multiplies
// the same probabilities, so it is exactly the probability that sample() returns the item.
//
// Items are anything with bounds: the scene's lights for the tree light sampler, point lights
// for stochastic lightcuts (a cut in this tree, then one descent below each cut node).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "lights/light_bounds.h"

namespace ml {

struct LightBvhNode {
    ImportanceBounds bounds;
    int32_t second = -1;  // interior: index of the second child (the first is the next node)
    int32_t item = -1;    // leaf: the item's index; -1 for interior nodes
    bool is_leaf() const { return item >= 0; }
};

struct LightBvhSample {
    int32_t item = -1;
    float pmf = 0;  // probability of this item, given the descent started at that node
};

class LightBvh {
public:
    LightBvh() = default;
    // Items with phi <= 0 (or empty boxes) are left out: they can never be chosen.
    explicit LightBvh(std::span<const LightBounds> items);

    bool empty() const { return m_nodes.empty(); }
    const LightBvhNode& node(int32_t i) const { return m_nodes[size_t(i)]; }
    size_t node_count() const { return m_nodes.size(); }

    // One item below node `from` (the root: 0), at shading point p with normal n (zero: none).
    // nullopt when no item below `from` has importance at p.
    std::optional<LightBvhSample> sample(const Vec3& p, const Vec3& n, float u,
                                         int32_t from = 0) const;
    // The probability that sample(p, n, u) from the root returns `item`, u uniform.
    float pmf(const Vec3& p, const Vec3& n, int32_t item) const;

private:
    int32_t build(std::vector<std::pair<int32_t, LightBounds>>& items, size_t begin, size_t end,
                  uint64_t trail, int depth);

    std::vector<LightBvhNode> m_nodes;
    // Per item: the branch taken at each level from the root (bit d: second child at depth d)
    // and the leaf's depth; depth -1 for an item not in the tree.
    std::vector<uint64_t> m_trail;
    std::vector<int8_t> m_depth;
};

// The probability of taking the first of two children with importances i0, i1, or -1 when
// neither has any; the one formula sample and pmf share, so that they agree to the bit.
inline float first_child_probability(float i0, float i1) {
    float s = i0 + i1;
    return s > 0 ? i0 / s : -1.f;
}

}  // namespace ml
