// Light tracing: the white furnace, agreement with path on the Cornell box (area, point and spot
// lights), the film's border pixels under a wide filter, and the same image for any thread count.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

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

TEST(LightTracer, BorderPixelsUnderAWideFilterGetWhatCameraSamplesGive) {
    // A diffuse floor of albedo 0.5 under a distant light of irradiance pi (the floor a little
    // wider than the view, so that most light paths land in it), seen from above
    // through the default gaussian filter (radius 1.5): every pixel is 0.5, the border pixels
    // too. A border pixel's camera samples land up to one pixel past the film's edge; light
    // paths joined to the lens must reach as far, or the border comes out dark (it did: 10% and
    // more at a 10x8 film's edge), and PSSMLT must draw its camera rays as far.
    const std::string scene =
        "\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 20 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 10 ] \"integer yresolution\" [ 8 ]\n"
        "Sampler \"independent\"\nWorldBegin\n"
        "LightSource \"distant\" \"point3 from\" [ 0 0 1 ] \"point3 to\" [ 0 0 0 ]\n"
        "  \"rgb L\" [ 3.14159265 3.14159265 3.14159265 ]\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -1.5 -1.5 0  1.5 -1.5 0  1.5 1.5 0  -1.5 1.5 0 ]\n";
    for (const char* integrator : {"lighttracer", "bdpt", "pssmlt"}) {
        SCOPED_TRACE(integrator);
        RenderOptions opt;
        opt.integrator = integrator;
        opt.spp = 1024;
        opt.max_depth = 1;
        opt.seed = 9;
        const Image img = test::render_text(scene, opt).image;
        double s = 0, s2 = 0, n = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                if (x > 0 && y > 0 && x < img.width - 1 && y < img.height - 1) continue;
                const double v = img.pixels[size_t(y) * img.width + x][1];
                s += v, s2 += v * v, n += 1;
            }
        const double mean = s / n, se = std::sqrt(std::max(0.0, s2 / n - mean * mean) / (n - 1));
        EXPECT_NEAR(mean, 0.5, 4 * se + 1e-4)
            << "border pixels' mean (standard error " << se << ")";
        EXPECT_NEAR(mean, 0.5, 0.02);
    }
}
