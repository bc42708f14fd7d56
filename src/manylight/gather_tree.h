// The gather tree of Multidimensional Lightcuts (Walter et al. 2006): a binary tree over the
// gather points of one pixel pass. Every node is a cluster of gather points with their summed
// RGB strength (the weights w_i the pixel's estimate gives them), the bounding box of their
// positions and representatives drawn in proportion to their selection weights (the strengths'
// luminance, representative.h).
//
// A node has a representative per key (the product cut keys it by the light representative it
// is paired with): walking down from the node, each internal node picks a child with
// probability proportional to its strength, using a uniform hashed from the node's own sampler
// uniform and the key. So
// - member i is rep(G, key) with probability selection_weight(w_i) / weight_G, for every key,
//   and stands for G scaled by weight_G / selection_weight(w_i);
// - rep(G, key) is rep(C, key) of the child C that holds it: a pair that splits its gather node
//   keeps its representative's shadow ray in one child;
// - pairs with different light representatives shade with (nearly) independent gather
//   representatives. With one representative per node, every pair of a pixel's cut would use
//   the same gather point until the gather node is split: that point's departure from the
//   pixel's mean (a partial shadow, a texture) would then repeat in every pair and add up over
//   the cut instead of averaging out, several times the error threshold in most pixels.
#pragma once

#include <cstdint>
#include <vector>

#include "core/color.h"
#include "core/math.h"

namespace ml {

struct GatherTreeNode {
    Bounds3 bounds;                  // positions of the node's gather points
    RGB strength;                    // sum of their weights
    float weight = 0;                // sum of their selection weights (representative.h)
    int32_t begin = 0, end = 0;      // members: GatherTree::members()[begin, end)
    int32_t children[2] = {-1, -1};  // both -1 for a leaf (a single gather point)
    int32_t point = -1;              // a leaf's gather point (index into the input)
    uint32_t bits = 0;               // an internal node's random bits (from its sampler uniform)
    float left_probability = 0.5f;   // of choosing children[0]: its share of `weight`

    bool is_leaf() const { return children[0] < 0; }
};

class GatherTree {
public:
    // Builds over n = p.size() points with weights w (>= 0 per channel) and one uniform number
    // u each (from the sampler): point i's u gives at most one internal node its random bits.
    // Splits recursively at the median of the longest axis of the positions' box. With `groups`
    // (empty, or one per point), a node whose members belong to several groups splits off its
    // lowest group first (the left child), so that no node below those splits mixes groups
    // (bdlightcuts: the VSPs' eye depths). Returns the index of the uniform left unused (each of
    // the n - 1 internal nodes takes one of the others), or -1 when n == 0.
    int build(const std::vector<Vec3>& p, const std::vector<RGB>& w, const std::vector<float>& u,
              const std::vector<uint8_t>& groups = {});

    int32_t root() const { return m_nodes.empty() ? -1 : 0; }
    const GatherTreeNode& node(int32_t i) const { return m_nodes[size_t(i)]; }
    size_t node_count() const { return m_nodes.size(); }
    // The input indices, ordered so that each node's members are contiguous.
    const std::vector<int32_t>& members() const { return m_order; }
    // The representative gather point of node i for `key` (see above).
    int32_t rep(int32_t i, uint32_t key) const;
    // Whether gather point `point` (an input index) is a member of node i: O(1). A child that
    // holds its parent's representative for a key has it as its own for that key, no walk.
    bool holds(int32_t i, int32_t point) const {
        int32_t at = m_position[size_t(point)];
        return at >= m_nodes[size_t(i)].begin && at < m_nodes[size_t(i)].end;
    }

private:
    int32_t build_range(const std::vector<Vec3>& p, const std::vector<RGB>& w,
                        const std::vector<float>& u, const std::vector<uint8_t>& groups,
                        int32_t begin, int32_t end);
    // Where [begin, end) of the order mixes groups: orders its lowest group first and returns
    // where the others start; else -1.
    int32_t split_groups(const std::vector<uint8_t>& groups, int32_t begin, int32_t end);

    std::vector<GatherTreeNode> m_nodes;
    std::vector<int32_t> m_order;
    std::vector<int32_t> m_position;  // inverse of m_order: where each input index sits in it
};

}  // namespace ml
