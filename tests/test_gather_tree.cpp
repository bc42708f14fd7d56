// The gather tree of Multidimensional Lightcuts (manylight/gather_tree.h): its nodes' members,
// strengths and boxes; groups split apart before positions (bdlightcuts' VSPs by eye depth); and
// representatives drawn in proportion to the members' selection weights, for every key, with or
// without groups.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/rng.h"
#include "manylight/gather_tree.h"
#include "manylight/representative.h"

using namespace ml;

namespace {

struct Points {
    std::vector<Vec3> p;
    std::vector<RGB> w;
    std::vector<float> u;
    std::vector<uint8_t> groups;
};

// n points: group g's points near a centre of their own (a pixel's first VSPs in a small box,
// later ones across a room), colours and weights varied.
Points random_points(Rng& rng, int n, int group_count) {
    Points s;
    for (int i = 0; i < n; ++i) {
        uint8_t g = uint8_t(std::min(group_count - 1, int(rng.next_float() * float(group_count))));
        float spread = g == 0 ? 0.01f : 3.f;
        s.p.push_back(Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * spread +
                      Vec3(float(g), 0, 0));
        s.w.push_back(RGB(0.1f + rng.next_float(), 0.1f + rng.next_float(), rng.next_float()));
        s.u.push_back(rng.next_float());
        s.groups.push_back(g);
    }
    return s;
}

// The lowest group among node i's members, and whether they all share it.
uint8_t lowest_group(const GatherTree& t, const Points& s, int32_t i, bool* single) {
    const GatherTreeNode& n = t.node(i);
    uint8_t lo = 255, hi = 0;
    for (int32_t m = n.begin; m < n.end; ++m) {
        uint8_t g = s.groups[size_t(t.members()[size_t(m)])];
        lo = std::min(lo, g), hi = std::max(hi, g);
    }
    *single = lo == hi;
    return lo;
}

}  // namespace

TEST(GatherTree, NodesHoldTheirMembersStrengthsAndBoxes) {
    Rng rng(3);
    for (int trial = 0; trial < 20; ++trial) {
        Points s = random_points(rng, 1 + int(rng.next_float() * 40), 3);
        for (bool grouped : {false, true}) {
            GatherTree t;
            int spare = t.build(s.p, s.w, s.u, grouped ? s.groups : std::vector<uint8_t>{});
            ASSERT_GE(spare, 0);
            ASSERT_EQ(t.node_count(), 2 * s.p.size() - 1);
            std::vector<int32_t> order = t.members();
            std::sort(order.begin(), order.end());
            for (size_t i = 0; i < order.size(); ++i) ASSERT_EQ(order[i], int32_t(i));
            for (int32_t i = 0; i < int32_t(t.node_count()); ++i) {
                const GatherTreeNode& n = t.node(i);
                RGB strength;
                for (int32_t m = n.begin; m < n.end; ++m) {
                    int32_t k = t.members()[size_t(m)];
                    strength += s.w[size_t(k)];
                    for (int a = 0; a < 3; ++a) {
                        EXPECT_GE(s.p[size_t(k)][a], n.bounds.lo[a]);
                        EXPECT_LE(s.p[size_t(k)][a], n.bounds.hi[a]);
                    }
                }
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(n.strength[c], strength[c], 1e-5f * strength[c]);
                if (n.is_leaf()) {
                    EXPECT_EQ(n.end - n.begin, 1);
                    continue;
                }
                const GatherTreeNode &a = t.node(n.children[0]), &b = t.node(n.children[1]);
                EXPECT_EQ(a.begin, n.begin);
                EXPECT_EQ(a.end, b.begin);
                EXPECT_EQ(b.end, n.end);
            }
        }
    }
}

TEST(GatherTree, GroupsAreSplitApartBeforePositions) {
    Rng rng(5);
    int mixed_nodes = 0;
    for (int trial = 0; trial < 20; ++trial) {
        Points s = random_points(rng, 2 + int(rng.next_float() * 40), 4);
        GatherTree t;
        t.build(s.p, s.w, s.u, s.groups);
        for (int32_t i = 0; i < int32_t(t.node_count()); ++i) {
            const GatherTreeNode& n = t.node(i);
            bool single = false;
            uint8_t lo = lowest_group(t, s, i, &single);
            if (single || n.is_leaf()) continue;
            // A node of several groups: its lowest group alone on the left, the others right.
            ++mixed_nodes;
            bool left_single = false, right_single = false;
            EXPECT_EQ(lowest_group(t, s, n.children[0], &left_single), lo);
            EXPECT_TRUE(left_single) << "node " << i << ": the left child mixes groups";
            EXPECT_GT(lowest_group(t, s, n.children[1], &right_single), lo)
                << "node " << i << ": the lowest group is on both sides";
        }
        // Without groups, or with one group for all, the same tree: groups change nothing else.
        GatherTree plain, one;
        plain.build(s.p, s.w, s.u);
        one.build(s.p, s.w, s.u, std::vector<uint8_t>(s.p.size(), 7));
        EXPECT_EQ(plain.members(), one.members());
    }
    EXPECT_GT(mixed_nodes, 20);
}

TEST(GatherTree, RepresentativesFollowTheSelectionWeightsForEveryKey) {
    // rep(node, key) over many keys: member i in proportion to selection_weight(w_i), at the root
    // and at a node of several groups alike (five standard deviations of the binomial counts).
    Rng rng(9);
    Points s = random_points(rng, 12, 3);
    for (bool grouped : {false, true}) {
        GatherTree t;
        t.build(s.p, s.w, s.u, grouped ? s.groups : std::vector<uint8_t>{});
        const GatherTreeNode& root = t.node(t.root());
        const int keys = 40000;
        std::vector<int> count(s.p.size(), 0);
        for (int key = 0; key < keys; ++key) ++count[size_t(t.rep(t.root(), uint32_t(key)))];
        double total = 0;
        for (const RGB& w : s.w) total += selection_weight(w);
        EXPECT_NEAR(root.weight, total, 1e-4 * total);
        for (size_t i = 0; i < s.p.size(); ++i) {
            double p = selection_weight(s.w[i]) / total, sd = std::sqrt(keys * p * (1 - p));
            EXPECT_NEAR(count[i], keys * p, 5 * sd) << "member " << i << " grouped " << grouped;
        }
    }
}
