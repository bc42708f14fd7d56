// Light tree invariants: boxes, cones and intensities of every node hold their children's, each
// light sits in exactly one leaf, representatives come from the subtree, builds are
// deterministic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "core/rng.h"
#include "manylight/light_tree.h"
#include "manylight/representative.h"
#include "tree_test_helpers.h"

using namespace ml;
using namespace ml::tree_test;

namespace {

bool box_contains(const Bounds3& outer, const Bounds3& inner) {
    if (inner.empty()) return true;
    return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
           outer.hi.x >= inner.hi.x && outer.hi.y >= inner.hi.y && outer.hi.z >= inner.hi.z;
}

// Walks the subtree of `n`, checking every node, and returns the lights of its leaves.
void check_subtree(const LightTree& tree, const std::vector<PointLight>& lights, int32_t n,
                   std::vector<int32_t>* leaves, std::vector<int>* seen) {
    const LightTreeNode& node = tree.node(n);
    size_t first = leaves->size();
    const int32_t light = tree.light(n);
    if (node.is_leaf()) {
        ASSERT_GE(light, 0);
        ASSERT_LT(size_t(light), lights.size());
        const PointLight& pl = lights[size_t(light)];
        EXPECT_EQ(pl.kind, node.kind);
        EXPECT_EQ(tree.intensity(n), pl.intensity);
        EXPECT_EQ(node.bound_intensity, pl.intensity);
        EXPECT_EQ(tree.weight(n), selection_weight(pl.intensity));
        (*seen)[size_t(light)]++;
        leaves->push_back(light);
    } else {
        // Siblings side by side (the hot node keeps only the first).
        EXPECT_EQ(node.children()[1], node.children()[0] + 1);
        for (int32_t c : node.children()) {
            ASSERT_GE(c, 0);
            const LightTreeNode& child = tree.node(c);
            EXPECT_EQ(child.kind, node.kind);
            EXPECT_TRUE(box_contains(node.bounds, child.bounds));
            if (node.kind != PointLightKind::Omni && !node.cone.is_entire_sphere()) {
                // The child's cone inside the parent's: axis offset plus its half-angle.
                float lhs = angle_between(node.cone.axis, child.cone.axis) + cone_angle(child.cone);
                EXPECT_LE(lhs, cone_angle(node.cone) + 1e-5f);
            }
            check_subtree(tree, lights, c, leaves, seen);
        }
        const int32_t a = node.children()[0], b = node.children()[1];
        RGB sum = tree.intensity(a) + tree.intensity(b);
        EXPECT_EQ(tree.intensity(n), sum);
        // Representatives are drawn by these weights (representative.h); the bound's intensity
        // holds the sum.
        EXPECT_EQ(tree.weight(n), tree.weight(a) + tree.weight(b));
        for (int c = 0; c < 3; ++c) EXPECT_GE(node.bound_intensity[c], tree.intensity(n)[c]);
    }
    // Every light of the subtree: inside the box and the cone; intensities add up; the
    // representative is one of them.
    double total[3] = {0, 0, 0};
    bool rep_found = false;
    for (size_t k = first; k < leaves->size(); ++k) {
        const PointLight& pl = lights[size_t((*leaves)[k])];
        if (node.kind != PointLightKind::Directional) {
            Bounds3 pb;
            pb.expand(pl.p);
            EXPECT_TRUE(box_contains(node.bounds, pb));
        } else {
            EXPECT_TRUE(node.bounds.empty());
        }
        if (node.kind != PointLightKind::Omni) {
            EXPECT_TRUE(cone_contains(node.cone, pl.n));
        }
        for (int c = 0; c < 3; ++c) total[c] += pl.intensity[c];
        rep_found |= (*leaves)[k] == light;
    }
    EXPECT_TRUE(rep_found) << "representative " << light << " not in subtree of " << n;
    // Clamping's cap: the count of lights when they are all VPLs (a leaf that is not: 0).
    size_t vpls = size_t(std::count_if(leaves->begin() + ptrdiff_t(first), leaves->end(),
                                       [&](int32_t l) { return lights[size_t(l)].is_vpl; }));
    size_t count = leaves->size() - first;
    int32_t expected = vpls == count ? int32_t(count) : (node.is_leaf() ? 0 : -1);
    EXPECT_EQ(node.clampable, expected) << "node " << n;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(tree.intensity(n)[c], total[c], 1e-4 * total[c] + 1e-6);
    // Glossy: bin by bin, the node's falloff is its lights' largest (so the node's intensity
    // times it holds the sum of theirs, and the estimate); other kinds have none.
    for (int k = 0; k < kFalloffBins; ++k) {
        if (node.kind != PointLightKind::Glossy) {
            EXPECT_EQ(tree.falloff(n)[k], 0);
            continue;
        }
        uint8_t q = 255;
        for (size_t j = first; j < leaves->size(); ++j)
            q = std::min(q, lights[size_t((*leaves)[j])].falloff[k]);
        EXPECT_EQ(tree.falloff(n)[k], q) << "node " << n << " bin " << k;
    }
}

void check_tree(const std::vector<PointLight>& lights, const LightTree& tree) {
    std::vector<int> seen(lights.size(), 0);
    size_t counts[kPointLightKinds] = {};
    for (const PointLight& pl : lights) counts[int(pl.kind)]++;
    for (PointLightKind kind : kAllPointLightKinds) {
        int32_t root = tree.root(kind);
        if (counts[int(kind)] == 0) {
            EXPECT_EQ(root, -1);
            continue;
        }
        ASSERT_GE(root, 0);
        EXPECT_EQ(tree.node(root).kind, kind);
        std::vector<int32_t> leaves;
        check_subtree(tree, lights, root, &leaves, &seen);
        EXPECT_EQ(leaves.size(), counts[int(kind)]);
    }
    for (size_t i = 0; i < lights.size(); ++i) EXPECT_EQ(seen[i], 1) << "light " << i;
    EXPECT_EQ(tree.node_count(), 2 * lights.size() - (counts[0] > 0) - (counts[1] > 0) -
                                     (counts[2] > 0) - (counts[3] > 0));
}

}  // namespace

