// pbrt-v4's coatedconductor and interface materials. The coated conductor: its delta lobe (a
// smooth coat over a mirror) against the closed form of the inter-reflections in the coat, and
// Lightcuts' bounds (lightcuts.verify) with glossy VPLs on it; its sampling is chi-square tested
// with the other Bxdfs (test_bsdf.cpp), its bounds in test_bounds.cpp, its renders against
// pbrt-v4's in test_pbrt_reference.cpp. The interface: invisible, casting no shadow, in every
// kind of integrator.
#include <gtest/gtest.h>

#include <cmath>

#include "materials/bxdfs.h"
#include "materials/fresnel.h"
#include "parser_test_helpers.h"
#include "render_helpers.h"

using namespace ml;

TEST(CoatedConductor, SmoothCoatOverMirrorSumsItsInterReflections) {
    // At incidence theta: the coat reflects F; the rest enters, reaches the mirror (reflectance
    // Fc at the refracted angle), and at each return to the top leaves with 1 - F or goes back
    // down with F, each pass through the layer keeping exp(-thickness / cos_t):
    //   R = F + (1 - F)^2 Fc tr^2 sum_{k<n} (F Fc tr^2)^k.
    const double eta = 1.5, thickness = 0.2;
    for (double deg : {0.0, 30.0, 60.0, 85.0}) {
        for (int visits : {1, 5}) {
            CoatedConductorLayers l;
            l.eta = float(eta);
            l.base_eta = RGB(0.3f, 0.5f, 1.2f);
            l.base_k = RGB(2.f, 3.f, 4.f);
            l.thickness = float(thickness);
            l.base_visits = visits;
            CoatedConductorBxdf bxdf(l);
            ASSERT_EQ(bxdf.flags(), kBxdfSpecularReflection);
            double t = deg * kPi / 180;
            Vec3 wo(float(std::sin(t)), 0, float(std::cos(t)));
            auto s = bxdf.sample(wo, 0.5f, Vec2(0.5f, 0.5f), TransportMode::Radiance);
            ASSERT_TRUE(s);
            EXPECT_NEAR(s->wi.x, -wo.x, 1e-6);
            double f = fr_dielectric(float(std::cos(t)), float(eta));
            double cos_t = std::sqrt(1 - std::sin(t) * std::sin(t) / (eta * eta));
            double tr2 = std::exp(-2 * thickness / cos_t);
            for (int c = 0; c < 3; ++c) {
                double fc = fr_complex(float(cos_t), l.base_eta[c], l.base_k[c]);
                double sum = 0;
                for (int k = 0; k < visits; ++k) sum += std::pow(f * fc * tr2, k);
                double expect = f + (1 - f) * (1 - f) * fc * tr2 * sum;
                EXPECT_NEAR(s->f[c] * std::cos(t), expect, 1e-5 * expect) << deg << " " << c;
            }
        }
    }
}

TEST(CoatedConductor, NeedsOneWayToGiveTheConductor) {
    ml::test::expect_scene_error(
        "WorldBegin\nMaterial \"coatedconductor\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]\n"
        "  \"rgb conductor.eta\" [ 1 1 1 ]\n",
        2, 28, "cannot be given with");
    ml::test::expect_scene_error(
        "WorldBegin\nMaterial \"coatedconductor\" \"rgb albedo\" [ 0.5 0.5 0.5 ]\n", 2, 28,
        "scattering coat");
}

TEST(Lightcuts, BoundsHoldOnCoatedConductors) {
    // A smooth-coated rough metal floor and a rough-coated one behind, lit by a spot: glossy
    // VPLs on both; every clustered node's error within its bound.
    const std::string scene = R"(
LookAt 0 -3 3  0 0 0  0 0 1
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 24 ] "integer yresolution" [ 24 ]
Sampler "independent" "integer pixelsamples" [ 1 ]
Integrator "path" "integer maxdepth" [ 4 ]
WorldBegin
LightSource "spot" "point3 from" [ 0.5 0.5 2.5 ] "point3 to" [ 0 0 0 ] "float coneangle" [ 60 ] "rgb I" [ 20 20 20 ]
AttributeBegin
  Material "coatedconductor" "rgb reflectance" [ 0.9 0.9 0.9 ] "float conductor.roughness" [ 0.1 ]
  Shape "trianglemesh" "point3 P" [ -2 -2 0  2 -2 0  2 2 0  -2 2 0 ] "integer indices" [ 0 1 2  0 2 3 ]
