// pbrt-v4's orthographic and spherical cameras: their rays against the projections' formulas,
// analytic renders (an orthographic view of a lit quad, the horizon of a spherical view), and
// the integrators that need camera importance refusing them.
#include <gtest/gtest.h>

#include <cmath>

#include "camera/camera.h"
#include "parser_test_helpers.h"
#include "render_helpers.h"

using namespace ml;

namespace {

ParameterList params(std::initializer_list<std::pair<const char*, std::vector<double>>> floats,
                     const char* mapping = nullptr) {
    ParameterList p(FileLoc{"test.pbrt", 3, 1});
    for (const auto& [name, values] : floats) {
        Param q;
        q.type = "float";
        q.name = name;
        q.numbers = values;
        p.add(q);
    }
    if (mapping) {
        Param q;
        q.type = "string";
        q.name = "mapping";
        q.strings = {mapping};
        p.add(q);
    }
    return p;
}

CameraSample film_at(float x, float y, Vec2 lens = Vec2(0.5f, 0.5f)) {
    return {Vec2(x, y), lens, 0};
}

// The scene must fail to render with an InputError at line:column holding `fragment`.
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

void expect_vec(const Vec3& a, const Vec3& b, float tol = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

}  // namespace

TEST(OrthographicCamera, RaysLeaveTheScreenWindowAlongTheView) {
    // Screen window [-4, 4] x [-2, 2] on a 64 x 32 film, camera moved to (1, 2, 3): each ray
    // starts at its window point (x right, y up, top-left pixel at (-4, 2)) and runs along +z.
    PerspectiveCamera cam(params({{"screenwindow", {-4, 4, -2, 2}}}),
                          Transform::translate({1, 2, 3}), 64, 32, "orthographic");
    EXPECT_FALSE(cam.has_importance());
    Ray corner = cam.generate_ray(film_at(0, 0));
    expect_vec(corner.o, Vec3(1 - 4, 2 + 2, 3));
    expect_vec(corner.d, Vec3(0, 0, 1));
    Ray centre = cam.generate_ray(film_at(32, 16));
    expect_vec(centre.o, Vec3(1, 2, 3));
    Ray right = cam.generate_ray(film_at(48, 24));
    expect_vec(right.o, Vec3(1 + 2, 2 - 1, 3));
    expect_vec(right.d, Vec3(0, 0, 1));
}

TEST(OrthographicCamera, DefaultWindowFollowsTheAspectRatio) {
    // Wider than tall: x spans [-aspect, aspect], y [-1, 1] (pbrt-v4's default screen window).
    PerspectiveCamera cam(params({}), Transform(), 40, 20, "orthographic");
    expect_vec(cam.generate_ray(film_at(0, 0)).o, Vec3(-2, 1, 0));
    expect_vec(cam.generate_ray(film_at(40, 20)).o, Vec3(2, -1, 0));
}

TEST(OrthographicCamera, ThinLensRaysMeetAtTheFocalPlaneAsInPbrtV4) {
    // pbrt-v4 starts lens rays at the lens point around the camera's axis (not around the film
    // point) and aims them at the film point's spot on the focal plane.
    PerspectiveCamera cam(params({{"lensradius", {0.5}}, {"focaldistance", {4}}}), Transform(), 32,
                          32, "orthographic");
    for (Vec2 lens : {Vec2(0.1f, 0.2f), Vec2(0.9f, 0.4f), Vec2(0.5f, 0.99f)}) {
        Ray r = cam.generate_ray(film_at(8, 24, lens));
        EXPECT_NEAR(r.o.z, 0, 1e-6f);
        EXPECT_LE(std::hypot(r.o.x, r.o.y), 0.5f + 1e-5f);
        // The film point (8, 24) of [-1, 1]^2 is (-0.5, -0.5); at z = 4 the ray is there.
        float t = 4 / r.d.z;
        EXPECT_NEAR(r.o.x + r.d.x * t, -0.5f, 1e-4f);
        EXPECT_NEAR(r.o.y + r.d.y * t, -0.5f, 1e-4f);
    }
}

TEST(SphericalCamera, EquirectangularRowsAreLatitudesAndColumnsLongitudes) {
    // Camera space: +y up (the top row), the film's u = 1/4 column looks along +z (forward),
    // u = 0 along +x, u = 1/2 along -x (pbrt-v4: theta from +y, phi from +x towards +z).
    PerspectiveCamera cam(params({}, "equirectangular"), Transform(), 64, 32, "spherical");
    EXPECT_FALSE(cam.has_importance());
    expect_vec(cam.generate_ray(film_at(16, 16)).d, Vec3(0, 0, 1));
    expect_vec(cam.generate_ray(film_at(0, 16)).d, Vec3(1, 0, 0));
    expect_vec(cam.generate_ray(film_at(32, 16)).d, Vec3(-1, 0, 0));
    expect_vec(cam.generate_ray(film_at(48, 16)).d, Vec3(0, 0, -1));
    expect_vec(cam.generate_ray(film_at(16, 0)).d, Vec3(0, 1, 0));
    expect_vec(cam.generate_ray(film_at(16, 32)).d, Vec3(0, -1, 0));
    // 45 degrees above the horizon at the quarter row.
    Vec3 d = cam.generate_ray(film_at(16, 8)).d;
    EXPECT_NEAR(d.y, std::sqrt(0.5f), 1e-5f);
    EXPECT_NEAR(d.z, std::sqrt(0.5f), 1e-5f);
    EXPECT_EQ(cam.generate_ray(film_at(16, 8)).o.x, 0.f);
}

TEST(SphericalCamera, EqualAreaPixelsCoverEqualSolidAngles) {
    // The film's centre looks up (+y); every pixel covers the same solid angle, so the share of
    // uniformly spread film points in any region of the sphere is its area over 4 pi: the upper
    // hemisphere (y > 0) a half, the cap y > 1/2 a quarter, the octant x, y, z > 0 an eighth.
    PerspectiveCamera cam(params({}, "equalarea"), Transform(), 64, 64, "spherical");
    expect_vec(cam.generate_ray(film_at(32, 32)).d, Vec3(0, 1, 0));
    const int n = 256;
    int up = 0, cap = 0, octant = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            Vec3 d = cam.generate_ray(film_at((i + 0.5f) * 64.f / n, (j + 0.5f) * 64.f / n)).d;
            ASSERT_NEAR(length(d), 1.f, 1e-5f);
            up += d.y > 0;
            cap += d.y > 0.5f;
            octant += d.x > 0 && d.y > 0 && d.z > 0;
        }
    EXPECT_NEAR(double(up) / (n * n), 0.5, 0.005);
    EXPECT_NEAR(double(cap) / (n * n), 0.25, 0.005);
    EXPECT_NEAR(double(octant) / (n * n), 0.125, 0.005);
}

