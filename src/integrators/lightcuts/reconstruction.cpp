#include "integrators/lightcuts/reconstruction.h"

#include <algorithm>
#include <array>

#include "core/assert.h"
#include "manylight/representative.h"

namespace ml {

namespace {

constexpr int kMaxCorners = 4;
// A corner whose cut has not yet been met on the way down from the root (the node lies above
// its cut): its ShadowResult once met.
constexpr uint8_t kAbove = 0xff;

// What corner c's cut says of `node` when its cut holds that node: the ShadowResult, else kAbove.
uint8_t lookup(const SparseCut& c, int32_t node) {
    auto it = std::lower_bound(c.cut.begin(), c.cut.end(), CutNode{node, ShadowResult::NotCast});
    return it != c.cut.end() && it->node == node ? uint8_t(it->shadow) : kAbove;
}

}  // namespace

int agreeing_corners(const GatherPoint& g, std::span<const SparseCut* const> corners,
                     std::array<const SparseCut*, 4>* agreeing) {
    const Vec3& p = g.si.p;
    const Vec3& n = g.si.ns;
    int count = 0;
    for (const SparseCut* c : corners) {
        if (!c->valid || c->material != g.si.material) continue;
        if (dot(c->n, n) < kReconstructNormalCos) continue;
        Vec3 d = c->p - p;
        if (std::abs(dot(d, n)) > kReconstructPlaneSlope * length(d)) continue;
        if (count < 4) (*agreeing)[size_t(count++)] = c;
    }
    return count;
}

RGB reconstruction_cut(const Scene& scene, const PointLightSet& set,
                       const ManyLightSettings& settings, const LightTree& tree,
                       const GatherPoint& g, int k, std::span<const SparseCut* const> corners,
                       int* nodes) {
    ML_ASSERT(corners.size() <= size_t(kMaxCorners), "at most four corners");
    struct Item {
        int32_t node;
        std::array<uint8_t, kMaxCorners> state;  // per corner: kAbove or its ShadowResult
    };
    thread_local std::vector<Item> stack;
    stack.clear();
    for (PointLightKind kind : kAllPointLightKinds) {
        int32_t root = tree.root(kind);
        if (root >= 0) stack.push_back({root, {kAbove, kAbove, kAbove, kAbove}});
    }
    RGB L;
    int count = 0;
    while (!stack.empty()) {
        Item item = stack.back();
        stack.pop_back();
        const LightTreeNode& n = tree.node(item.node);
        // Which corners' cuts hold the node (or held an ancestor), and what they saw.
        bool held = true, seen = false, blocked = false;
        for (size_t c = 0; c < corners.size(); ++c) {
            if (item.state[c] == kAbove) item.state[c] = lookup(*corners[c], item.node);
            held = held && item.state[c] != kAbove;
            seen = seen || item.state[c] == uint8_t(ShadowResult::Visible);
            blocked = blocked || item.state[c] == uint8_t(ShadowResult::Occluded);
        }
        if (!held && !n.is_leaf()) {
            // Some corner needed it finer: split (a leaf is in every cut; kept for safety).
            stack.push_back({n.children()[1], item.state});
            stack.push_back({n.children()[0], item.state});
            continue;
        }
        ++count;
        if (held && blocked && !seen) continue;  // every corner found it blocked
        const PointLight& pl = set.lights[size_t(tree.rep(item.node, k))];
        RGB value = held && seen && !blocked ? unshadowed_point_light(set, settings, pl, g)
                                             : visible_point_light(scene, set, settings, pl, g);
        if (!n.is_leaf())
            value = value *
                    representative_scale(tree.weight(item.node), selection_weight(pl.intensity));
        L += value;
    }
    *nodes = count;
    return L;
}

}  // namespace ml
