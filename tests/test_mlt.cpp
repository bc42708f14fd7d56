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

TEST(Mlt, WhiteFurnaceHoldsAtDepthThree) { test::expect_mlt_furnace(small_bootstrap()); }

TEST(Mlt, AgreesWithPathOnTheCornellBox) {
    test::expect_mlt_agrees_with_path_on_cornell(small_bootstrap(), "mlt");
}

TEST(Mlt, AgreesWithPathThroughGlassAndMirrors) {
    test::expect_mlt_agrees_with_path_through_glass(small_bootstrap(), "mlt");
}

TEST(Mlt, AgreesWithBdptForPointLightCausticsThroughGlass) {
    test::expect_mlt_agrees_with_bdpt_on_caustics(small_bootstrap(), "mlt");
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

namespace {

// Block means of `k` renders of each integrator (seeds 1..k): the worst |t| over 8 x 8 blocks and
// channels of the difference of their averages, each block's variance estimated from the spread
// of its k means. Metropolis renders' pixels are correlated (perturbations move paths by a few
// pixels), so per-pixel variances would understate the noise of a block.
double worst_block_t(const std::string& scene, const std::string& a, const std::string& b, int spp,
                     int k, const std::map<std::string, std::string>& set) {
    const int res = 32, block = 8, nb = res / block;
    std::vector<std::vector<double>> means[2];
    for (int which = 0; which < 2; ++which)
        for (int seed = 1; seed <= k; ++seed) {
            RenderOptions opt;
            opt.integrator = which == 0 ? a : b;
            opt.spp = spp;
            opt.max_depth = 4;
            opt.width = opt.height = res;
            opt.seed = seed;
            opt.sampler = "independent";
            if (which == 0) opt.set = set;  // the settings are a's
            Image img = test::render_text(scene, opt).image;
            std::vector<double> m(size_t(nb * nb * 3), 0.0);
            for (int y = 0; y < res; ++y)
                for (int x = 0; x < res; ++x)
                    for (int c = 0; c < 3; ++c)
                        m[size_t(((y / block) * nb + x / block) * 3 + c)] +=
                            img.at(x, y)[c] / double(block * block);
            means[which].push_back(m);
        }
    double worst = 0;
    for (size_t i = 0; i < size_t(nb * nb * 3); ++i) {
        double mu[2], var[2];
        for (int w = 0; w < 2; ++w) {
            double s = 0, s2 = 0;
            for (const auto& m : means[w]) s += m[i], s2 += m[i] * m[i];
            mu[w] = s / k;
            var[w] = std::max(0.0, (s2 - s * s / k) / (k - 1)) / k;
        }
        double sd = std::sqrt(var[0] + var[1]);
        if (sd > 0) worst = std::max(worst, std::abs(mu[0] - mu[1]) / sd);
    }
    return worst;
}

}  // namespace

TEST(Cmlt, ExpectedValuesOfEveryTryKeepItUnbiased) {
    // Most mutations multiple-try lens steps, each splatting all four tries by their expected
    // values: agreement with path in blocks of 8 x 8 pixels, where a splat that blurred the
    // image at the scale of the offsets would show at the box's edges and shadows.
    std::string scene = test::cornell_variant();
    std::map<std::string, std::string> set = {{"cmlt.bootstrap", "20000"},
                                              {"cmlt.chains", "64"},
                                              {"cmlt.bidirectional_prob", "0.25"},
                                              {"cmlt.lens_prob", "0.7"}};
    // Eight renders each: t with 7 degrees of freedom, beyond 7 with probability 2e-4 per
    // block and channel (48 of them).
    EXPECT_LT(worst_block_t(scene, "cmlt", "path", 64, 8, set), 7.0);
}

TEST(Mlt, BorderPixelsGetWhatCameraSamplesPastTheEdgeGiveThem) {
    // Under the default Gaussian filter a border pixel takes camera samples from up to the
    // filter's radius past the film's edge. Chains whose film positions stayed on the film gave
    // the border pixels none of that (a floor under a light, 16x16: the image 2.7% dark, about
    // 25 standard errors); now camera rays are drawn over the margin too, and their densities
    // count it. The means of the whole image and of its outer ring of pixels, over six seeds of
    // mlt (whose bootstrap moves each image's mean as a whole) and two of path.
    const std::string scene =
        "LookAt 0 2 -6  0 0.8 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 40 ]\n"
        "WorldBegin\nAttributeBegin\nTranslate 0 4 0\n"
        "AreaLightSource \"diffuse\" \"rgb L\" [ 20 20 20 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -0.6 0 -0.6  0.6 0 -0.6  0.6 0 0.6  -0.6 0 0.6 ]\nAttributeEnd\n"
        "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
        "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 0 2 3 ]\n"
        "  \"point3 P\" [ -5 0 -5  -5 0 5  5 0 5  5 0 -5 ]\n";
    const int res = 16;
    std::map<std::string, std::string> set = {{"mlt.bootstrap", "200000"}, {"mlt.chains", "64"}};
    const test::TwoRenders m = test::render_twice(scene, "mlt", 256, 2, res, set, 6);
    const test::TwoRenders p = test::render_twice(scene, "path", 1024, 2, res);
    auto mean = [&](const Image& img, bool ring) {
        double sum = 0;
        int n = 0;
        for (int y = 0; y < res; ++y)
            for (int x = 0; x < res; ++x) {
                if (ring && x > 0 && y > 0 && x < res - 1 && y < res - 1) continue;
                sum += img.pixels[size_t(y * res + x)].g;
                ++n;
            }
        return sum / n;
    };
    for (bool ring : {false, true}) {
        auto stats = [&](const test::TwoRenders& r, double* avg, double* var_of_avg) {
            std::vector<double> v;
            for (const Image* img : r.all()) v.push_back(mean(*img, ring));
            double s = 0, ss = 0;
            for (double x : v) s += x;
            *avg = s / double(v.size());
            for (double x : v) ss += (x - *avg) * (x - *avg);
            *var_of_avg = ss / double(v.size() - 1) / double(v.size());
        };
        double am, vm, ap, vp;
        stats(m, &am, &vm);
        stats(p, &ap, &vp);
        EXPECT_NEAR(am, ap, 4 * std::sqrt(vm + vp) + 1e-3 * ap)
            << (ring ? "the border ring" : "the whole image");
    }
}
