// Path-space Metropolis light transport: the white furnace, agreement with path on the Cornell box
// (with glass and mirror spheres too: lens and caustic perturbations through specular chains),
// with light tracing for point-light caustics, and the same image for any thread count.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "bidir_test_helpers.h"

using namespace ml;

namespace {

std::map<std::string, std::string> small_bootstrap() {
    return {{"mlt.bootstrap", "20000"}, {"mlt.chains", "64"}};
}

}  // namespace

TEST(Mlt, WhiteFurnaceHoldsAtDepthThree) {
    // Le (1 + a + a^2 + a^3); the two seeds' spread sets the tolerance (the image's scale b
    // comes from the bootstrap, whose noise moves every pixel together).
    auto r =
        test::render_twice(test::furnace_scene(0.5f, 1.f, 16), "mlt", 64, 3, 16, small_bootstrap());
    double expected = 1.875;
    for (int c = 0; c < 3; ++c) {
        double m1 = test::channel_stats(r.a, c).mean, m2 = test::channel_stats(r.b, c).mean;
        double sd = std::abs(m1 - m2) / std::sqrt(2.0);
        EXPECT_NEAR(0.5 * (m1 + m2), expected, 5 * sd + 0.01 * expected) << "channel " << c;
    }
}

TEST(Mlt, AgreesWithPathOnTheCornellBox) {
    std::string scene = test::cornell_variant();
    auto m = test::render_twice(scene, "mlt", 64, 4, 32, small_bootstrap());
    auto p = test::render_twice(scene, "path", 64, 4, 32);
    test::expect_agreement(m, p, 16, "mlt vs path, area light");
}

TEST(Mlt, AgreesWithPathThroughGlassAndMirrors) {
    std::string scene = test::cornell_variant(test::glass_and_mirror());
    auto m = test::render_twice(scene, "mlt", 128, 5, 32, small_bootstrap());
    auto p = test::render_twice(scene, "path", 256, 5, 32);
    test::expect_agreement(m, p, 16, "mlt vs path, glass and mirror");
}

TEST(Mlt, AgreesWithBdptForPointLightCausticsThroughGlass) {
    // Path tracing cannot find these caustics; BDPT (tested against light tracing) can.
    std::string scene = test::cornell_variant(test::glass_and_mirror(), test::kCornellPointLight);
    auto m = test::render_twice(scene, "mlt", 128, 4, 32, small_bootstrap());
    auto b = test::render_twice(scene, "bdpt", 64, 4, 32);
    test::expect_agreement(m, b, 16, "mlt vs bdpt, point light, glass and mirror");
}

TEST(Mlt, SameImageForAnyThreadCount) {
    std::string scene = test::cornell_variant(test::glass_and_mirror());
    auto render = [&](int threads) {
        RenderOptions opt;
        opt.integrator = "mlt";
        opt.spp = 4;
        opt.max_depth = 4;
        opt.width = opt.height = 16;
        opt.threads = threads;
        opt.seed = 3;
        opt.set = small_bootstrap();
        return test::render_text(scene, opt).image;
    };
    Image a = render(1), b = render(2);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i) ASSERT_TRUE(a.pixels[i] == b.pixels[i]) << i;
}

TEST(Cmlt, AgreesWithPathThroughGlassAndMirrors) {
    // Coherent MLT: the lens perturbation as multiple-try Metropolis over packets of four rays
    // (with the whole-path bidirectional proposal: test_mlt_bidir.cpp tests the partial one).
    std::string scene = test::cornell_variant(test::glass_and_mirror());
    std::map<std::string, std::string> set = {
        {"cmlt.bootstrap", "20000"}, {"cmlt.chains", "64"}, {"cmlt.bidirectional", "whole"}};
    auto m = test::render_twice(scene, "cmlt", 128, 5, 32, set);
    auto p = test::render_twice(scene, "path", 256, 5, 32);
    test::expect_agreement(m, p, 16, "cmlt vs path, glass and mirror");
}

TEST(Cmlt, SameImageForAnyThreadCount) {
    std::string scene = test::cornell_variant(test::glass_and_mirror());
    auto render = [&](int threads) {
        RenderOptions opt;
        opt.integrator = "cmlt";
        opt.spp = 4;
        opt.max_depth = 4;
        opt.width = opt.height = 16;
        opt.threads = threads;
        opt.seed = 3;
        opt.set = {{"cmlt.bootstrap", "20000"}, {"cmlt.chains", "64"}};
        return test::render_text(scene, opt).image;
    };
    Image a = render(1), b = render(2);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i) ASSERT_TRUE(a.pixels[i] == b.pixels[i]) << i;
}
