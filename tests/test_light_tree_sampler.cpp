// The tree light sampler (lights/light_sampler.h "tree", lights/light_bvh.h): its pmf at a
// shading point is the probability that sample() returns each light (observed frequencies,
// chi-square), sums to 1, and is zero only for lights that cannot light the point.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "chi2.h"
#include "core/rng.h"
#include "lights/light_bvh.h"
#include "lights/light_sampler.h"
#include "lights/lights.h"
#include "sampling/warps.h"

namespace ml {
namespace {

// Lights of every kind the tree holds and two it does not, spread through [-4, 4]^3.
struct LightSet {
    std::vector<std::unique_ptr<TriangleMesh>> meshes;
    std::vector<std::unique_ptr<Light>> lights;

    explicit LightSet(int n, uint64_t seed) {
        Rng rng(seed);
        auto point = [&] {
            return Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 8 - Vec3(4, 4, 4);
        };
        auto colour = [&] { return RGB(rng.next_float(), rng.next_float(), rng.next_float()) * 3; };
        for (int i = 0; i < n; ++i) {
            switch (i % 4) {
                case 0:
                    lights.push_back(make_point_light(point(), colour()));
                    break;
                case 1: {
                    Vec3 axis = sample_uniform_sphere({rng.next_float(), rng.next_float()});
                    lights.push_back(make_spot_light(point(), axis, colour(), 0.9f, 0.7f));
                    break;
                }
                default: {  // a small quad of random orientation, one- or two-sided
                    auto m = std::make_unique<TriangleMesh>();
                    Vec3 o = point();
                    Vec3 a = sample_uniform_sphere({rng.next_float(), rng.next_float()}) * 0.3f;
                    Vec3 b = sample_uniform_sphere({rng.next_float(), rng.next_float()}) * 0.3f;
                    m->p = {o, o + a, o + a + b, o + b};
                    m->indices = {0, 1, 2, 0, 2, 3};
                    lights.push_back(make_diffuse_area_light(m.get(), colour() * 0.2f, i % 4 == 3));
                    meshes.push_back(std::move(m));
                }
            }
        }
        lights.push_back(make_point_light(point(), RGB(0)));  // emits nothing
        lights.push_back(make_distant_light(normalize(Vec3(1, 2, 3)), RGB(2, 1.5f, 1)));
        lights.push_back(make_uniform_infinite_light(RGB(0.1f, 0.2f, 0.4f)));
        Bounds3 scene;
        scene.expand(Vec3(-5, -5, -5));
        scene.expand(Vec3(5, 5, 5));
        for (size_t i = 0; i < lights.size(); ++i) {
            lights[i]->index = int(i);
            lights[i]->preprocess(scene);
        }
    }
};

std::vector<LightSampleContext> receivers(int n, uint64_t seed) {
    Rng rng(seed);
    std::vector<LightSampleContext> out;
    for (int i = 0; i < n; ++i) {
        Vec3 p = Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 10 - Vec3(5, 5, 5);
        Vec3 nrm = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        // One receiver in three has no normal (a point in a medium).
        out.push_back(i % 3 == 2 ? LightSampleContext{p, Vec3(), Vec3()}
                                 : LightSampleContext{p, nrm, nrm});
    }
    return out;
}

TEST(LightTreeSampler, FrequenciesMatchPmfAndPmfSumsToOne) {
    LightSet set(200, 7);
    LightSampler s("tree", set.lights);
    const int n_points = 6, n = 200000;
    auto ctxs = receivers(n_points, 11);
    double alpha = chi2::sidak_alpha(0.01, n_points);
    Rng rng(5);
    for (const auto& ctx : ctxs) {
        // The pmf sums to 1 less the probability that the descent fails (a subtree none of
        // whose lights reaches the point, though the union of their bounds does); that failure
        // rate is one more bin of the test.
        double sum = 0;
        for (const auto& l : set.lights) sum += s.pmf(ctx, l.get());
        EXPECT_LE(sum, 1.0 + 1e-5);
        EXPECT_GT(sum, 0.9);
        EXPECT_EQ(s.pmf(ctx, set.lights[set.lights.size() - 3].get()), 0.f);  // no power
        std::vector<double> obs(set.lights.size(), 0);
        double failed = 0;
        for (int i = 0; i < n; ++i) {
            auto sl = s.sample(ctx, rng.next_float());
            if (!sl) {
                failed += 1;
                continue;
            }
            ASSERT_EQ(sl->light, set.lights[size_t(sl->index)].get());
            ASSERT_NEAR(sl->pmf, s.pmf(ctx, sl->light), 1e-6f * sl->pmf);
            obs[size_t(sl->index)] += 1;
        }
        // Pool lights of small expected count into one bin.
        double stat = 0, pooled_e = 0, pooled_o = 0;
        int bins = 0;
        for (size_t i = 0; i < obs.size(); ++i) {
            double e = double(s.pmf(ctx, set.lights[i].get())) * n;
            if (e == 0) {
                EXPECT_EQ(obs[i], 0) << "light " << i << " sampled with pmf 0";
                continue;
            }
            if (e < 20) {
                pooled_e += e, pooled_o += obs[i];
                continue;
            }
            stat += sqr(obs[i] - e) / e;
            ++bins;
        }
        if (pooled_e > 0) stat += sqr(pooled_o - pooled_e) / pooled_e, ++bins;
        double fail_e = std::max(0.0, 1 - sum) * n;
        if (fail_e > 1)
            stat += sqr(failed - fail_e) / fail_e, ++bins;
        else
            EXPECT_LE(failed, 10);
        EXPECT_GT(chi2::chi2_survival(stat, bins - 1), alpha)
            << "stat " << stat << " bins " << bins;
    }
}

// With lights that reach every point (omni point lights, an environment) no descent fails: the
// pmf sums to 1.
TEST(LightTreeSampler, PmfSumsToOneWhenEveryLightReaches) {
    std::vector<std::unique_ptr<Light>> lights;
    Rng rng(2);
    for (int i = 0; i < 300; ++i)
        lights.push_back(
            make_point_light(Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 4,
                             RGB(rng.next_float(), rng.next_float(), rng.next_float())));
    lights.push_back(make_uniform_infinite_light(RGB(0.3f)));
    Bounds3 scene;
    scene.expand(Vec3(-5, -5, -5));
    scene.expand(Vec3(5, 5, 5));
    for (size_t i = 0; i < lights.size(); ++i)
        lights[i]->index = int(i), lights[i]->preprocess(scene);
    LightSampler s("tree", lights);
    for (const auto& ctx : receivers(20, 4)) {
        double sum = 0;
        for (const auto& l : lights) sum += s.pmf(ctx, l.get());
        EXPECT_NEAR(sum, 1.0, 1e-5);
    }
}

// A light the sampler never chooses at a point must give it nothing: every sample_li towards the
// point either fails or carries no radiance.
TEST(LightTreeSampler, ZeroPmfOnlyWhereTheLightCannotReach) {
    LightSet set(400, 3);
    LightSampler s("tree", set.lights);
    Rng rng(9);
    int zeros = 0;
    for (const auto& ctx : receivers(64, 13)) {
        for (const auto& l : set.lights) {
            if (s.pmf(ctx, l.get()) > 0) continue;
            ++zeros;
            for (int k = 0; k < 32; ++k) {
                auto ls = l->sample_li(ctx, {rng.next_float(), rng.next_float()});
                if (!ls || ls->pdf_solid_angle == 0) continue;
                EXPECT_TRUE(ls->L.is_black()) << "light " << l->index;
            }
        }
    }
    // The test means something only if some lights were ruled out (one-sided quads and spots
    // facing away, the dark light).
    EXPECT_GT(zeros, 64);
}

TEST(LightTreeSampler, ContextFreeChoiceIsPowerAndNamesAreChecked) {
    LightSet set(20, 1);
    LightSampler tree("tree", set.lights), power("power", set.lights);
    for (const auto& l : set.lights) EXPECT_EQ(tree.pmf(l.get()), power.pmf(l.get()));
    // uniform and power ignore the receiver.
    LightSampleContext ctx{Vec3(1, 2, 3), Vec3(0, 0, 1), Vec3(0, 0, 1)};
    for (const auto& l : set.lights) EXPECT_EQ(power.pmf(ctx, l.get()), power.pmf(l.get()));
    LightSampler empty("tree", std::vector<std::unique_ptr<Light>>{});
    EXPECT_FALSE(empty.sample(ctx, 0.5f));
    EXPECT_EQ(empty.pmf(ctx, set.lights[0].get()), 0.f);
}

// Facing the sun, a receiver samples it more often than one facing away (the top-level choice
// weighs each unbounded light by the irradiance it gives that orientation), and never less than
// the uniform share.
TEST(LightTreeSampler, DistantLightWeighedByOrientation) {
    std::vector<std::unique_ptr<Light>> lights;
    Vec3 to_sun = normalize(Vec3(0, 1, 1));
    lights.push_back(make_distant_light(to_sun, RGB(10)));
    lights.push_back(make_uniform_infinite_light(RGB(0.5f)));
    Bounds3 scene;
    scene.expand(Vec3(-1, -1, -1));
    scene.expand(Vec3(1, 1, 1));
    for (size_t i = 0; i < lights.size(); ++i)
        lights[i]->index = int(i), lights[i]->preprocess(scene);
    LightSampler s("tree", lights);
    Vec3 side = normalize(cross(to_sun, Vec3(1, 0, 0)));
    LightSampleContext facing{Vec3(), to_sun, to_sun}, edge_on{Vec3(), side, side};
    float p_facing = s.pmf(facing, lights[0].get()), p_edge = s.pmf(edge_on, lights[0].get());
    EXPECT_GT(p_facing, 0.7f);
    EXPECT_LT(p_edge, 0.4f);
    EXPECT_LT(p_edge, 0.5f * p_facing);
    EXPECT_GE(p_edge, 0.5f * kTopLevelUniform);
    EXPECT_NEAR(s.pmf(edge_on, lights[0].get()) + s.pmf(edge_on, lights[1].get()), 1.f, 1e-6f);
}

}  // namespace
}  // namespace ml
