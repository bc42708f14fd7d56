// lights.direct=sample (manylight/direct.h): the many-light integrators take the area and
// infinite lights' direct light by next-event estimation with MIS instead of as point lights.
// Checked against the path tracer's direct light (an independent estimator) on scenes where the
// point-light conversion is singular (a receiver nearly touching the emitter), with an environment
// light, a delta light that stays a point light, and a glossy receiver; and Lightcuts against the
// exact `vpl` sum on the same set, now that the sampled light counts in its threshold.
#include <gtest/gtest.h>

#include "render_helpers.h"
#include "scene/default_scene.h"

using namespace ml;

namespace {

// A glossy floor, a diffuse wall that touches the bottom edge of an area light, a point light,
// and a dim constant environment.
const char* kScene = R"(
LookAt 0 1.5 -3.5  0 0.6 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 32 ]
WorldBegin
LightSource "infinite" "rgb L" [ 0.2 0.25 0.3 ]
LightSource "point" "point3 from" [ -1 1.5 -0.5 ] "rgb I" [ 0.8 0.6 0.4 ]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 6 6 6 ]
  Material "diffuse" "rgb reflectance" [ 0 0 0 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -0.6 0.8 0.99  0.6 0.8 0.99  0.6 1.2 0.6  -0.6 1.2 0.6 ]
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.6 0.5 0.4 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -2 0 1  2 0 1  2 2.5 1  -2 2.5 1 ]
AttributeEnd
AttributeBegin
  Material "coateddiffuse" "float roughness" [ 0.1 ] "rgb reflectance" [ 0.4 0.4 0.4 ]
  Shape "trianglemesh" "integer indices" [ 0 2 1 0 3 2 ]
    "point3 P" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ]
AttributeEnd
)";

Image render(const std::string& integrator, int spp, const std::string& direct, bool mis = true) {
    RenderOptions opt;
    opt.integrator = integrator;
    opt.spp = spp;
    opt.seed = 11;
    opt.max_depth = 1;
    if (integrator != "path") {
        opt.set["vpl.count"] = "0";
        opt.set["lights.direct"] = direct;
        opt.set["lights.area_count"] = "64";
        if (!mis) opt.set["lights.direct_mis"] = "glossy";
    }
    return test::render_text(kScene, opt).image;
}

}  // namespace

// Direct light only (no VPLs): `vpl` and `lightcuts` with sampled direct light agree with the
// path tracer at depth 1 in every channel, to 4 standard errors. (Leaving out the BSDF-sampled
// half of the MIS pair makes them 20 standard errors too dark.)
TEST(SampledDirect, MatchesThePathTracersDirectLight) {
    Image ref = render("path", 1024, "");
    for (const char* integrator : {"vpl", "lightcuts"}) {
        Image img = render(integrator, 64, "sample");
        for (int c = 0; c < 3; ++c) {
            test::MeanDifference d = test::mean_difference(img, ref, c);
            EXPECT_NEAR(d.mean, 0, 4 * d.stderr_of_mean) << integrator << " channel " << c;
            std::printf("%s sample, channel %d: mean difference %+.5f (reference %.4f, se %.5f)\n",
                        integrator, c, d.mean, d.reference_mean, d.stderr_of_mean);
        }
    }
}

// lights.direct_mis=glossy (the viewer's moving frames): light samples alone on the diffuse
// wall, light and BSDF samples with MIS on the glossy floor. The same expectation as the path
// tracer's direct light in every channel, to 4 standard errors of the difference, on the scene
// with a receiver touching the area light, a point light and a uniform sky. The sky is what fails
// if the light samples kept MIS's incomplete density (a uniform sky is left to BSDF sampling
// there): the test then fails (the diffuse wall lacks the sky's light).
// And the images differ from MIS's everywhere at the same seed: the setting is used.
TEST(SampledDirect, MisOnGlossyOnlyMatchesThePathTracersDirectLight) {
    Image ref = render("path", 1024, "");
    for (const char* integrator : {"vpl", "igi"}) {
        Image img = render(integrator, 64, "sample", false);
        for (int c = 0; c < 3; ++c) {
            test::MeanDifference d = test::mean_difference(img, ref, c);
            EXPECT_NEAR(d.mean, 0, 4 * d.stderr_of_mean) << integrator << " channel " << c;
            std::printf(
                "%s light samples only, channel %d: mean difference %+.5f (reference "
                "%.4f, se %.5f)\n",
                integrator, c, d.mean, d.reference_mean, d.stderr_of_mean);
        }
        EXPECT_NE(img.pixels, render(integrator, 64, "sample", true).pixels) << integrator;
    }
}

