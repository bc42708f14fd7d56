#include "manylight/cluster_sampling.h"

#include <algorithm>
#include <limits>

#include "lights/light_bvh.h"
#include "manylight/bounds.h"

namespace ml {

float cluster_importance(const LightTreeNode& node, const ClusterView& view) {
    if (!(node.weight > 0)) return 0;
    float emitter = emitter_cos_bound(node, view.x);
    if (emitter == 0) return 0;
    float receiver = receiver_cos_bound(node, view.x, view.n, view.two_sided);
    if (receiver == 0) return 0;
    float d2 = 1;
    if (node.kind != PointLightKind::Directional) {
        d2 = std::max(length_squared(view.x - node.bounds.center()),
                      0.25f * length_squared(node.bounds.diagonal()));
        d2 = std::max(d2, 1e-20f);  // a light at x itself: large but finite
    }
    // Never 0 here (a product of positive factors that underflows): a node that can give light
    // must keep a chance.
    return std::max(node.weight * emitter * receiver / d2, std::numeric_limits<float>::min());
}

float first_child_probability(const LightTree& tree, const LightTreeNode& node,
                              const ClusterView& view) {
    return first_child_probability(cluster_importance(tree.node(node.children[0]), view),
                                   cluster_importance(tree.node(node.children[1]), view));
}

ClusterSample sample_cluster(const LightTree& tree, int32_t from, const ClusterView& view,
                             float u) {
    const LightTreeNode* node = &tree.node(from);
    float pmf = 1;
    while (!node->is_leaf()) {
        float p0 = first_child_probability(tree, *node, view);
        if (!(p0 >= 0)) return {};
        if (u < p0) {
            pmf *= p0;
            u = std::min(u / p0, kOneMinusEpsilon);
            node = &tree.node(node->children[0]);
        } else {
            pmf *= 1 - p0;
            u = std::min((u - p0) / (1 - p0), kOneMinusEpsilon);
            node = &tree.node(node->children[1]);
        }
    }
    return {node->light, pmf};
}

}  // namespace ml
