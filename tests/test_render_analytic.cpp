// Analytic scenes through every radiance integrator (DESIGN.md section 4): the white furnace and
// a plane under a point light, with tolerances from the images' own variance.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "render_helpers.h"

using namespace ml;

namespace {

void expect_furnace(const std::string& integrator, int max_depth, float albedo, float Le,
                    double expected) {
    RenderOptions opt;
    opt.integrator = integrator;
    opt.spp = 64;
    opt.max_depth = max_depth;
    opt.seed = 7;
    RenderOutput out = test::render_text(test::furnace_scene(albedo, Le), opt);
    for (int c = 0; c < 3; ++c) {
        test::ChannelStats st = test::channel_stats(out.image, c);
        // 5 standard errors plus the tessellated sphere's tiny geometric error.
        double tol = 5 * st.stderr_of_mean + 2e-3 * expected;
        EXPECT_NEAR(st.mean, expected, tol)
            << integrator << " channel " << c << " stderr " << st.stderr_of_mean;
    }
}

}  // namespace

TEST(RenderFurnace, PathConvergesToGeometricSeries) {
    // Le / (1 - a): every bounce adds a times the last; deep paths, roulette keeps it unbiased.
    expect_furnace("path", 1000, 0.5f, 1.f, 2.0);
    expect_furnace("path", 1000, 0.8f, 0.5f, 2.5);
}

TEST(RenderFurnace, PathHonoursMaxDepth) {
    // Depth d: Le (1 + a + ... + a^d).
    expect_furnace("path", 2, 0.5f, 1.f, 1.75);
    expect_furnace("path", 0, 0.5f, 1.f, 1.0);
}

TEST(RenderFurnace, DirectAddsOneBounce) {
    // Emission seen plus direct light reflected once: Le (1 + a).
    expect_furnace("direct", 5, 0.5f, 1.f, 1.5);
}

TEST(RenderFurnace, WhittedAddsOneBounce) { expect_furnace("whitted", 5, 0.5f, 1.f, 1.5); }

namespace {

// A diffuse plane z = 0 (albedo rho) under a point light of intensity I at height h, seen by
// a camera looking straight down.
constexpr float kRho = 0.6f, kI = 5.f, kH = 2.f;
constexpr int kRes = 32;

std::string plane_scene() {
    return fmt::format(R"(
LookAt 0 0 4  0 0 0  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ {2} ] "integer yresolution" [ {2} ]
Sampler "sobol"
PixelFilter "box"
WorldBegin
LightSource "point" "rgb I" [ {1} {1} {1} ] "point3 from" [ 0.5 0.3 {3} ]
Material "diffuse" "rgb reflectance" [ {0} {0} {0} ]
Shape "trianglemesh" "point3 P" [ -20 -20 0  20 -20 0  20 20 0  -20 20 0 ]
  "integer indices" [ 0 1 2 0 2 3 ]
)",
                       kRho, kI, kRes, kH);
}

// Radiance at the plane point seen through pixel (x, y): rho/pi * I cos / d^2.
double expected_plane_radiance(float x, float y) {
    // The camera at (0,0,4) looks down -z; pbrt's LookAt with up +y puts +x of the image at
    // world -x (left-handed camera looking down).
    float t = std::tan(radians(50.f) / 2);
    float sx = (2 * (x + 0.5f) / kRes - 1) * t;
    float sy = (1 - 2 * (y + 0.5f) / kRes) * t;
    // Direction in camera space (sx, sy, 1); camera right = up x dir = (0,1,0)x(0,0,-1) = (-1,0,0).
    Vec3 d(-sx, sy, -1);
    Vec3 p = Vec3(0, 0, 4) + d * (4.f / 1.f);
    Vec3 light(0.5f, 0.3f, kH);
    Vec3 to = light - p;
    float d2 = length_squared(to);
    float cos = to.z / std::sqrt(d2);
    return kRho / kPi * kI * cos / d2;
}

void expect_plane(const std::string& integrator) {
    RenderOptions opt;
    opt.integrator = integrator;
    opt.spp = 16;
    opt.max_depth = 5;
    RenderOutput out = test::render_text(plane_scene(), opt);
    int bad = 0;
    double worst = 0;
    for (int y = 0; y < kRes; ++y)
        for (int x = 0; x < kRes; ++x) {
            double e = expected_plane_radiance(float(x), float(y));
            double v = out.image.at(x, y).g;
            // The pixel footprint averages a smooth function: second-order error, well under
            // 1% at this resolution; the light is exact (no noise but the footprint's).
            double rel = std::abs(v - e) / e;
            worst = std::max(worst, rel);
            if (rel > 0.01) ++bad;
        }
    EXPECT_EQ(bad, 0) << integrator << ": worst relative error " << worst;
}

}  // namespace

TEST(RenderPointOverPlane, Path) { expect_plane("path"); }
TEST(RenderPointOverPlane, Direct) { expect_plane("direct"); }
TEST(RenderPointOverPlane, Whitted) { expect_plane("whitted"); }