TEST(SphericalCamera, UnknownMappingIsAnErrorAtItsPlace) {
    expect_render_error(
        "Camera \"spherical\"\n  \"string mapping\" \"cubemap\"\nWorldBegin\n"
        "LightSource \"point\"\nShape \"sphere\"\n",
        2, 3, "unknown spherical camera mapping \"cubemap\"");
}

namespace {

// The quad [-1, 1]^2 of albedo 0.5 lit from above, seen from above by `camera` with the screen
// window [-2, 2]^2 (its Camera line is line 3).
std::string lit_quad(const std::string& camera) {
    return ml::test::lit_from_above(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"" + camera +
            "\" \"float screenwindow\" [ -2 2 -2 2 ]",
        32, 32, 4,
        "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ]\n"
        "  \"integer indices\" [ 0 1 2  0 2 3 ]");
}

}  // namespace

TEST(OrthographicCamera, RendersALitQuadAtItsTrueSize) {
    // The quad [-1, 1]^2 in a window [-2, 2]^2 covers exactly the middle 16 x 16 pixels, at
    // radiance 0.5 (albedo 0.5 under irradiance pi), whatever its distance.
    RenderOptions opt;
    opt.threads = 1;
    Image img = ml::test::render_text(lit_quad("orthographic"), opt).image;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            bool inside = x >= 8 && x < 24 && y >= 8 && y < 24;
            ASSERT_NEAR(img.at(x, y).g, inside ? 0.5f : 0.f, 1e-4f) << x << "," << y;
        }
}

