// Reconstruction cuts (`lightcuts.reconstruct`, integrators/lightcuts/reconstruction.h) against
// the brute-force `vpl` sum over the same point lights, and against `lightcuts` without them.
//
// The scene: a grey floor lit by two groups of 256 point lights, a bright one on the +x side and
// a dim one on the -x side, and between them a low red wall across the whole image, which casts a
// straight shadow edge of each group on the floor. The floor and the wall differ in material, and
// the wall's top is a depth step above the floor.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "core/error.h"
#include "render_helpers.h"

namespace ml {
namespace {

constexpr int kRes = 48;

std::string light_group(float x, float scale) {
    std::string lights;
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j)
            lights += fmt::format(
                "LightSource \"point\" \"rgb I\" [ {} {} {} ] \"point3 from\" [ {} 2.5 {} ]\n",
                0.02 * scale, 0.015 * scale, 0.01 * scale, x - 0.2 + 0.4 * i / 15.0,
                -2 + 4 * j / 15.0);
    return lights;
}

std::string floor_scene(bool wall) {
    std::string text = fmt::format(R"(LookAt 0 9 0  0 0 0  0 0 1
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ {0} ] "integer yresolution" [ {0} ]
WorldBegin
)",
                                   kRes) +
                       light_group(1.2f, 1.f) + light_group(-3.f, 0.3f) + R"(
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ -6 0 -6  6 0 -6  6 0 6  -6 0 6 ]
)";
    if (wall)
        text += R"(
Material "diffuse" "rgb reflectance" [ 0.6 0.2 0.2 ]
AttributeBegin
  Translate 0 0.5 0
  Scale 0.3 0.5 8
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3  4 6 5 4 7 6  0 4 5 0 5 1
      2 6 7 2 7 3  0 3 7 0 7 4  1 5 6 1 6 2 ]
    "point3 P" [ -1 -1 -1  1 -1 -1  1 1 -1  -1 1 -1  -1 -1 1  1 -1 1  1 1 1  -1 1 1 ]
AttributeEnd
)";
    return text;
}

struct ReconRun {
    Image image;
    double shadow_rays = 0, reconstructed = 0, avg_cut = 0;
};

ReconRun render_with(const std::string& integrator, bool wall, int reconstruct, int threads = 2) {
    RenderOptions opt;
    opt.integrator = integrator;
    opt.spp = 4;
    opt.seed = 11;
    opt.threads = threads;
    opt.set["vpl.count"] = "0";
    opt.set["lights.direct"] = "points";
    if (integrator == "lightcuts") {
        opt.set["lightcuts.error"] = "0.02";
        opt.set["lightcuts.floor"] = "0";
        opt.set["lightcuts.reconstruct"] = std::to_string(reconstruct);
    }
    RenderOutput out = test::render_text(floor_scene(wall), opt);
    ReconRun r{out.image};
    if (integrator == "lightcuts") {
        const nlohmann::json& s = out.figures.integrator_stats.at("lightcuts");
        r.shadow_rays = s.at("shadow_rays_per_pixel").get<double>();
        r.avg_cut = s.at("avg_cut_size").get<double>();
        if (reconstruct > 1)
            r.reconstructed = s.at("reconstruction").at("reconstructed_fraction").get<double>();
    }
    return r;
}

// The fraction of pixels within `error` of the exact sum, relative to the larger of the exact
// value and `floor` (the shadowed floor's exact value is near 0).
double fraction_within(const Image& estimate, const Image& exact, double error, double floor) {
    size_t within = 0;
    for (size_t i = 0; i < exact.pixels.size(); ++i) {
        double e = exact.pixels[i].luminance(), c = estimate.pixels[i].luminance();
        if (std::abs(c - e) <= error * std::max(e, floor)) ++within;
    }
    return double(within) / double(exact.pixels.size());
}

double mean_luminance(const Image& img) {
    double s = 0;
    for (const RGB& p : img.pixels) s += p.luminance();
    return s / double(img.pixels.size());
}

