// pbrt-v4's "alpha" on shapes (cut-outs through Embree's filter functions), on
// tests/scenes/alpha_shadow.pbrt: a floor of albedo 0.5 lit from straight above (radiance 0.5
// where unshadowed) under a black occluder. Alpha 0 casts no shadow, alpha 1 a full one, a
// fractional alpha the fraction 1 - alpha of light through, and a checkerboard alpha texture
// the shadow of its squares; the many-light integrators' shadow rays see the same.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "parser_test_helpers.h"
#include "render_helpers.h"

using namespace ml;
using ml::test::channel_stats;
using ml::test::expect_scene_error;

namespace {

std::string scene_text() {
    std::ifstream in(MANYLIGHT_SOURCE_DIR "/tests/scenes/alpha_shadow.pbrt");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// The scene with the occluder's alpha given by `alpha` ("float alpha" 0.3, ...).
std::string with_alpha(const std::string& alpha) {
    std::string text = scene_text();
    size_t a = text.find("\"texture alpha\" \"holes\"");
    EXPECT_NE(a, std::string::npos);
    return text.replace(a, std::string("\"texture alpha\" \"holes\"").size(), alpha);
}

Image render(const std::string& text, const std::string& integrator = "",
             std::optional<std::array<float, 9>> look_at = std::nullopt) {
    RenderOptions opt;
    opt.progress = false;
    opt.integrator = integrator;
    opt.look_at = look_at;
    return render_scene(parse_scene_string(text, ".", "alpha_shadow.pbrt"), opt).image;
}

// Under the checkerboard alpha: the quadrants (-, -) and (+, +) of the floor in view are in
// shadow. The camera's image x runs along world -x, its y along world -y (pbrt-v4's LookAt).
void expect_checker_shadow(const Image& img) {
    ASSERT_EQ(img.width, 32);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            bool wx_neg = x >= 16, wy_neg = y >= 16;
            float expected = wx_neg == wy_neg ? 0.f : 0.5f;
            ASSERT_NEAR(img.at(x, y).g, expected, 2e-3f) << "pixel " << x << "," << y;
        }
}

}  // namespace

TEST(Alpha, ZeroCastsNoShadowAndOneAFullOne) {
    for (const char* integrator : {"path", "lightcuts"}) {
        SCOPED_TRACE(integrator);
        Image open = render(with_alpha("\"float alpha\" [ 0 ]"), integrator);
        Image shut = render(with_alpha("\"float alpha\" [ 1 ]"), integrator);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(channel_stats(open, c).mean, 0.5, 1e-3);
            EXPECT_NEAR(channel_stats(shut, c).mean, 0.0, 1e-6);
        }
    }
}

TEST(Alpha, FractionalAlphaPassesTheRestOfTheLight) {
    // Each shadow ray is blocked with probability 0.3: the mean is 0.5 (1 - 0.3) = 0.35, within
    // the binomial noise of 32 x 32 x 4 independent tests (sd 0.0036), for both integrators.
    for (const char* integrator : {"path", "lightcuts"}) {
        SCOPED_TRACE(integrator);
        Image img = render(with_alpha("\"float alpha\" [ 0.3 ]"), integrator);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(channel_stats(img, c).mean, 0.35, 0.015);
    }
}

TEST(Alpha, TextureAlphaShadowsItsSquares) {
    for (const char* integrator : {"path", "lightcuts", "vpl"}) {
        SCOPED_TRACE(integrator);
        expect_checker_shadow(render(scene_text(), integrator));
    }
}

TEST(Alpha, CameraRaysSeeThroughTheHoles) {
    // From far above (z = 100, rays within 0.3 degrees of vertical) the camera sees [-0.5, 0.5]^2
    // of the black occluder (4 x 4 squares): through each hole (alpha 0), the floor lit through
    // the same hole; black where alpha is 1. Half the image: mean 0.25 (less 0.5% of parallax at
    // the holes' edges).
    std::string text = scene_text();
    const std::string camera =
        "LookAt 0 0 0.25  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 90 ]";
    size_t a = text.find(camera);
    ASSERT_NE(a, std::string::npos);
    text.replace(a, camera.size(),
                 "LookAt 0 0 100  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 0.5757 ]");
    Image img = render(text, "path");
    EXPECT_NEAR(channel_stats(img, 1).mean, 0.25, 5e-3);
    // Pixel (4, 4) lies over world (0.36, 0.36): s = t = 1.4, square (1, 1), even: alpha 1.
    EXPECT_NEAR(img.at(4, 4).g, 0.f, 1e-6f);
    // Pixel (12, 4) over world (0.11, 0.36): square (0, 1), a hole.
    EXPECT_NEAR(img.at(12, 4).g, 0.5f, 2e-3f);
}

TEST(Alpha, BadInputIsReportedAtItsPlace) {
    expect_scene_error("WorldBegin\nShape \"sphere\"\n  \"texture alpha\" \"nope\"\n", 3, 3,
                       "undefined float texture \"nope\"");
    expect_scene_error("WorldBegin\nShape \"sphere\"\n  \"rgb alpha\" [ 0.5 0.5 0.5 ]\n", 3, 3,
                       "expected float");
}