TEST(LightTree, EmptyAndSingle) {
    LightTree empty(std::vector<PointLight>{});
    for (PointLightKind kind : kAllPointLightKinds) EXPECT_EQ(empty.root(kind), -1);
    std::vector<PointLight> one = random_lights(1, LightMix::Oriented, 3);
    LightTree t(one);
    int32_t r = t.root(PointLightKind::Oriented);
    ASSERT_GE(r, 0);
    EXPECT_TRUE(t.node(r).is_leaf());
    EXPECT_EQ(t.light(r), 0);
}

TEST(LightTree, InvariantsEachKind) {
    for (LightMix mix : {LightMix::Omni, LightMix::Oriented, LightMix::Directional, LightMix::Mixed,
                         LightMix::Glossy}) {
        for (size_t n : {2, 3, 17, 100, 1000, 5000}) {
            std::vector<PointLight> lights = random_lights(n, mix, 100 + n);
            LightTree tree(lights);
            SCOPED_TRACE(testing::Message() << "mix " << int(mix) << " n " << n);
            check_tree(lights, tree);
        }
    }
}

TEST(LightTree, InvariantsWithDegenerateInput) {
    // Coincident positions, identical normals, zero intensities: ties everywhere.
    std::vector<PointLight> lights(300);
    for (size_t i = 0; i < lights.size(); ++i) {
        lights[i].p = Vec3(1, 2, 3);
        lights[i].n = Vec3(0, 0, 1);
        lights[i].kind = PointLightKind(i % 3);
        lights[i].intensity = i % 7 == 0 ? RGB(1, 0, 0) : RGB(0);
    }
    LightTree tree(lights);
    check_tree(lights, tree);
}

TEST(LightTree, Deterministic) {
    std::vector<PointLight> lights = random_lights(20000, LightMix::Mixed, 7);
    LightTreeOptions opts;
    opts.seed = 42;
    LightTree a(lights, opts), b(lights, opts);
    ASSERT_EQ(a.node_count(), b.node_count());
    for (int32_t i = 0; i < int32_t(a.node_count()); ++i) {
        const LightTreeNode &x = a.node(i), &y = b.node(i);
        ASSERT_EQ(a.light(i), b.light(i));
        ASSERT_EQ(x.children(), y.children());
        ASSERT_EQ(a.intensity(i), b.intensity(i));
        ASSERT_EQ(x.cone.axis, y.cone.axis);
        ASSERT_EQ(x.cone.cos_theta, y.cone.cos_theta);
    }
    for (int k = 0; k < 3; ++k) EXPECT_EQ(a.root(PointLightKind(k)), b.root(PointLightKind(k)));
}

TEST(LightTree, RepresentativeProportionalToIntensity) {
    // Two lights of luminance 1 and 3: over many seeds the brighter represents the root 3/4 of
    // the time.
    std::vector<PointLight> lights(2);
    lights[0].p = Vec3(0, 0, 0), lights[0].intensity = RGB(1);
    lights[1].p = Vec3(1, 0, 0), lights[1].intensity = RGB(3);
    int bright = 0, trials = 4000;
    for (int s = 0; s < trials; ++s) {
        LightTreeOptions opts;
        opts.seed = uint64_t(s);
        LightTree t(lights, opts);
        bright += t.light(t.root(PointLightKind::Omni)) == 1;
    }
    // Binomial sd: sqrt(4000 * 0.75 * 0.25) = 27.
    EXPECT_NEAR(bright, 0.75 * trials, 5 * 27.4);
}

