// The bias check (integrators/bias_check.h): its interval is honest on made-up data, its pixels
// and estimates are the same for a seed on any thread count and leave the image alone, it
// catches a clamp set by hand on the classroom and stays quiet on the Cornell box.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "core/rng.h"
#include "integrators/bias_check.h"
#include "integrators/render_job.h"
#include "render_helpers.h"
#include "scene/default_scene.h"
#include "shared_files.h"

using namespace ml;

namespace {

bool identical(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height) return false;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        if (!(a.pixels[i] == b.pixels[i])) return false;
    return true;
}

// The check's figures without its time, which is the one thing that may differ between runs.
nlohmann::json without_seconds(const BiasCheckResult& r) {
    nlohmann::json j = r.to_json();
    j.erase("seconds");
    return j;
}

RenderOutput render_shared(const std::string& rel, RenderOptions opt) {
    LoadedScene scene = load_scene(test::shared_path(rel));
    return render_scene(std::move(scene.desc), opt);
}

std::string describe(const RenderOutput& out) {
    nlohmann::json j = out.figures.bias_check ? out.figures.bias_check->to_json() : nullptr;
    return j.dump() + "\nwarnings: " + nlohmann::json(out.figures.warnings).dump();
}

bool warned(const RenderOutput& out) {
    for (const std::string& w : out.figures.warnings)
        if (w.rfind("bias check:", 0) == 0) return true;
    return false;
}

}  // namespace

TEST(BiasCheck, StudentQuantilesMatchTables) {
    EXPECT_NEAR(student_t_quantile(0.95, 10), 2.228, 2e-3);
    EXPECT_NEAR(student_t_quantile(0.99, 30), 2.750, 2e-3);
    EXPECT_NEAR(student_t_quantile(0.99, 255), 2.596, 2e-3);
    EXPECT_NEAR(student_t_quantile(0.95, 1e9), 1.960, 1e-3);
}

// On pairs whose means agree, the interval holds the true ratio 1 about as often as its level
// says, with the reference as skewed as a path tracer's few-sample estimates (exponential) and
// pixels of very different brightness (a one-sample reference: the interval is about +-16%
// at 99%); on pairs 30% apart it finds the difference.
TEST(BiasCheck, IntervalCoversTheTrueRatio) {
    const int trials = 400, n = 256;
    int covered95 = 0, covered99 = 0, found = 0;
    for (int t = 0; t < trials; ++t) {
        Rng rng(hash_ints(7, uint64_t(t)));
        std::vector<double> image(n), reference(n), biased(n);
        for (int i = 0; i < n; ++i) {
            double truth = 0.05 + 5.0 * double(rng.next_float()) * rng.next_float();
            image[size_t(i)] = truth * (0.8 + 0.4 * rng.next_float());
            reference[size_t(i)] = truth * -std::log(1.0 - double(rng.next_float()));
            biased[size_t(i)] = 0.7 * image[size_t(i)];
        }
        auto ci95 = ratio_of_means(image, reference, 0.95);
        auto ci99 = ratio_of_means(image, reference, 0.99);
        ASSERT_TRUE(ci95 && ci99);
        EXPECT_LT(ci95->hi - ci95->lo, ci99->hi - ci99->lo);
        covered95 += ci95->lo <= 1 && 1 <= ci95->hi;
        covered99 += ci99->lo <= 1 && 1 <= ci99->hi;
        auto off = ratio_of_means(biased, reference, 0.99);
        found += off->hi < 1;
    }
    EXPECT_GE(covered95, int(0.92 * trials));
    EXPECT_LE(covered95, int(0.98 * trials));
    EXPECT_GE(covered99, int(0.97 * trials));
    EXPECT_GE(found, int(0.95 * trials));
    std::printf("covered: %d (95%%), %d (99%%); 30%% found: %d of %d\n", covered95, covered99,
                found, trials);
}

TEST(BiasCheck, UndefinedWithoutLight) {
    EXPECT_FALSE(ratio_of_means({0, 0, 0}, {0, 0, 0}, 0.99));
    EXPECT_FALSE(ratio_of_means({1}, {1}, 0.99));
}