AttributeEnd
AttributeBegin
  Material "coatedconductor" "float interface.roughness" [ 0.05 ] "float conductor.roughness" [ 0.2 ]
  Shape "trianglemesh" "point3 P" [ -2 2 0  2 2 0  2 2 2  -2 2 2 ] "integer indices" [ 0 1 2  0 2 3 ]
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ]
  Shape "trianglemesh" "point3 P" [ -2 -2 0  -2 2 0  -2 2 2  -2 -2 2 ] "integer indices" [ 0 1 2  0 2 3 ]
AttributeEnd
)";
    RenderOptions opt;
    opt.integrator = "lightcuts";
    opt.seed = 3;
    opt.set["vpl.count"] = "2000";
    opt.set["vpl.glossy"] = "bsdf";
    opt.set["vpl.clamp"] = "0";
    opt.set["lightcuts.verify"] = "true";
    RenderOutput out = ml::test::render_text(scene, opt);
    const nlohmann::json& json = out.figures.integrator_stats.at("lightcuts");
    std::printf("%s\n", json.dump().c_str());
    EXPECT_GT(json.at("verify").at("nodes").get<double>(), 1000);
    EXPECT_EQ(json.at("verify").at("violations").get<double>(), 0);
    EXPECT_GT(json.at("glossy").get<double>(), 10) << "glossy VPLs on the coated metal";
}

namespace {

// A diffuse quad of albedo 0.8 under a distant light of radiance pi from straight above, seen
// from above: at max depth 1 (and at any depth: nothing else reflects) its radiance is 0.8.
// Between it and the light, and between it and the camera, shapes of the interface material.
std::string quad_under_interfaces(bool with_interfaces) {
    std::string interfaces = with_interfaces ? R"(
AttributeBegin
  Material "interface"
  Shape "trianglemesh" "point3 P" [ -3 -3 1  3 -3 1  3 3 1  -3 3 1 ] "integer indices" [ 0 1 2  0 2 3 ]
  Translate 0 0 2
  Shape "sphere" "float radius" [ 0.5 ]
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 5 5 5 ]
  Material "interface"
  Translate 0.5 0 1.5
  Shape "sphere" "float radius" [ 0.3 ]
AttributeEnd
)"
                                             : "";
    return ml::test::lit_from_above(
        "LookAt 0 0 3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]", 16, 16, 16,
        "Material \"diffuse\" \"rgb reflectance\" [ 0.8 0.8 0.8 ]\n"
        "Shape \"trianglemesh\" \"point3 P\" [ -2 -2 0  2 -2 0  2 2 0  -2 2 0 ]\n"
        "  \"integer indices\" [ 0 1 2  0 2 3 ]" +
            interfaces);
}

}  // namespace

TEST(InterfaceMaterial, IsInvisibleAndCastsNoShadowInEveryIntegrator) {
    // The sheet and the sphere between the light and the quad, and the emitting sphere (pbrt-v4
    // ignores an area light on an interface shape), change nothing: each integrator renders the
    // same image as without them, pixel for pixel (same seed), and path tracing the quad's 0.8.
    const std::string with = quad_under_interfaces(true), without = quad_under_interfaces(false);
    for (const char* integrator : {"path", "bdpt", "lighttracer", "lightcuts", "vpl"}) {
        RenderOptions opt;
        opt.integrator = integrator;
        opt.seed = 5;
        Image a = ml::test::render_text(with, opt).image;
        Image b = ml::test::render_text(without, opt).image;
        ASSERT_EQ(a.pixels.size(), b.pixels.size());
        for (size_t i = 0; i < a.pixels.size(); ++i)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(a.pixels[i][c], b.pixels[i][c]) << integrator << " pixel " << i;
        if (std::string(integrator) == "path") {
            ml::test::ChannelStats st = ml::test::channel_stats(a, 1);
            EXPECT_NEAR(st.mean, 0.8, 5 * st.stderr_of_mean + 2e-3);
        }
    }
}

TEST(InterfaceMaterial, CannotBeMixed) {
    ml::test::expect_scene_error(
        "WorldBegin\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
        "MakeNamedMaterial \"i\" \"string type\" \"interface\"\n"
        "Material \"mix\" \"string materials\" [ \"a\" \"i\" ]\n",
        4, 16, "cannot be mixed");
}