// Every representative k of a node is representative k of one of its children (so it lies in
// the node's subtree), leaves are their own, and each k picks the root's light in proportion to
// intensity independently of the others.
TEST(LightTree, RepresentativesPerSample) {
    std::vector<PointLight> lights(4);
    for (int i = 0; i < 4; ++i) lights[size_t(i)].p = Vec3(float(i), 0, 0);
    for (int i = 0; i < 4; ++i) lights[size_t(i)].intensity = RGB(float(i + 1));
    for (int reps : {kLightTreeReps, 64}) {
        std::vector<std::array<int, 4>> count(size_t(reps), std::array<int, 4>{});
        int same_as_first = 0, same_as_last = 0, trials = 2000;
        for (int s = 0; s < trials; ++s) {
            LightTreeOptions opts;
            opts.seed = uint64_t(s);
            opts.reps = reps;
            LightTree t(lights, opts);
            ASSERT_EQ(t.reps(), reps);
            for (int32_t i = 0; i < int32_t(t.node_count()); ++i) {
                const LightTreeNode& n = t.node(i);
                ASSERT_EQ(t.rep(i, 0), t.light(i));
                for (int k = 0; k < reps; ++k) {
                    if (n.is_leaf()) {
                        ASSERT_EQ(t.rep(i, k), t.light(i));
                    } else {
                        int32_t r = t.rep(i, k);
                        ASSERT_TRUE(r == t.rep(n.children()[0], k) ||
                                    r == t.rep(n.children()[1], k));
                    }
                }
            }
            int32_t root = t.root(PointLightKind::Omni);
            for (int k = 0; k < reps; ++k) ++count[size_t(k)][size_t(t.rep(root, k))];
            same_as_first += t.rep(root, 1) == t.rep(root, 0);
            same_as_last += t.rep(root, reps - 1) == t.rep(root, reps - 2);
        }
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < reps; ++k) {
                double p = (i + 1) / 10.0, sd = std::sqrt(trials * p * (1 - p));
                EXPECT_NEAR(count[size_t(k)][size_t(i)], trials * p, 5 * sd)
                    << "light " << i << " rep " << k << " of " << reps;
            }
        // Independent picks agree with probability sum p_i^2 = 0.3.
        EXPECT_NEAR(same_as_first, 0.3 * trials, 5 * std::sqrt(trials * 0.3 * 0.7));
        EXPECT_NEAR(same_as_last, 0.3 * trials, 5 * std::sqrt(trials * 0.3 * 0.7));
    }
    LightTreeOptions none;
    none.reps = 0;
    EXPECT_THROW(LightTree(lights, none), UsageError);
    none.reps = kLightTreeMaxReps + 1;
    EXPECT_THROW(LightTree(lights, none), UsageError);
}

TEST(LightTree, MetricPrefersCloseAndAligned) {
    Bounds3 small, big;
    small.expand(Vec3(0, 0, 0)), small.expand(Vec3(1, 0, 0));
    big.expand(Vec3(0, 0, 0)), big.expand(Vec3(10, 0, 0));
    EXPECT_LT(light_cluster_metric(1, small, 0, 0, false),
              light_cluster_metric(1, big, 0, 0, false));
    EXPECT_LT(light_cluster_metric(1, small, 0.1f, 5, false),
              light_cluster_metric(1, small, 1.f, 5, false));
    EXPECT_EQ(light_cluster_metric(1, big, 0.5f, 1, true),
              light_cluster_metric(1, small, 0.5f, 1, true));
}

// The hot nodes are cache lines: each starts one (the cut reads one line per node), and the
// side arrays hold the same node count.
TEST(LightTree, HotNodesAreCacheLines) {
    std::vector<PointLight> lights = random_lights(1000, LightMix::Mixed, 13);
    LightTree tree(lights);
    for (int32_t i = 0; i < int32_t(tree.node_count()); ++i)
        ASSERT_EQ(reinterpret_cast<uintptr_t>(&tree.node(i)) % 64, 0u) << "node " << i;
    EXPECT_EQ(tree.node_count(), 2 * lights.size() - 3);
    int32_t last = int32_t(tree.node_count()) - 1;
    EXPECT_GE(tree.light(last), 0);
    EXPECT_GE(tree.rep(last, kLightTreeReps - 1), 0);
}

TEST(LightTree, Builds100kLights) {
    std::vector<PointLight> lights = random_lights(100000, LightMix::Mixed, 11);
    LightTree tree(lights);
    std::vector<int> seen(lights.size(), 0);
    for (int32_t i = 0; i < int32_t(tree.node_count()); ++i)
        if (tree.node(i).is_leaf()) seen[size_t(tree.light(i))]++;
    for (size_t i = 0; i < lights.size(); ++i) ASSERT_EQ(seen[i], 1);
    // Cluster quality: nodes near the leaves are small (Morton order plus the metric keep them
    // local), far below the scene's extent of 20.
    double sum_diag = 0;
    int count = 0;
    for (int32_t i = 0; i < int32_t(tree.node_count()); ++i) {
        const LightTreeNode& n = tree.node(i);
        if (!n.is_leaf() && n.kind == PointLightKind::Omni &&
            tree.node(n.children()[0]).is_leaf() && tree.node(n.children()[1]).is_leaf()) {
            sum_diag += length(n.bounds.diagonal());
            ++count;
        }
    }
    ASSERT_GT(count, 0);
    EXPECT_LT(sum_diag / count, 1.0);
}
