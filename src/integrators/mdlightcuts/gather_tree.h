// The gather tree of Multidimensional Lightcuts (Walter et al. 2006): a binary tree over the
// gather points of one pixel pass. Every node is a cluster of gather points with their summed
// RGB strength (the weights w_i the pixel's estimate gives them), the bounding box of their
// positions and a representative gather point, drawn in proportion to strength luminance. A
// node's representative is always one of its children's, so a pair that splits its gather node
// keeps the representative's shadow ray in one child.
#pragma once

#include <cstdint>
#include <vector>

#include "core/color.h"
#include "core/math.h"

namespace ml {

struct GatherTreeNode {
    Bounds3 bounds;                  // positions of the node's gather points
    RGB strength;                    // sum of their weights
    int32_t begin = 0, end = 0;      // members: GatherTree::members()[begin, end)
    int32_t children[2] = {-1, -1};  // both -1 for a leaf (a single gather point)
    int32_t rep = -1;                // the representative gather point (index into the input)

    bool is_leaf() const { return children[0] < 0; }
};

class GatherTree {
public:
    // Builds over n = p.size() points with weights w (>= 0 per channel) and one uniform number
    // u each (from the sampler): point i's u decides at most one internal node's choice of
    // representative, so the choices are independent. Splits recursively at the median of the
    // longest axis of the positions' box. Returns the index of the uniform left unused (every
    // choice takes one of the n - 1 others), or -1 when n == 0.
    int build(const std::vector<Vec3>& p, const std::vector<RGB>& w, const std::vector<float>& u);

    int32_t root() const { return m_nodes.empty() ? -1 : 0; }
    const GatherTreeNode& node(int32_t i) const { return m_nodes[size_t(i)]; }
    size_t node_count() const { return m_nodes.size(); }
    // The input indices, ordered so that each node's members are contiguous.
    const std::vector<int32_t>& members() const { return m_order; }

private:
    int32_t build_range(const std::vector<Vec3>& p, const std::vector<RGB>& w,
                        const std::vector<float>& u, int32_t begin, int32_t end);

    std::vector<GatherTreeNode> m_nodes;
    std::vector<int32_t> m_order;
};

}  // namespace ml
