#include "manylight/gather_tree.h"

#include <algorithm>

#include "core/rng.h"
#include "manylight/representative.h"

namespace ml {

int GatherTree::build(const std::vector<Vec3>& p, const std::vector<RGB>& w,
                      const std::vector<float>& u, const std::vector<uint8_t>& groups) {
    m_nodes.clear();
    m_order.resize(p.size());
    for (size_t i = 0; i < p.size(); ++i) m_order[i] = int32_t(i);
    if (p.empty()) return -1;
    m_nodes.reserve(2 * p.size() - 1);
    build_range(p, w, u, groups, 0, int32_t(p.size()));
    m_position.resize(p.size());
    for (size_t i = 0; i < p.size(); ++i) m_position[size_t(m_order[i])] = int32_t(i);
    // Every internal node's split position is a distinct member position in (0, n): the member
    // at position 0 never gives one its bits.
    return m_order[0];
}

int32_t GatherTree::split_groups(const std::vector<uint8_t>& groups, int32_t begin, int32_t end) {
    if (groups.empty()) return -1;
    uint8_t lowest = groups[size_t(m_order[size_t(begin)])], highest = lowest;
    for (int32_t i = begin; i < end; ++i) {
        lowest = std::min(lowest, groups[size_t(m_order[size_t(i)])]);
        highest = std::max(highest, groups[size_t(m_order[size_t(i)])]);
    }
    if (lowest == highest) return -1;
    // Stable, so the order (and every split after it) is the same on every platform and run.
    auto first_other =
        std::stable_partition(m_order.begin() + begin, m_order.begin() + end,
                              [&](int32_t a) { return groups[size_t(a)] == lowest; });
    return int32_t(first_other - m_order.begin());
}

int32_t GatherTree::build_range(const std::vector<Vec3>& p, const std::vector<RGB>& w,
                                const std::vector<float>& u, const std::vector<uint8_t>& groups,
                                int32_t begin, int32_t end) {
    int32_t id = int32_t(m_nodes.size());
    m_nodes.emplace_back();
    GatherTreeNode node;
    node.begin = begin, node.end = end;
    for (int32_t i = begin; i < end; ++i) {
        node.bounds.expand(p[size_t(m_order[size_t(i)])]);
        node.strength += w[size_t(m_order[size_t(i)])];
    }
    if (end - begin == 1) {
        node.point = m_order[size_t(begin)];
        node.weight = selection_weight(node.strength);
        m_nodes[size_t(id)] = node;
        return id;
    }
    // Groups apart first; within a group, split at the median along the longest axis (ties
    // broken by index, so the order is the same on every platform and run).
    int32_t mid = split_groups(groups, begin, end);
    if (mid < 0) {
        Vec3 d = node.bounds.diagonal();
        int axis = (d.x >= d.y && d.x >= d.z) ? 0 : (d.y >= d.z ? 1 : 2);
        mid = begin + (end - begin) / 2;
        std::nth_element(m_order.begin() + begin, m_order.begin() + mid, m_order.begin() + end,
                         [&](int32_t a, int32_t b) {
                             float pa = p[size_t(a)][axis], pb = p[size_t(b)][axis];
                             return pa < pb || (pa == pb && a < b);
                         });
    }
    int32_t left = build_range(p, w, u, groups, begin, mid);
    int32_t right = build_range(p, w, u, groups, mid, end);
    node.children[0] = left, node.children[1] = right;
    // The children are built, so the order of [begin, end) is final: the uniform of the member
    // at the split position is this node's, and no other node splits there.
    node.bits = uint32_t(double(u[size_t(m_order[size_t(mid)])]) * 4294967296.0);
    // The probabilities along the path from a node to a member multiply to the member's weight
    // over the node's, with the very weights the estimate's scale uses.
    node.weight = m_nodes[size_t(left)].weight + m_nodes[size_t(right)].weight;
    node.left_probability = node.weight > 0 ? m_nodes[size_t(left)].weight / node.weight : 0.5f;
    m_nodes[size_t(id)] = node;
    return id;
}

int32_t GatherTree::rep(int32_t i, uint32_t key) const {
    // The key is hashed once; each node's uniform is one mix of its bits with that (a bijection
    // of distinct inputs: the bits fill the high half, where the key's hash differs between keys).
    uint64_t key_hash = Rng::mix_bits(uint64_t(key) + 0x9e3779b97f4a7c15ULL);
    for (;;) {
        const GatherTreeNode& n = m_nodes[size_t(i)];
        if (n.is_leaf()) return n.point;
        // A uniform of the node's bits and the key: 24 bits of the hash.
        float v = float(Rng::mix_bits((uint64_t(n.bits) << 32) ^ key_hash) >> 40) * 0x1p-24f;
        i = n.children[v < n.left_probability ? 0 : 1];
    }
}

}  // namespace ml
