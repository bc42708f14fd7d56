// Stochastic lightcuts (issue 13, item 6): the descent that draws one light of a cluster
// (manylight/cluster_sampling.h) and the integrator. The descent's pmf is checked against the
// frequencies of its samples (chi-square) and against geometry: every light that can light the
// shading point must have a non-zero probability, else the estimate loses its light. The
// renders' unbiasedness against `vpl` is checked with the coloured lights of
// test_coloured_lights.cpp; determinism over thread counts in test_many_light_seeds.cpp.
#include <gtest/gtest.h>

#include <vector>

#include "chi2.h"
#include "core/rng.h"
#include "integrators/stochasticlightcuts/stochastic_lightcuts.h"
#include "manylight/cluster_sampling.h"
#include "manylight/light_tree.h"
#include "render_helpers.h"

using namespace ml;

namespace {

// A direction uniform over the sphere.
Vec3 random_direction(Rng& rng) {
    float z = 2 * rng.next_float() - 1, phi = 2 * kPi * rng.next_float();
    float r = std::sqrt(std::max(0.f, 1 - z * z));
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// Omni and oriented lights (random normals) in the unit cube, random colours.
std::vector<PointLight> mixed_lights(int n, uint64_t seed) {
    Rng rng(seed);
    std::vector<PointLight> lights(size_t(n), PointLight{});
    for (int i = 0; i < n; ++i) {
        PointLight& pl = lights[size_t(i)];
        pl.p = Vec3(rng.next_float(), rng.next_float(), rng.next_float());
        pl.intensity = RGB(rng.next_float(), rng.next_float(), rng.next_float()) * 2.f;
        if (i % 2) {
            pl.kind = PointLightKind::Oriented;
            pl.n = random_direction(rng);
        }
    }
    return lights;
}

// Spot lights (omni lights with a cone) in the unit cube, aimed every way, with cones of 3 to 60
// degrees (a quarter of them with no falloff band) and random colours.
std::vector<PointLight> spot_lights(int n, uint64_t seed) {
    Rng rng(seed);
    std::vector<PointLight> lights(size_t(n), PointLight{});
    for (int i = 0; i < n; ++i) {
        PointLight& pl = lights[size_t(i)];
        pl.p = Vec3(rng.next_float(), rng.next_float(), rng.next_float());
        pl.intensity = RGB(rng.next_float(), rng.next_float(), rng.next_float()) * 2.f;
        pl.n = random_direction(rng);
        float cone = radians(3 + 57 * rng.next_float());
        float delta = i % 4 ? cone * rng.next_float() : 0.f;
        pl.cos_end = std::cos(cone);
        pl.cos_start = std::cos(cone - delta);
    }
    return lights;
}

// Every leaf below `node` with the product of the descent's probabilities down to it.
void leaf_pmfs(const LightTree& tree, const ClusterSampler& sampler, int32_t node,
               const ClusterView& view, double p, std::vector<double>* out) {
    const LightTreeNode& n = tree.node(node);
    if (n.is_leaf()) {
        (*out)[size_t(tree.light(node))] += p;
        return;
    }
    float p0 = sampler.first_child_probability(node, view);
    if (p0 < 0) return;
    leaf_pmfs(tree, sampler, n.children()[0], view, p * p0, out);
    leaf_pmfs(tree, sampler, n.children()[1], view, p * (1 - p0), out);
}

// Whether light `pl` can give the point any light: it lies on the receiver's side (either side
// when it transmits) and, oriented, faces it; a spot light's cone holds the point.
bool can_light(const PointLight& pl, const ClusterView& view) {
    Vec3 d = pl.p - view.x;
    if (!view.two_sided && dot(d, view.n) <= 0) return false;
    if (pl.kind == PointLightKind::Omni && pl.cos_end > -1)
        return dot(pl.n, -normalize(d)) > pl.cos_end;
    return pl.kind != PointLightKind::Oriented || dot(pl.n, -d) > 0;
}

// The descent's pmf below the roots of `kinds` and two nodes under each, at four views: it sums
// to at most 1, gives every light that can light the point a chance, and matches the frequencies
// of its samples (chi-square). Returns the number of pmfs tested.
int check_cluster_pmfs(const std::vector<PointLight>& lights,
                       const std::vector<PointLightKind>& kinds) {
    LightTree tree(lights);
    ClusterSampler sampler(tree, lights);
    Rng rng(9);
    const int samples = 50000;
    const int expected_tests = 4 * 3 * int(kinds.size());
    bool spots = false;
    for (const PointLight& pl : lights) spots |= pl.cos_end > -1;
    int tests = 0;
    // Shading points inside the lights' box and outside it, facing various ways.
    const ClusterView views[] = {{Vec3(0.5f, 0.5f, 0.5f), Vec3(0, 0, 1), false},
                                 {Vec3(0.2f, 0.9f, 0.1f), normalize(Vec3(1, -1, 1)), false},
                                 {Vec3(2.f, 0.5f, -1.f), normalize(Vec3(-1, 0, 1)), false},
                                 {Vec3(0.5f, 0.3f, 0.7f), Vec3(0, 1, 0), true}};
    for (const ClusterView& view : views) {
        // The roots and two nodes below.
        for (PointLightKind kind : kinds) {
            int32_t root = tree.root(kind);
            EXPECT_GE(root, 0);
            if (root < 0) return tests;
            auto below = [&](int32_t i, int k) {
                return tree.node(i).is_leaf() ? i : tree.node(i).children()[size_t(k)];
            };
            for (int32_t node : {root, below(root, 0), below(below(root, 1), 1)}) {
                std::vector<double> pmf(lights.size(), 0.0), observed(lights.size(), 0.0);
                leaf_pmfs(tree, sampler, node, view, 1.0, &pmf);
                double sum = 0;
                for (double p : pmf) sum += p;
                // Below 1 by the subtrees the descent cannot enter (no light there can light x:
                // checked below); the samples that end there (-1) are counted as one more bin.
                EXPECT_LE(sum, 1.0 + 1e-5) << "node " << node;
                if (view.two_sided && kind == PointLightKind::Omni && !spots) {
                    EXPECT_NEAR(sum, 1.0, 1e-5) << "node " << node;
                }
                // Every light below the node that can light x has a chance.
                std::vector<int32_t> stack = {node};
                while (!stack.empty()) {
                    const LightTreeNode& m = tree.node(stack.back());
                    int32_t light = tree.light(stack.back());
                    stack.pop_back();
                    if (!m.is_leaf()) {
                        stack.insert(stack.end(), {m.children()[0], m.children()[1]});
                        continue;
                    }
                    if (can_light(lights[size_t(light)], view)) {
                        EXPECT_GT(pmf[size_t(light)], 0) << "light " << light << " node " << node;
                    }
                }
                double failed = 0;
                for (int i = 0; i < samples; ++i) {
                    ClusterSample s = sampler.sample(node, view, rng.next_float());
                    if (s.light < 0) {
                        failed += 1;
                        continue;
                    }
                    EXPECT_NEAR(s.pmf, pmf[size_t(s.light)], 1e-5 * pmf[size_t(s.light)])
                        << "light " << s.light;
                    observed[size_t(s.light)] += 1;
                }
                double stat = 0, pooled_e = 0, pooled_o = 0;
                int bins = 0;
                for (size_t light = 0; light < pmf.size(); ++light) {
                    double e = pmf[light] * samples, o = observed[light];
                    if (e == 0) {
                        EXPECT_EQ(o, 0) << "light " << light << " sampled with pmf 0";
                        continue;
                    }
                    if (e < 20) {
                        pooled_e += e, pooled_o += o;
                        continue;
                    }
                    stat += sqr(o - e) / e;
                    ++bins;
                }
                if (pooled_e > 0) stat += sqr(pooled_o - pooled_e) / pooled_e, ++bins;
                double fail_e = std::max(0.0, 1 - sum) * samples;
                if (fail_e > 1) {
                    stat += sqr(failed - fail_e) / fail_e, ++bins;
                } else {
                    EXPECT_LE(failed, 10) << "node " << node;
                }
                ++tests;
                if (bins > 1) {
                    EXPECT_GT(chi2::chi2_survival(stat, bins - 1),
                              chi2::sidak_alpha(0.01, expected_tests))
                        << "stat " << stat << " bins " << bins << " node " << node;
                }
            }
        }
    }
    EXPECT_EQ(tests, expected_tests);
    return tests;
}

}  // namespace

TEST(StochasticLightcuts, ClusterPmfSumsToOneAndMatchesItsSamples) {
    EXPECT_EQ(
        check_cluster_pmfs(mixed_lights(400, 3), {PointLightKind::Omni, PointLightKind::Oriented}),
        24);
}

// Spot lights: the pmf follows their cones (zero for a spot whose cone misses the point, never
// zero for one whose cone holds it), and still matches its samples.
TEST(StochasticLightcuts, SpotClusterPmfFollowsTheConesAndMatchesItsSamples) {
    EXPECT_EQ(check_cluster_pmfs(spot_lights(400, 5), {PointLightKind::Omni}), 12);
    // Spots mixed with plain omni lights in one tree.
    std::vector<PointLight> lights = spot_lights(200, 6);
    std::vector<PointLight> omni = mixed_lights(200, 7);
    for (const PointLight& pl : omni)
        if (pl.kind == PointLightKind::Omni) lights.push_back(pl);
    EXPECT_EQ(check_cluster_pmfs(lights, {PointLightKind::Omni}), 12);
}

// A cluster of spot lights all aimed away from the point has no importance there and cannot be
// descended (before: spots counted as lights that emit every way, and half the descents of a
// stage's spot rig ended on a spot that gives nothing). Turned to face the point, or with a cone
// wide enough to hold it, they can.
TEST(StochasticLightcuts, SpotClustersAimedAwayHaveNoImportance) {
    std::vector<PointLight> lights(3, PointLight{});
    for (int i = 0; i < 3; ++i) {
        PointLight& pl = lights[size_t(i)];
        pl.p = Vec3(0.5f * float(i), 2, 0);
        pl.n = normalize(Vec3(0, -1, 2));  // about 63 degrees from straight down
        pl.intensity = i ? RGB(1, 0, 0) : RGB(1);
        pl.cos_end = std::cos(radians(30));
        pl.cos_start = std::cos(radians(25));
    }
    ClusterView view{Vec3(0.5f, 0, 0), Vec3(0, 1, 0), false};
    auto root_sample = [&](const std::vector<PointLight>& ls, float* importance) {
        LightTree tree(ls);
        ClusterSampler sampler(tree, ls);
        *importance = sampler.importance(tree.root(PointLightKind::Omni), view);
        return sampler.sample(tree.root(PointLightKind::Omni), view, 0.3f);
    };
    float importance = -1;
    EXPECT_EQ(root_sample(lights, &importance).light, -1);
    EXPECT_EQ(importance, 0.f);
    // Aimed straight down: the point is in every cone.
    std::vector<PointLight> facing = lights;
    for (PointLight& pl : facing) pl.n = Vec3(0, -1, 0);
    ClusterSample s = root_sample(facing, &importance);
    EXPECT_GE(s.light, 0);
    EXPECT_GT(s.pmf, 0);
    EXPECT_GT(importance, 0);
    // The first aim with 80-degree cones (and plain omni lights): light reaches the point.
    for (float cos_end : {std::cos(radians(80)), -2.f}) {
        std::vector<PointLight> wide = lights;
        for (PointLight& pl : wide) pl.cos_end = cos_end, pl.cos_start = std::max(cos_end, 0.9f);
        EXPECT_GE(root_sample(wide, &importance).light, 0) << cos_end;
        EXPECT_GT(importance, 0) << cos_end;
    }
}

// Oriented lights facing away from the point cannot light it and get no chance; a cluster of
// only such lights cannot be descended. Facing it, they can.
TEST(StochasticLightcuts, ClustersThatCannotLightThePointAreNotDescended) {
    std::vector<PointLight> lights(2, PointLight{});
    for (int i = 0; i < 2; ++i) {
        lights[size_t(i)].kind = PointLightKind::Oriented;
        lights[size_t(i)].p = Vec3(0.5f * float(i), -1, 0);
        lights[size_t(i)].n = Vec3(0, -1, 0);
        lights[size_t(i)].intensity = i ? RGB(1, 0, 0) : RGB(1);
    }
    LightTree away(lights);
    ClusterView view{Vec3(0, 0, 0), Vec3(0, 1, 0), true};
    EXPECT_EQ(
        ClusterSampler(away, lights).sample(away.root(PointLightKind::Oriented), view, 0.3f).light,
        -1);
    for (PointLight& pl : lights) pl.n = Vec3(0, 1, 0);
    LightTree facing(lights);
    ClusterSample s =
        ClusterSampler(facing, lights).sample(facing.root(PointLightKind::Oriented), view, 0.3f);
    EXPECT_GE(s.light, 0);
    EXPECT_GT(s.pmf, 0);
}

TEST(StochasticLightcuts, BadCutSizeIsAUsageError) {
    Settings s("stochasticlightcuts", nullptr, {{"stochasticlightcuts.cut", "0"}});
    EXPECT_THROW(StochasticLightcutsIntegrator{s}, UsageError);
}
