// pbrt-v4's "realistic" camera (src/camera/lens_system.h): its sampled rays against a
// brute-force integral over the whole rear element (the exit-pupil bounds must not cut light
// off), focus, the aperture shapes, its parameters' errors and the integrators that refuse it.
// tests/test_pbrt_reference.cpp compares whole renders with pbrt-v4's.
#include <gtest/gtest.h>

#include <cmath>

#include "camera/camera.h"
#include "camera/lens_system.h"
#include "parser_test_helpers.h"
#include "render_helpers.h"

using namespace ml;

namespace {

const std::string kLens = MANYLIGHT_SOURCE_DIR "/tests/scenes/dgauss_50mm.dat";
const FileLoc kLoc{"test.pbrt", 1, 1};

LensSystem dgauss(float aperture_mm, float focus, ApertureImage aperture = {}) {
    return LensSystem(read_lens_table(kLens, kLoc), aperture_mm, focus, 35.f, 2.f / 3.f,
                      std::move(aperture), kLoc);
}

// The mean of generate()'s weight at film fraction s over n x n stratified pupil samples.
double sampled_mean(const LensSystem& lens, Vec2 s, int n) {
    double sum = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            sum += lens.generate(s, Vec2((i + 0.5f) / n, (j + 0.5f) / n)).weight;
    return sum / (double(n) * n);
}

// The same integral without the pupil bounds: cos^4 / z^2 over every point of a square three
// times the rear element's diameter that lets the ray through (a midpoint rule).
double brute_force(const LensSystem& lens, Vec2 s, float film_w, float film_h, float rear_r,
                   int n) {
    Vec3 p_film(-(s.x - 0.5f) * film_w, (s.y - 0.5f) * film_h, 0);
    double sum = 0;
    const float half = 3 * rear_r, z = lens.rear_z();
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            Vec3 p(-half + 2 * half * (i + 0.5f) / n, -half + 2 * half * (j + 0.5f) / n, z);
            Vec3 d = p - p_film;
            float w = lens.trace_from_film(Ray{p_film, d}, nullptr);
            if (w == 0) continue;
            float c = normalize(d).z;
            sum += w * c * c * c * c / (z * z);
        }
    return sum * sqr(2 * half / n);
}

}  // namespace

TEST(RealisticCamera, SampledWeightsMatchTheIntegralOverTheWholeRearElement) {
    // The film: 35 mm across at 3:2 (36 x 24 minus rounding); the rear element's radius 10 mm.
    const float film_w = 0.035f / std::sqrt(1 + 4.f / 9.f), film_h = film_w * 2 / 3;
    for (float aperture : {4.f, 17.f}) {
        LensSystem lens = dgauss(aperture, 5.f);
        for (Vec2 s : {Vec2(0.5f, 0.5f), Vec2(0.8f, 0.35f), Vec2(0.02f, 0.97f)}) {
            SCOPED_TRACE(fmt::format("aperture {} film {},{}", aperture, s.x, s.y));
            double expected = brute_force(lens, s, film_w, film_h, 0.010f, 800);
            double got = sampled_mean(lens, s, 400);
            ASSERT_GT(expected, 0);
            EXPECT_NEAR(got / expected, 1.0, 0.01) << got << " vs " << expected;
        }
    }
}

TEST(RealisticCamera, ExitPupilBoundsHoldEveryRayThatPasses) {
    LensSystem lens = dgauss(17.f, 5.f);
    // Film points along +x in each band, rays to a fine grid over three rear diameters.
    const float rear_r = 0.010f, z = lens.rear_z();
    const int bands = lens.pupil_bounds_count();
    for (int b = 0; b < bands; b += 7) {
        const PupilBounds& bounds = lens.pupil_bounds(b);
        Vec3 p_film((b + 0.5f) / bands * 0.0175f, 0, 0);
        for (int i = 0; i < 150; ++i)
            for (int j = 0; j < 150; ++j) {
                Vec2 q(-3 * rear_r + 6 * rear_r * (i + 0.5f) / 150,
                       -3 * rear_r + 6 * rear_r * (j + 0.5f) / 150);
                if (lens.trace_from_film(Ray{p_film, Vec3(q.x, q.y, z) - p_film}, nullptr) == 0)
                    continue;
                ASSERT_TRUE(bounds.inside(q)) << "band " << b << " point " << q.x << "," << q.y;
            }
    }
}

TEST(RealisticCamera, FocusesTheFocusDistanceOntoTheFilm) {
    // pbrt-v4 measures the focus distance from the film. Rays from the axial point there,
    // through the front element at up to 3 mm from the axis, meet the film (z = 0) within
    // 10 microns of its centre (a pixel of a 96-pixel image is 300).
    for (float focus : {1.f, 5.f, 100.f}) {
        LensSystem lens = dgauss(8.f, focus);
        const Vec3 src(0, 0, focus);
        double max_r = 0;
        for (int i = 1; i <= 10; ++i) {
            const Vec3 target(0.0003f * i, 0, lens.front_z());
            const Vec3 d = normalize(target - src);
            // Start a centimetre before the lens: float rays from 100 m lose the element.
            Ray out;
            ASSERT_TRUE(lens.trace_from_scene(Ray{target - d * 0.01f, d}, &out))
                << focus << " " << i;
            const float t = -out.o.z / out.d.z;
            max_r = std::max(max_r, double(std::abs(out.at(t).x)));
        }
        EXPECT_LT(max_r, 1e-5) << focus;
    }
}