// The environment light alone in the white furnace: sampled, it gives the furnace's exact value
// through the gather's direct light (depth 1 has no VPL bounce).
TEST(SampledDirect, FurnaceHolds) {
    for (const char* integrator : {"vpl", "lightcuts"}) {
        RenderOptions opt;
        opt.integrator = integrator;
        opt.spp = 16;
        opt.seed = 3;
        opt.set["vpl.count"] = "0";
        opt.set["lights.direct"] = "sample";
        opt.set["lights.direct_samples"] = "2";
        test::expect_furnace(opt, 1);
    }
}

// With VPLs and sampled direct light, Lightcuts stays within its error of the exact `vpl` sum
// (the two draw the same direct-light samples, so only the cut differs) in 99% of the Cornell
// box's pixels.
TEST(SampledDirect, LightcutsWithinTheErrorOfTheExactSum) {
    auto run = [](const std::string& integrator) {
        RenderOptions opt;
        opt.integrator = integrator;
        opt.spp = 16;
        opt.width = opt.height = 32;
        opt.seed = 5;
        opt.progress = false;
        opt.set["vpl.count"] = "2000";
        opt.set["lights.direct"] = "sample";
        opt.set["vpl.clamp"] = "0";
        if (integrator == "lightcuts") {
            opt.set["lightcuts.error"] = "0.02";
            opt.set["lightcuts.max_cut"] = "1000";
            // Walter's relative test, which this checks; the floor (test_cut_floor.cpp)
            // relaxes it below the image's mean by design.
            opt.set["lightcuts.floor"] = "0";
        }
        return render_scene(parse_scene_string(default_scene_text(), "."), opt);
    };
    RenderOutput exact = run("vpl"), lc = run("lightcuts");
    size_t within = 0, n = exact.image.pixels.size();
    for (size_t i = 0; i < n; ++i) {
        double e = exact.image.pixels[i].luminance(), c = lc.image.pixels[i].luminance();
        if (std::abs(c - e) <= 0.02 * std::max(e, 1e-6)) ++within;
    }
    std::printf("%.1f%% of pixels within 2%%\n", 100.0 * double(within) / double(n));
    EXPECT_GE(double(within), 0.99 * double(n));
    EXPECT_EQ(lc.figures.integrator_stats.at("lightcuts").at("direct"), "sample");
}

TEST(SampledDirect, RejectsUnknownModesAndUnusedCounts) {
    RenderOptions opt;
    opt.integrator = "vpl";
    opt.set["lights.direct"] = "maybe";
    EXPECT_THROW(test::render_text(test::furnace_scene(0.5f, 1.f, 4), opt), std::exception);
    opt.set["lights.direct"] = "points";
    opt.set["lights.direct_samples"] = "8";
    EXPECT_THROW(test::render_text(test::furnace_scene(0.5f, 1.f, 4), opt), std::exception);
    opt.set["lights.direct"] = "sample";
    opt.set["lights.direct_samples"] = "0";
    EXPECT_THROW(test::render_text(test::furnace_scene(0.5f, 1.f, 4), opt), std::exception);
    opt.set.erase("lights.direct_samples");
    opt.set["lights.direct_mis"] = "false";
    EXPECT_THROW(test::render_text(test::furnace_scene(0.5f, 1.f, 4), opt), std::exception);
    opt.set["lights.direct"] = "points";
    opt.set["lights.direct_mis"] = "glossy";
    EXPECT_THROW(test::render_text(test::furnace_scene(0.5f, 1.f, 4), opt), std::exception);
}

// The whole transport: with sampled direct light and VPLs made to maxdepth - 1 bounces (the
// default vpl.max_depth), `vpl` gives the path tracer's image at the same maxdepth, to 4
// standard errors plus 1% for the VPL set's own error (shared by all pixels). At maxdepth 2,
// VPLs made to the old fixed depth of 5 are 11% too bright in red (7 standard errors).
TEST(SampledDirect, InstantRadiosityMatchesThePathTracerAtItsDepth) {
    auto run = [](const std::string& integrator, int spp) {
        RenderOptions opt;
        opt.integrator = integrator;
        opt.spp = spp;
        opt.width = opt.height = 16;
        opt.max_depth = 2;
        opt.seed = 9;
        opt.progress = false;
        if (integrator == "vpl") {
            opt.set["vpl.count"] = "4000";
            opt.set["lights.direct"] = "sample";
            opt.set["vpl.clamp"] = "0";  // clamping takes light away: not the path tracer's
        }
        return render_scene(parse_scene_string(default_scene_text(), "."), opt).image;
    };
    Image ref = run("path", 4096), img = run("vpl", 64);
    for (int c = 0; c < 3; ++c) {
        test::MeanDifference d = test::mean_difference(img, ref, c);
        EXPECT_NEAR(d.mean, 0, 4 * d.stderr_of_mean + 0.01 * d.reference_mean) << "channel " << c;
        std::printf("channel %d: mean difference %+.5f (reference %.4f, se %.5f)\n", c, d.mean,
                    d.reference_mean, d.stderr_of_mean);
    }
}