TEST(SphericalCamera, SeesTheFloorBelowTheHorizon) {
    // From above a wide lit floor (albedo 0.5, radiance 0.5), with +z up: the rows below the
    // middle of an equirectangular image see the floor, those above see nothing; an equal-area
    // image sees it on half its area (its mean is 0.25 up to the far floor's edge).
    auto scene = [](const char* mapping, int height) {
        return ml::test::lit_from_above(
            fmt::format(
                "LookAt 0 0 1  1 0 1  0 0 1\nCamera \"spherical\" \"string mapping\" \"{}\"",
                mapping),
            32, height, 16,
            "Material \"diffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
            "Shape \"trianglemesh\"\n"
            "  \"point3 P\" [ -1e4 -1e4 0  1e4 -1e4 0  1e4 1e4 0  -1e4 1e4 0 ]\n"
            "  \"integer indices\" [ 0 1 2  0 2 3 ]");
    };
    RenderOptions opt;
    opt.threads = 1;
    Image eq = ml::test::render_text(scene("equirectangular", 16), opt).image;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) {
            if (y == 8) continue;  // the row below the horizon may miss the floor's far edge
            ASSERT_NEAR(eq.at(x, y).g, y < 8 ? 0.f : 0.5f, 1e-3f) << x << "," << y;
        }
    Image ea = ml::test::render_text(scene("equalarea", 32), opt).image;
    // The pixels across the horizon (a diamond in this mapping) are sampled: 3 standard errors.
    EXPECT_NEAR(ml::test::channel_stats(ea, 1).mean, 0.25, 2e-3);
}

TEST(CameraImportance, LightPathIntegratorsRefuseCamerasWithoutIt) {
    for (const char* camera : {"orthographic", "spherical"})
        for (const char* integrator : {"lighttracer", "bdpt", "mlt", "pssmlt"}) {
            SCOPED_TRACE(std::string(camera) + " " + integrator);
            RenderOptions opt;
            opt.integrator = integrator;
            opt.spp = 1;
            try {
                ml::test::render_text(lit_quad(camera), opt);
                ADD_FAILURE() << "rendered";
            } catch (const InputError& e) {
                EXPECT_EQ(e.loc().line, 3);
                EXPECT_NE(std::string(e.what()).find("camera's importance"), std::string::npos)
                    << e.what();
            }
        }
    // The many-light integrators take them.
    for (const char* integrator : {"lightcuts", "vpl", "bdlightcuts"}) {
        RenderOptions opt;
        opt.integrator = integrator;
        opt.spp = 1;
        EXPECT_NO_THROW(ml::test::render_text(lit_quad("orthographic"), opt)) << integrator;
    }
}

TEST(CylinderShape, SideViewIsLitAsTheCosineAcrossIt) {
    // An orthographic view across a cylinder of radius 0.8 (taller than the view), lit along
    // the view by radiance pi, albedo 0.5: at x the radiance is 0.5 sqrt(1 - (x / 0.8)^2), so the
    // image's mean over the window [-1, 1]^2 is 0.5 (0.8 pi / 2) / 2 and the columns beyond
    // |x| = 0.8 are black.
    const std::string scene = R"(
LookAt 0 -5 0  0 0 0  0 0 1
Camera "orthographic" "float screenwindow" [ -1 1 -1 1 ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 32 ]
Sampler "stratified" "integer xsamples" [ 4 ] "integer ysamples" [ 4 ]
PixelFilter "box"
Integrator "path" "integer maxdepth" [ 1 ]
WorldBegin
LightSource "distant" "point3 from" [ 0 -1 0 ] "point3 to" [ 0 0 0 ] "rgb L" [ 3.14159265 3.14159265 3.14159265 ]
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "cylinder" "float radius" [ 0.8 ] "float zmin" [ -2 ] "float zmax" [ 2 ]
)";
    RenderOptions opt;
    opt.threads = 1;
    Image img = ml::test::render_text(scene, opt).image;
    EXPECT_NEAR(ml::test::channel_stats(img, 1).mean, 0.5 * 0.8 * kPi / 4, 2e-3);
    for (int y = 0; y < 32; ++y)
        for (int x : {0, 1, 2, 29, 30, 31}) ASSERT_EQ(img.at(x, y).g, 0.f) << x << "," << y;
    // Mirror-symmetric columns agree.
    for (int x = 3; x < 16; ++x) EXPECT_NEAR(img.at(x, 16).g, img.at(31 - x, 16).g, 0.02f) << x;
}
