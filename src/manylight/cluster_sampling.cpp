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

bool is_spot(const PointLight& pl) {
    return pl.kind == PointLightKind::Omni && pl.surface < 0 && pl.cos_end > -1;
}

// A spot light emits at full intensity within theta_start of its axis and fades out by
// theta_end (point_light_intensity): pbrt-v4's bounds, theta_o = theta_start and theta_e =
// theta_end - theta_start, so that the importance is zero exactly where the cone cannot reach.
void set_spot_cone(ImportanceBounds& b, const PointLight& pl) {
    b.w = pl.n;
    b.cos_theta_o = pl.cos_start;
    b.sin_theta_o = safe_sqrt(1 - sqr(pl.cos_start));
    b.cos_theta_e = std::cos(std::max(0.f, safe_acos(pl.cos_end) - safe_acos(pl.cos_start)));
}

// Node i's cone of emitters as the union of its children's (each already set): the axes' cone
// of both, the wider theta_e. A child of weight 0 is never descended into and does not count.
void set_union_cone(ImportanceBounds& b, const ImportanceBounds& c0, float w0,
                    const ImportanceBounds& c1, float w1) {
    DirectionCone a(c0.w, c0.cos_theta_o), c(c1.w, c1.cos_theta_o);
    DirectionCone cone = !(w1 > 0) ? a : !(w0 > 0) ? c : union_cones(a, c);
    b.w = cone.axis;
    b.cos_theta_o = std::max(-1.f, cone.cos_theta);
    b.sin_theta_o = safe_sqrt(1 - sqr(b.cos_theta_o));
    b.cos_theta_e = !(w1 > 0)   ? c0.cos_theta_e
                    : !(w0 > 0) ? c1.cos_theta_e
                                : std::min(c0.cos_theta_e, c1.cos_theta_e);
}

}  // namespace

ClusterSampler::ClusterSampler(const LightTree& tree, const std::vector<PointLight>& lights)
    : m_nodes(tree.node_count()), m_tree(&tree) {
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
    // Spot lights are omni lights with a cone: their nodes take the cones of their emitters,
    // bottom-up (the tree lays children out after their parent), so that a cluster of spots
    // aimed away from x has no importance there. Without spots the omni nodes emit every way.
    if (std::none_of(lights.begin(), lights.end(), is_spot)) return;
    for (size_t i = m_nodes.size(); i-- > 0;) {
        const LightTreeNode& n = tree.node(int32_t(i));
        if (n.kind != PointLightKind::Omni) continue;
        Node& d = m_nodes[i];
        if (n.is_leaf()) {
            if (is_spot(lights[size_t(d.light)])) set_spot_cone(d.bounds, lights[size_t(d.light)]);
            continue;
        }
        set_union_cone(d.bounds, m_nodes[size_t(d.children[0])].bounds, tree.weight(d.children[0]),
                       m_nodes[size_t(d.children[1])].bounds, tree.weight(d.children[1]));
    }
}

float ClusterSampler::importance(int32_t i, const ClusterView& view) const {
    const Node& d = m_nodes[size_t(i)];
    if (!d.directional) return d.bounds.importance(view.x, view.n);
    float weight = m_tree->weight(i);
    if (!(weight > 0)) return 0;
    float receiver = view.n == Vec3()
                         ? 1.f
                         : receiver_cos_bound(m_tree->node(i), view.x, view.n, view.two_sided);
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