TEST(RealisticCamera, ApertureShapesPassAsMuchLightAsTheRoundStop) {
    // pbrt-v4 scales each shape's image to the mean pi / 4 of a disk in its square; on the
    // axis the lens passes the same light through each (up to the shape's rasterization).
    const float aperture = 6.f;
    double round = sampled_mean(dgauss(aperture, 5.f), Vec2(0.5f, 0.5f), 300);
    for (const char* name : {"gaussian", "square", "pentagon", "star"}) {
        SCOPED_TRACE(name);
        ApertureImage shape = ApertureImage::builtin(name);
        ASSERT_FALSE(shape.empty());
        double got = sampled_mean(dgauss(aperture, 5.f, shape), Vec2(0.5f, 0.5f), 300);
        EXPECT_NEAR(got / round, 1.0, 0.03);
    }
    // The square passes the middle half of each axis (4 x pi/4 / 4 = pi/4 inside, 0 outside);
    // the star has a point towards -x and a notch towards +x.
    ApertureImage square = ApertureImage::builtin("square");
    EXPECT_NEAR(square.lookup(0.2f, -0.3f), kPi, 1e-4);
    EXPECT_EQ(square.lookup(0.7f, 0.f), 0.f);
    ApertureImage star = ApertureImage::builtin("star");
    EXPECT_GT(star.lookup(-0.9f, 0.f), 0.f);
    EXPECT_EQ(star.lookup(0.9f, 0.f), 0.f);
    EXPECT_GT(star.lookup(0.f, 0.f), 0.f);
    EXPECT_TRUE(ApertureImage::builtin("hexagon").empty());
}

namespace {

std::string realistic_scene(const std::string& camera_params, const std::string& film = "") {
    return ml::test::lit_from_above(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"realistic\" \"string lensfile\" \"" + kLens + "\"" +
            camera_params + "\n" + film,
        24, 16, 1,
        "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -9 -9 0  9 -9 0  9 9 0  -9 9 0 ]\n"
        "  \"integer indices\" [ 0 1 2  0 2 3 ]");
}

void expect_render_error(const std::string& text, int line, int column,
                         const std::string& fragment) {
    ml::test::expect_input_error(
        [&] {
            RenderOptions opt;
            opt.spp = 1;
            opt.progress = false;
            render_scene(parse_scene_string(text, ".", "test.pbrt"), opt);
        },
        "test.pbrt", line, column, fragment);
}

}  // namespace

TEST(RealisticCamera, LitFloorImageIsItsRadianceTimesTheMeanRayWeight) {
    // A lit floor of radiance 0.5 fills the view: each pixel is 0.5 times the mean camera
    // weight over the pupil, which the brute-force integral gives for the centre pixels.
    RenderOptions opt;
    opt.spp = 1024;  // about 0.8% standard error over the 4 centre pixels
    opt.threads = 1;
    Image img =
        ml::test::render_text(realistic_scene(" \"float aperturediameter\" [ 8 ]"), opt).image;
    const float film_w = 0.035f / std::sqrt(1 + 4.f / 9.f), film_h = film_w * 2 / 3;
    LensSystem focused = dgauss(8.f, 10.f);  // the camera's default focus distance
    double centre = 0.5 * brute_force(focused, Vec2(0.5f, 0.5f), film_w, film_h, 0.010f, 800);
    double got = (img.at(11, 7).g + img.at(12, 7).g + img.at(11, 8).g + img.at(12, 8).g) / 4;
    EXPECT_NEAR(got / centre, 1.0, 0.03) << got << " vs " << centre;
    // Dimmer towards the corners (cos^4 and vignetting).
    EXPECT_LT(img.at(0, 0).g, img.at(11, 7).g);
}

TEST(RealisticCamera, ParametersAreCheckedAtTheirPlace) {
    expect_render_error("Camera \"realistic\"\nWorldBegin\n", 1, 1,
                        "\"string lensfile\" is required");
    expect_render_error("Camera \"realistic\" \"string lensfile\" \"" + kLens +
                            "\"\n  \"string aperture\" \"bokeh.png\"\nWorldBegin\n",
                        2, 3, "cannot read image");
    expect_render_error(
        "Camera \"realistic\"\n  \"string lensfile\" \"nonexistent.dat\"\nWorldBegin\n", 2, 3,
        "cannot read the lens file");
    expect_render_error("Camera \"realistic\" \"string lensfile\" \"" + kLens +
                            "\"\n  \"float fov\" [ 45 ]\nWorldBegin\n",
                        2, 3, "fov");
}

TEST(RealisticCamera, LightPathIntegratorsRefuseIt) {
    for (const char* integrator : {"lighttracer", "bdpt", "mlt", "pssmlt"}) {
        SCOPED_TRACE(integrator);
        RenderOptions opt;
        opt.integrator = integrator;
        opt.spp = 1;
        try {
            ml::test::render_text(realistic_scene(""), opt);
            ADD_FAILURE() << "rendered";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("camera's importance"), std::string::npos)
                << e.what();
        }
    }
}

TEST(RealisticCamera, ManyLightIntegratorsAgreeWithPath) {
    // The camera weight reaches every integrator's film: the same lit floor through each.
    RenderOptions opt;
    opt.spp = 16;
    const std::string scene = realistic_scene(" \"float aperturediameter\" [ 8 ]");
    opt.integrator = "path";
    double path = ml::test::channel_stats(ml::test::render_text(scene, opt).image, 1).mean;
    ASSERT_GT(path, 0);
    // Each with its own way to the film (vpl and stochasticlightcuts share direct's,
    // PixelIntegrator::render).
    for (const char* integrator : {"direct", "lightcuts", "mdlightcuts", "bdlightcuts", "igi"}) {
        SCOPED_TRACE(integrator);
        opt.integrator = integrator;
        double m = ml::test::channel_stats(ml::test::render_text(scene, opt).image, 1).mean;
        EXPECT_NEAR(m / path, 1.0, 0.03) << m << " vs " << path;
    }
}
