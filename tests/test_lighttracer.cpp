// Light tracing: the white furnace, agreement with path on the Cornell box (area, point and spot
// lights), and the same image for any thread count.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "bidir_test_helpers.h"

using namespace ml;

TEST(LightTracer, WhiteFurnaceHoldsAtEachDepth) {
    // Depth d: Le (1 + a + ... + a^d); splats reach every pixel with their own noise.
    for (int depth : {0, 3}) {
        RenderOptions opt;
        opt.integrator = "lighttracer";
        opt.spp = 64;
        opt.seed = 5;
        test::expect_furnace(opt, depth);
    }
}

TEST(LightTracer, AgreesWithPathOnTheCornellBox) {
    std::string scene = test::cornell_variant();
    auto lt = test::render_twice(scene, "lighttracer", 64, 4, 32);
    auto pt = test::render_twice(scene, "path", 64, 4, 32);
    test::expect_agreement(lt, pt, 8, "lighttracer vs path, area light");
}

TEST(LightTracer, AgreesWithPathUnderPointAndSpotLights) {
    std::string point = R"(LightSource "point" "rgb I" [ 60000 50000 30000 ]
  "point3 from" [ 278 500 279 ])";
    std::string spot = R"(LightSource "spot" "rgb I" [ 150000 120000 80000 ]
  "point3 from" [ 278 540 279 ] "point3 to" [ 278 0 279 ] "float coneangle" [ 40 ]
  "float conedeltaangle" [ 10 ])";
    for (const std::string& light : {point, spot}) {
        std::string scene = test::cornell_variant("", light);
        auto lt = test::render_twice(scene, "lighttracer", 32, 3, 32);
        auto pt = test::render_twice(scene, "path", 32, 3, 32);
        test::expect_agreement(lt, pt, 8, "lighttracer vs path: " + light);
    }
}

TEST(LightTracer, SameImageForAnyThreadCount) {
    std::string scene = test::cornell_variant();
    auto render = [&](int threads) {
        RenderOptions opt;
        opt.integrator = "lighttracer";
        opt.spp = 4;
        opt.max_depth = 3;
        opt.width = opt.height = 32;
        opt.threads = threads;
        opt.seed = 3;
        return test::render_text(scene, opt).image;
    };
    Image a = render(1), b = render(2);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i) ASSERT_TRUE(a.pixels[i] == b.pixels[i]) << i;
}