TEST(BiasCheck, OptionsAreCheckedAndAutoPicksTheManyLightIntegrators) {
    EXPECT_EQ(parse_bias_check_mode("auto"), BiasCheckMode::Auto);
    EXPECT_THROW(parse_bias_check_mode("yes"), UsageError);
    BiasCheckOptions o;
    o.share = 0.8;
    EXPECT_THROW(validate(o), UsageError);
    o.share = 0.1;
    o.pixels = 1;
    EXPECT_THROW(validate(o), UsageError);
    o.mode = BiasCheckMode::Auto;
    for (const char* name :
         {"vpl", "lightcuts", "mdlightcuts", "bdlightcuts", "stochasticlightcuts", "igi"})
        EXPECT_TRUE(bias_check_enabled(o, name)) << name;
    for (const char* name : {"path", "bdpt", "mlt", "pssmlt", "lighttracer"})
        EXPECT_FALSE(bias_check_enabled(o, name)) << name;
    o.mode = BiasCheckMode::Off;
    EXPECT_FALSE(bias_check_enabled(o, "lightcuts"));
    o.mode = BiasCheckMode::On;
    EXPECT_TRUE(bias_check_enabled(o, "path"));
    // Without a time limit: a tenth of the time is a ninth of the render's samples.
    o.pixels = 256;
    EXPECT_EQ(bias_check_spp(o, 16, 64, 64), int(std::ceil(16.0 * 64 * 64 / 256 / 9)));
}

// The check's pixels and estimates follow the seed, not the thread count, and the image is the
// one a render without the check makes.
TEST(BiasCheck, SeedStableAndLeavesTheImageAlone) {
    RenderOptions opt;
    opt.integrator = "path";
    opt.spp = 4;
    opt.width = opt.height = 32;
    opt.seed = 5;
    opt.bias_check.mode = BiasCheckMode::On;
    opt.bias_check.pixels = 64;
    opt.threads = 1;
    RenderOutput one = test::render_text(default_scene_text(), opt);
    opt.threads = 2;
    RenderOutput two = test::render_text(default_scene_text(), opt);
    ASSERT_TRUE(one.figures.bias_check && two.figures.bias_check);
    EXPECT_EQ(without_seconds(*one.figures.bias_check), without_seconds(*two.figures.bias_check));
    EXPECT_EQ(one.figures.bias_check->pixels, 64);
    EXPECT_TRUE(identical(one.image, two.image));
    opt.bias_check.mode = BiasCheckMode::Off;
    RenderOutput off = test::render_text(default_scene_text(), opt);
    EXPECT_FALSE(off.figures.bias_check);
    EXPECT_TRUE(identical(one.image, off.image));
    EXPECT_FALSE(off.figures.to_json().contains("bias_check"));
    EXPECT_TRUE(one.figures.to_json().contains("bias_check"));
    opt.bias_check.mode = BiasCheckMode::On;
    opt.seed = 6;
    RenderOutput other = test::render_text(default_scene_text(), opt);
    EXPECT_NE(without_seconds(*one.figures.bias_check), without_seconds(*other.figures.bias_check));
}

// A clamp set by hand darkens the classroom by far more than 1%: the check must say so.
TEST(BiasCheck, CatchesAHandClampOnTheClassroom) {
    ML_NEED_SHARED("scenes/classroom/scene-v4.pbrt");
    RenderOptions opt;
    opt.integrator = "mdlightcuts";
    opt.set["vpl.clamp"] = "0.05";
    opt.width = 80;
    opt.height = 45;
    opt.spp = 4;
    opt.seed = 1;
    opt.bias_check.mode = BiasCheckMode::Auto;
    opt.bias_check.spp = 32;
    RenderOutput out = render_shared("scenes/classroom/scene-v4.pbrt", opt);
    ASSERT_TRUE(out.figures.bias_check) << describe(out);
    const BiasCheckResult& r = *out.figures.bias_check;
    EXPECT_EQ(r.verdict, "off") << describe(out);
    EXPECT_TRUE(warned(out)) << describe(out);
    for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(r.ci99[size_t(c)]) << describe(out);
        EXPECT_LT(r.ci99[size_t(c)]->hi, 1.0) << describe(out);
    }
}

// The Cornell box rendered without bias: `path` under the check given by hand, and
// `mdlightcuts` with no clamp (every surface is diffuse, so its VPLs miss nothing).
TEST(BiasCheck, QuietOnTheCornellBox) {
    ML_NEED_SHARED("scenes/cornell-box/scene-v4.pbrt");
    for (auto [integrator, spp] :
         {std::pair{std::string("path"), 32}, std::pair{std::string("mdlightcuts"), 8}}) {
        RenderOptions opt;
        opt.integrator = integrator;
        if (integrator != "path") opt.set["vpl.clamp"] = "0";
        opt.width = opt.height = 64;
        opt.spp = spp;
        opt.seed = 1;
        opt.bias_check.mode = BiasCheckMode::On;
        opt.bias_check.spp = 64;
        RenderOutput out = render_shared("scenes/cornell-box/scene-v4.pbrt", opt);
        ASSERT_TRUE(out.figures.bias_check) << integrator << describe(out);
        EXPECT_EQ(out.figures.bias_check->verdict, "ok") << integrator << describe(out);
        EXPECT_FALSE(warned(out)) << integrator << describe(out);
    }
}