// Within the error of the exact sum as often as ordinary lightcuts are, no pixel across a shadow
// edge takes the lit side's value, and the shadow rays that remain are those of the edges.
TEST(ReconstructionCuts, AgreeWithTheExactSumAcrossShadowEdges) {
    ReconRun exact = render_with("vpl", true, 0);
    ReconRun full = render_with("lightcuts", true, 0);
    ReconRun recon = render_with("lightcuts", true, 4);
    const double mean = mean_luminance(exact.image);

    // The scene has what the test is about: floor pixels in shadow beside lit ones. An edge
    // pixel is under half the brighter of the pixels two to either side of it in x (the wall
    // and its shadows run along the image's y).
    const Image& e = exact.image;
    auto lum = [&](const Image& img, int x, int y) {
        return double(img.pixels[size_t(y) * kRes + size_t(x)].luminance());
    };
    double lit = 0;
    for (const RGB& p : e.pixels) lit = std::max<double>(lit, p.luminance());
    int edge_pixels = 0, took_lit = 0;
    double worst_edge = 0;
    for (int y = 0; y < kRes; ++y)
        for (int x = 2; x < kRes - 2; ++x) {
            double here = lum(e, x, y), side = std::max(lum(e, x - 2, y), lum(e, x + 2, y));
            if (!(here < 0.5 * side && side > 0.1 * lit)) continue;
            ++edge_pixels;
            // How far towards the lit side's value the reconstruction moved it.
            double moved = (lum(recon.image, x, y) - here) / (side - here);
            worst_edge = std::max(worst_edge, moved);
            if (moved > 0.5) ++took_lit;
        }

    double f_full = fraction_within(full.image, e, 0.05, 0.1 * mean);
    double f_recon = fraction_within(recon.image, e, 0.05, 0.1 * mean);
    std::printf(
        "within 5%%: %.1f%% of pixels (lightcuts), %.1f%% (reconstruct=4, %.0f%% of samples "
        "reconstructed); shadow rays per pixel %.1f, %.1f; %d shadow-edge pixels, the worst "
        "moved %.3f of the way to the lit side\n",
        100 * f_full, 100 * f_recon, 100 * recon.reconstructed, full.shadow_rays, recon.shadow_rays,
        edge_pixels, worst_edge);
    ASSERT_GT(edge_pixels, kRes);
    EXPECT_EQ(took_lit, 0);
    EXPECT_LT(worst_edge, 0.2);
    EXPECT_GE(f_full, 0.99);
    EXPECT_GE(f_recon, 0.99);
    EXPECT_GT(recon.reconstructed, 0.5);
    EXPECT_LT(recon.shadow_rays, 0.7 * full.shadow_rays);

    // And per channel, the image means agree with the exact sum.
    for (int c = 0; c < 3; ++c) {
        double se = 0, sr = 0;
        for (size_t i = 0; i < e.pixels.size(); ++i) {
            se += e.pixels[i][c];
            sr += recon.image.pixels[i][c];
        }
        EXPECT_NEAR(sr, se, 0.01 * se) << "channel " << c;
    }
}

// Where every block's corners agree (the floor without the wall: one material, no shadow), the
// samples between them cast no shadow rays of their own.
TEST(ReconstructionCuts, CastFewerShadowRaysWhereTheCornersAgree) {
    ReconRun exact = render_with("vpl", false, 0);
    ReconRun full = render_with("lightcuts", false, 0);
    ReconRun recon = render_with("lightcuts", false, 4);
    std::printf(
        "shadow rays per pixel: %.1f (lightcuts), %.1f (reconstruct=4, %.0f%% of "
        "samples reconstructed)\n",
        full.shadow_rays, recon.shadow_rays, 100 * recon.reconstructed);
    // 13 x 13 of the 48 x 48 pixels are sparse samples (7%); every other one reconstructs.
    EXPECT_GT(recon.reconstructed, 0.9);
    EXPECT_LT(recon.shadow_rays, 0.15 * full.shadow_rays);
    EXPECT_GE(fraction_within(recon.image, exact.image, 0.05, 0), 0.99);
}

TEST(ReconstructionCuts, SameImageAtAnyThreadCount) {
    ReconRun one = render_with("lightcuts", true, 4, 1);
    ReconRun two = render_with("lightcuts", true, 4, 2);
    ASSERT_EQ(one.image.pixels.size(), two.image.pixels.size());
    for (size_t i = 0; i < one.image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            ASSERT_EQ(one.image.pixels[i][c], two.image.pixels[i][c]) << "pixel " << i;
}

TEST(ReconstructionCuts, BadSpacingIsAUsageError) {
    RenderOptions opt;
    opt.integrator = "lightcuts";
    opt.spp = 1;
    opt.set["lightcuts.reconstruct"] = "-1";
    EXPECT_THROW(test::render_text(floor_scene(false), opt), UsageError);
}

}  // namespace
}  // namespace ml
