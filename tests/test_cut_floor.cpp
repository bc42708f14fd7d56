// The cuts' error floor (manylight/pilot.h) in `lightcuts` and `mdlightcuts`, against the
// brute-force `vpl` sum over the same point lights.
//
// The scene: 256 point lights over one corner of a floor, and a wall that shadows the rest of it.
// Behind the wall the exact value is 0, so without a floor every cut there is refined to single
// lights (the clusters' bounds take visibility as 1, and no bound is below 0.1 times 0). With the
// floor those cuts stop at a tolerance of the error times the floor times the image's mean, and
// the image does not change where it is lit: the criterion there is the same.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "render_helpers.h"

namespace ml {
namespace {

std::string corner_lights_scene() {
    std::string lights;
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j)
            lights += fmt::format(
                "LightSource \"point\" \"rgb I\" [ 0.02 0.015 0.01 ] \"point3 from\" [ {} 1 {} ]\n",
                -3.5 + i / 15.0, -3.5 + j / 15.0);
    return R"(LookAt 0 9 0  0 0 0  0 0 1
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 24 ] "integer yresolution" [ 24 ]
WorldBegin
)" + lights +
           R"(
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ]
Material "diffuse" "rgb reflectance" [ 0 0 0 ]
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ -2 0 -4  -2 0 4  -2 3 4  -2 3 -4 ]
)";
}

struct FloorRun {
    Image image;
    double avg_cut = 0, floor_luminance = 0;
};

FloorRun render_with(const std::string& integrator, const std::string& floor) {
    RenderOptions opt;
    opt.integrator = integrator;
    opt.spp = 16;
    opt.seed = 7;
    opt.set["vpl.count"] = "0";
    opt.set["lights.direct"] = "points";
    if (integrator != "vpl") {
        opt.set[integrator + ".floor"] = floor;
        opt.set[integrator + ".error"] = "0.05";
    }
    if (integrator == "mdlightcuts") opt.set["mdlightcuts.samples"] = "16";
    RenderOutput out = test::render_text(corner_lights_scene(), opt);
    FloorRun r{out.image};
    if (integrator != "vpl") {
        const nlohmann::json& s = out.figures.integrator_stats.at(integrator);
        r.avg_cut = s.at("avg_cut_size").get<double>();
        r.floor_luminance = s.at("floor_luminance").get<double>();
    }
    return r;
}

class CutFloor : public testing::TestWithParam<const char*> {};

TEST_P(CutFloor, ShrinksTheShadowedCutsAndKeepsTheLitPixels) {
    const std::string integrator = GetParam();
    FloorRun exact = render_with("vpl", "0");
    FloorRun none = render_with(integrator, "0");
    FloorRun floor = render_with(integrator, "1");

    // The pilot's floor is the image's mean luminance, within the pilot's noise.
    double mean = 0;
    for (const RGB& p : exact.image.pixels)
        mean += p.luminance() / double(exact.image.pixels.size());
    EXPECT_EQ(none.floor_luminance, 0.0);
    EXPECT_NEAR(floor.floor_luminance, mean, 0.2 * mean);

    // The shadowed cuts collapse.
    std::printf("%s: average cut %.1f without the floor, %.1f with it\n", integrator.c_str(),
                none.avg_cut, floor.avg_cut);
    EXPECT_LT(floor.avg_cut, 0.5 * none.avg_cut);

    // Pixels well above the floor: as close to the exact sum as without it. Everywhere: within
    // the error of the larger of the pixel and the floor, a few times over (the max criterion
    // bounds each cluster, not the sum, as in the other cut tests), and the image mean as
    // without the floor (the cuts' estimates are unbiased whatever their size).
    size_t lit = 0, lit_within = 0, lit_within_none = 0, within = 0;
    double sum_floor = 0, sum_none = 0;
    const double F = floor.floor_luminance;
    for (size_t i = 0; i < exact.image.pixels.size(); ++i) {
        double e = exact.image.pixels[i].luminance();
        double f = floor.image.pixels[i].luminance(), n = none.image.pixels[i].luminance();
        sum_floor += f, sum_none += n;
        if (std::abs(f - e) <= 0.15 * std::max(e, F)) ++within;
        if (e < 3 * F) continue;
        ++lit;
        if (std::abs(f - e) <= 0.05 * e) ++lit_within;
        if (std::abs(n - e) <= 0.05 * e) ++lit_within_none;
    }
    ASSERT_GT(lit, 30u);
    EXPECT_GE(lit_within, lit_within_none * 95 / 100);
    EXPECT_GE(double(within), 0.98 * double(exact.image.pixels.size()));
    EXPECT_NEAR(sum_floor, sum_none, 0.01 * sum_none);
}

INSTANTIATE_TEST_SUITE_P(ManyLight, CutFloor, testing::Values("lightcuts", "mdlightcuts"));

}  // namespace
}  // namespace ml