// Light selection and MIS: the path tracer picks one light by power for next-event estimation,
// so the light strategy's density is pmf * pdf, and the BSDF strategy's weight and the light
// strategy's must both use it or their weights no longer sum to one. A rough metal floor
// reflects a dim light while a bright one, 50 times the power, lights it from the side: with
// power sampling the dim light is rarely picked, which is where a weight without the pmf
// counts its reflection almost twice. Power, uniform, tree and all-lights selection must agree.
TEST(RenderLightSelection, PowerUniformTreeAndAllAgreeOnAGlossyFloor) {
    const std::string scene = R"(
LookAt 0 1 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 24 ] "integer yresolution" [ 24 ]
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 1 1 1 ]
  Material "diffuse" "rgb reflectance" [ 0 0 0 ]
  Shape "trianglemesh" "integer indices" [ 0 2 1 0 3 2 ]
    "point3 P" [ -1 0.5 1  1 0.5 1  1 1.5 1.2  -1 1.5 1.2 ]
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 50 50 50 ]
  Material "diffuse" "rgb reflectance" [ 0 0 0 ]
  Shape "trianglemesh" "integer indices" [ 0 2 1 0 3 2 ]
    "point3 P" [ 3 3 -1  3 3 1  3 1 1  3 1 -1 ]
AttributeEnd
AttributeBegin
  Material "conductor" "float roughness" [ 0.15 ] "spectrum eta" "metal-Ag-eta"
    "spectrum k" "metal-Ag-k"
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ]
AttributeEnd
)";
    auto render = [&](const std::string& light_sampler, uint64_t seed) {
        RenderOptions opt;
        opt.integrator = "path";
        opt.spp = 256;
        opt.seed = seed;
        opt.max_depth = 1;
        opt.set["path.lightsampler"] = light_sampler;
        return test::render_text(scene, opt).image;
    };
    Image power = render("power", 1), uniform = render("uniform", 2);
    test::MeanDifference d = test::mean_difference(power, uniform, 1);
    std::printf("power - uniform: %+.5f (mean %.4f, standard error %.5f)\n", d.mean,
                d.reference_mean, d.stderr_of_mean);
    EXPECT_NEAR(d.mean, 0.0, 4 * d.stderr_of_mean);
    // The tree sampler's pmf depends on the shading point: the BSDF strategy's weight must use
    // the pmf at the point the ray left, as next-event estimation there did. Per channel.
    Image tree = render("tree", 3);
    for (int c = 0; c < 3; ++c) {
        test::MeanDifference dt = test::mean_difference(tree, power, c);
        std::printf("tree - power, channel %d: %+.5f (mean %.4f, standard error %.5f)\n", c,
                    dt.mean, dt.reference_mean, dt.stderr_of_mean);
        EXPECT_NEAR(dt.mean, 0.0, 4 * dt.stderr_of_mean) << "channel " << c;
    }
    // Every light at each vertex (pmf 1): the BSDF strategy's weight must use pmf 1 too, or the
    // dim light's reflection counts almost twice again. Per channel.
    Image all = render("all", 4);
    for (int c = 0; c < 3; ++c) {
        test::MeanDifference da = test::mean_difference(all, power, c);
        std::printf("all - power, channel %d: %+.5f (mean %.4f, standard error %.5f)\n", c, da.mean,
                    da.reference_mean, da.stderr_of_mean);
        EXPECT_NEAR(da.mean, 0.0, 4 * da.stderr_of_mean) << "channel " << c;
    }
}

// The kitchen's blinds in miniature: a closed diffuse-transmission sheet 0.27 mm thick, 2.75
// units from the origin (as Mesh110.ply), in front of a large emitter of radiance 1 and seen
// from the other side. Light crosses both of its surfaces, with reflections between them:
// L = T^2 / (1 - R^2) (pbrt-v4's answer); a ray offset that skips the second surface gives T.
TEST(RenderThinSheet, LightCrossesBothSurfacesOfAClosedSheet) {
    const float t = 0.3f, r = 0.3f, z = -2.7485f, half = 1.35e-4f;
    std::string scene = fmt::format(R"(
LookAt 0 0 -1.5  0 0 -3  0 1 0
Camera "perspective" "float fov" [ 10 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ]
Sampler "independent"
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 1 1 1 ] "bool twosided" true
  Material "diffuse" "rgb reflectance" [ 0 0 0 ]
  Shape "trianglemesh" "point3 P" [ -8 -8 -2.76  8 -8 -2.76  8 8 -2.76  -8 8 -2.76 ]
    "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Material "diffusetransmission" "rgb reflectance" [ {0} {0} {0} ]
  "rgb transmittance" [ {1} {1} {1} ]
Shape "trianglemesh" "point3 P" [ -5 -5 {2}  5 -5 {2}  -5 5 {2}  5 5 {2}
                                  -5 -5 {3}  5 -5 {3}  -5 5 {3}  5 5 {3} ]
  "integer indices" [ 0 2 3 0 3 1  4 5 7 4 7 6  0 1 5 0 5 4  2 6 7 2 7 3  0 4 6 0 6 2
                      1 3 7 1 7 5 ]
)",
                                    r, t, z - half, z + half);
    RenderOptions opt;
    opt.integrator = "path";
    opt.spp = 64;
    opt.max_depth = 16;
    opt.seed = 3;
    Image img = test::render_text(scene, opt).image;
    double expected = t * t / (1 - r * r);
    test::ChannelStats st = test::channel_stats(img, 1);
    EXPECT_NEAR(st.mean, expected, 5 * st.stderr_of_mean + 5e-3 * expected)
        << "one surface crossed would give " << t;
}
