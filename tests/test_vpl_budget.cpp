// The VPL build under a time limit (manylight/vpl_budget.h): the sizing fit by hand; without a
// limit, sample_vpls itself, bit for bit; a budget too small for the count asked gives exactly
// the sampler's set at the least count; and a time-limited render that reduced its count still
// agrees with the analytic furnace.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "camera/camera.h"
#include "integrators/render_job.h"
#include "manylight/point_light_set.h"
#include "manylight/vpl_budget.h"
#include "manylight/vpl_sampler.h"
#include "render_helpers.h"
#include "scene/scene.h"
#include "vpl_test_scenes.h"

namespace ml {
namespace {

TEST(VplBudget, FitByHand) {
    // Two probes: 1000 VPLs in 0.3 s, 2000 in 0.5 s: 0.2 ms a VPL and 0.1 s fixed, so 2.1 s
    // hold (2.1 - 0.1) / 0.0002 = 10000 VPLs.
    const VplProbe a{1000, 0.3}, b{2000, 0.5};
    EXPECT_NEAR(fit_vpl_count(100000, a, b, 2.1), 10000, 1);
    EXPECT_EQ(fit_vpl_count(5000, a, b, 2.1), 5000);  // fits: the count asked
    // One probe: through it, no fixed part: 1000 in 0.25 s, 1 s holds 4000.
    EXPECT_NEAR(fit_vpl_count(100000, VplProbe{}, VplProbe{1000, 0.25}, 1.0), 4000, 1);
    // The larger probe no slower (noise): its mean cost, 0.14 ms a VPL, 1.4 s holds 10000.
    EXPECT_NEAR(fit_vpl_count(100000, a, VplProbe{2000, 0.28}, 1.4), 10000, 1);
    // Less time than the fixed part: the least count, or the count asked where it is smaller.
    EXPECT_EQ(fit_vpl_count(100000, a, b, 0.05), kVplFirstProbe);
    EXPECT_EQ(fit_vpl_count(500, a, b, 0.05), 500);
    // No probe (a count too small to probe): the count asked.
    EXPECT_EQ(fit_vpl_count(3000, VplProbe{}, VplProbe{}, 0.01), 3000);
}

PerspectiveCamera test_camera() {
    bool ok = false;
    Transform to_world = Transform::look_at({0, 0, -5}, {0, 0, 0}, {0, 1, 0}, &ok).inverse();
    return PerspectiveCamera(ParameterList(), to_world, 8, 8);
}

void expect_same_set(const PointLightSet& a, const PointLightSet& b, const char* what) {
    ASSERT_EQ(a.lights.size(), b.lights.size()) << what;
    ASSERT_GT(a.lights.size(), 0u) << what;
    for (size_t i = 0; i < a.lights.size(); ++i) {
        EXPECT_EQ(a.lights[i].p, b.lights[i].p) << what << " " << i;
        EXPECT_EQ(a.lights[i].intensity, b.lights[i].intensity) << what << " " << i;
    }
    EXPECT_EQ(a.vpls, b.vpls) << what;
    EXPECT_EQ(a.light_paths, b.light_paths) << what;
}

VplBudget budget_of(double seconds) {
    VplBudget b;
    b.seconds = seconds;
    return b;
}

VplOptions sampler_options(const char* sampler, int count) {
    VplOptions o;
    o.count = count;
    o.max_depth = 3;
    o.seed = 11;
    o.sampler.kind = parse_vpl_sampler(sampler);
    o.sampler.mir_pilot = 64;
    return o;
}

// No limit, or one the whole count fits: the set sample_vpls makes, bit for bit (so a render
// without --time-limit is today's).
TEST(VplBudget, WithoutALimitTheSetIsSampleVpls) {
    auto scene = vpl_test::make_scene(vpl_test::mixed_box());
    PerspectiveCamera camera = test_camera();
    for (const char* sampler : {"standard", "power", "bidirectional", "metropolis"}) {
        VplOptions o = sampler_options(sampler, 4096);
        PointLightSet direct, none, generous;
        sample_vpls(*scene, &camera, o, direct);
        EXPECT_EQ(sample_vpls_within(*scene, &camera, o, VplBudget{}, none), 4096);
        expect_same_set(direct, none, sampler);
        EXPECT_EQ(sample_vpls_within(*scene, &camera, o, budget_of(1e6), generous), 4096);
        expect_same_set(direct, generous, sampler);
    }
}

// A budget nothing fits: the least count, and exactly the sampler's set at that count (its own
// normalisation, by the paths or candidates it traced for it).
TEST(VplBudget, NoTimeGivesTheSamplersSetAtTheLeastCount) {
    auto scene = vpl_test::make_scene(vpl_test::mixed_box());
    PerspectiveCamera camera = test_camera();
    for (const char* sampler : {"standard", "power", "bidirectional", "metropolis"}) {
        VplOptions o = sampler_options(sampler, 1000000);
        PointLightSet reduced, direct;
        // The probe (kVplFirstProbe VPLs) is timed with the work the caller does next.
        VplBudget budget = budget_of(1e-6);
        int timed = 0;
        budget.also_timed = [&](const PointLightSet& probe) {
            ++timed;
            EXPECT_GT(probe.vpls, 0u) << sampler;
        };
        EXPECT_EQ(sample_vpls_within(*scene, &camera, o, budget, reduced), kVplFirstProbe)
            << sampler;
        EXPECT_EQ(timed, 1) << sampler;
        o.count = kVplFirstProbe;
        sample_vpls(*scene, &camera, o, direct);
        expect_same_set(direct, reduced, sampler);
    }
}

// The warning and the stats say what was reduced; none without a reduction.
TEST(VplBudget, WarningAndStats) {
    PointLightSet set;
    set.vpl_count_requested = set.vpl_count_used = 100000;
    EXPECT_EQ(vpl_budget_warning(set), "");
    set.vpl_count_used = 16000;
    std::string w = vpl_budget_warning(set);
    EXPECT_NE(w.find("from 100000 to 16000"), std::string::npos) << w;
    EXPECT_NE(w.find("a longer time limit lifts it"), std::string::npos) << w;
    EXPECT_EQ(vpl_budget_json(set).at("vpl_count_used"), 16000);
}

// Under a time limit that a million VPLs overrun many times, every sampler builds fewer, says
// so, and the furnace's image mean is still the geometric series (over seeds, as
// test_vpl_samplers' FurnaceEverySampler).
TEST(VplBudget, ReducedSetsAgreeWithTheFurnace) {
    const int depth = 3;
    const double expected = (1 - std::pow(0.5, depth + 1)) / (1 - 0.5);
    for (const char* sampler : {"standard", "power", "bidirectional", "metropolis"}) {
        const int count = std::string(sampler) == "standard" ? 100000000 : 1000000;
        double s = 0, s2 = 0;
        const int seeds = 6;
        for (int seed = 1; seed <= seeds; ++seed) {
            RenderOptions opt;
            opt.integrator = "stochasticlightcuts";  // unbiased, and its cost is not the set's size
            opt.spp = 2;
            opt.seed = uint64_t(seed);
            opt.max_depth = depth;
            opt.time_limit = 1.5;
            opt.set["vpl.sampler"] = sampler;
            opt.set["vpl.count"] = std::to_string(count);
            opt.set["vpl.clamp"] = "0";
            if (std::string(sampler) == "metropolis") opt.set["vpl.metropolis.pilot"] = "64";
            RenderOutput out = test::render_text(test::furnace_scene(0.5f, 1.f, 8), opt);
            int used = out.figures.integrator_stats.at("stochasticlightcuts").at("vpl_count_used");
            EXPECT_LT(used, count) << sampler;
            EXPECT_GE(used, kVplFirstProbe) << sampler;
            // (A loaded machine may cut the second pass short: pixels of 1 sample or 2, each an
            // unbiased estimate; none may have none.)
            EXPECT_EQ(out.figures.pixels_without_samples, 0u) << sampler;
            bool warned = false;
            for (const std::string& w : out.figures.warnings)
                warned |= w.find("vpl.count was reduced") != std::string::npos;
            EXPECT_TRUE(warned) << sampler;
            double mean = 0;
            for (const RGB& p : out.image.pixels) mean += p.luminance();
            mean /= double(out.image.pixels.size());
            s += mean, s2 += mean * mean;
        }
        double mean = s / seeds;
        double se = std::sqrt(std::max(0.0, s2 / seeds - mean * mean) / (seeds - 1));
        EXPECT_NEAR(mean, expected, 4.5 * se + 3e-3 * expected) << sampler;
    }
}

}  // namespace
}  // namespace ml
