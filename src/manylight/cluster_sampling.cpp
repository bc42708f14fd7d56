#include "manylight/cluster_sampling.h"

#include <algorithm>
#include <limits>

#include "core/parallel.h"
#include "lights/light_bvh.h"
#include "manylight/bounds.h"

namespace ml {

namespace {

// The light BVH's bounds of a node: the cone of normals of oriented lights emits a cosine lobe
// (theta_e = pi / 2); omni and glossy lights count as emitting every way (a glossy light's
// falloff is not a cone).
LightBounds importance_bounds(const LightTreeNode& n, float weight) {
    LightBounds b;
    b.box = n.bounds;
    b.phi = weight;
    if (n.kind == PointLightKind::Oriented) {
        b.w = n.cone.axis;
        b.cos_theta_o = n.cone.cos_theta;
        b.cos_theta_e = 0;
    } else {
        b.cos_theta_o = -1;
        b.cos_theta_e = -1;
    }
    return b;
}

}  // namespace

ClusterSampler::ClusterSampler(const LightTree& tree) : m_nodes(tree.node_count()), m_tree(&tree) {
    parallel_for(size_t(0), m_nodes.size(), [&](size_t i) {
        const LightTreeNode& n = tree.node(int32_t(i));
        Node& d = m_nodes[i];
        d.directional = n.kind == PointLightKind::Directional;
        if (!d.directional)
            d.bounds = ImportanceBounds(importance_bounds(n, tree.weight(int32_t(i))));
        d.children[0] = n.children()[0];
        d.children[1] = n.children()[1];
        d.light = tree.light(int32_t(i));
    });
}

float ClusterSampler::importance(int32_t i, const ClusterView& view) const {
    const Node& d = m_nodes[size_t(i)];
    if (!d.directional) return d.bounds.importance(view.x, view.n);
    float weight = m_tree->weight(i);
    if (!(weight > 0)) return 0;
    float receiver = receiver_cos_bound(m_tree->node(i), view.x, view.n, view.two_sided);
    // Never 0 for a node that can give light, even where the product underflows.
    return receiver > 0 ? std::max(weight * receiver, std::numeric_limits<float>::min()) : 0.f;
}

float ClusterSampler::first_child_probability(int32_t i, const ClusterView& view) const {
    const Node& d = m_nodes[size_t(i)];
    return ml::first_child_probability(importance(d.children[0], view),
                                       importance(d.children[1], view));
}

ClusterSample ClusterSampler::sample(int32_t from, const ClusterView& view, float u) const {
    int32_t i = from;
    float pmf = 1;
    while (m_nodes[size_t(i)].children[0] >= 0) {
        const Node& d = m_nodes[size_t(i)];
        float p0 = first_child_probability(i, view);
        if (!(p0 >= 0)) return {};
        if (u < p0) {
            pmf *= p0;
            u = std::min(u / p0, kOneMinusEpsilon);
            i = d.children[0];
        } else {
            pmf *= 1 - p0;
            u = std::min((u - p0) / (1 - p0), kOneMinusEpsilon);
            i = d.children[1];
        }
    }
    return {m_nodes[size_t(i)].light, pmf};
}

}  // namespace ml
