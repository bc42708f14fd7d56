// pbrt-v4's thindielectric and mix materials: the thin sheet's lobes against the closed form of
// its inter-reflections, the mix's hashed choice against its amount, renders against analytic
// radiance through path and many-light integrators, and Lightcuts' bounds (lightcuts.verify) on
// a scene with both. tests/test_pbrt_reference.cpp compares their renders with pbrt-v4's.
#include <gtest/gtest.h>

#include <cmath>

#include "core/scratch.h"
#include "materials/bxdfs.h"
#include "materials/create.h"
#include "materials/materials.h"
#include "parser_test_helpers.h"
#include "render_helpers.h"

using namespace ml;

namespace {

// Unpolarised Fresnel reflectance of a smooth interface, light arriving from the eta = 1 side.
double fresnel(double cos_i, double eta) {
    double sin_t = std::sqrt(std::max(0.0, 1 - cos_i * cos_i)) / eta;
    if (sin_t >= 1) return 1;
    double cos_t = std::sqrt(1 - sin_t * sin_t);
    double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return (rs * rs + rp * rp) / 2;
}

}  // namespace

TEST(ThinDielectric, NormalIncidenceReflectsTwoROverOnePlusR) {
    // Summing the sheet's inter-reflections, R = r + t^2 r / (1 - r^2) = 2r / (1 + r).
    for (float eta : {1.33f, 1.5f, 2.4f}) {
        double r = fresnel(1, eta);
        EXPECT_NEAR(ThinDielectricBxdf(eta).reflectance(1), 2 * r / (1 + r), 1e-6) << eta;
    }
}

TEST(ThinDielectric, LobesAreChosenByTheirWeightsAndCarryWeightOne) {
    const float eta = 1.5f;
    ThinDielectricBxdf bxdf(eta);
    EXPECT_EQ(bxdf.flags(), kBxdfReflection | kBxdfTransmission | kBxdfSpecular);
    for (float cos_o : {0.95f, 0.6f, 0.2f, -0.5f}) {
        SCOPED_TRACE(cos_o);
        float sin_o = std::sqrt(1 - cos_o * cos_o);
        Vec3 wo(sin_o * 0.6f, sin_o * 0.8f, cos_o);
        double r = fresnel(std::abs(cos_o), eta), expected = r + sqr(1 - r) * r / (1 - r * r);
        const int n = 20000;
        int reflected = 0;
        for (int i = 0; i < n; ++i) {
            auto s = bxdf.sample(wo, (i + 0.5f) / n, Vec2(0.3f, 0.7f), TransportMode::Radiance);
            ASSERT_TRUE(s);
            ASSERT_TRUE(s->is_specular());
            // Weight f |cos| / pdf is one for both lobes (each is chosen by its own weight).
            EXPECT_NEAR(s->f.g * std::abs(s->wi.z) / s->pdf_solid_angle, 1.f, 1e-5f);
            if (s->flags & kBxdfReflection) {
                ++reflected;
                EXPECT_NEAR(s->wi.z, wo.z, 1e-6f);
                EXPECT_NEAR(s->wi.x, -wo.x, 1e-6f);
            } else {
                // Straight through, unbent, in both transport modes.
                EXPECT_EQ(s->wi.x, -wo.x);
                EXPECT_EQ(s->wi.z, -wo.z);
                EXPECT_EQ(s->eta, 1.f);
            }
        }
        EXPECT_NEAR(double(reflected) / n, expected, 1e-3);
        // Delta lobes only: nothing to evaluate, no density, no bound towards point lights.
        EXPECT_TRUE(bxdf.eval(wo, Vec3(0, 0, 1), TransportMode::Radiance).is_black());
        EXPECT_EQ(bxdf.pdf_solid_angle(wo, Vec3(0, 0, 1), TransportMode::Radiance), 0.f);
        EXPECT_TRUE(bxdf.max_value_bound(wo, {Vec3(0, 0, 1), 0.f}).is_black());
    }
}

TEST(MixMaterial, ChoosesTheSecondWithProbabilityAmountByPointAndDirection) {
    NamedTextures none;
    ParameterList empty;
    auto a = create_material("diffuse", empty, none, {});
    auto b = create_material("conductor", empty, none, {});
    std::map<std::string, const Material*> named = {{"a", a.get()}, {"b", b.get()}};
    for (double amount : {0.0, 0.3, 0.75, 1.0}) {
        SCOPED_TRACE(amount);
        ParameterList params;
        Param names, amt;
        names.type = "string", names.name = "materials", names.strings = {"a", "b"};
        amt.type = "float", amt.name = "amount", amt.numbers = {amount};
        params.add(names);
        params.add(amt);
        auto mix = create_material("mix", params, none, {}, named);
        const auto& m = dynamic_cast<const MixMaterial&>(*mix);
        SurfaceInteraction si;
        si.ng = si.ns = Vec3(0, 0, 1);
        const int n = 40000;
        int second = 0;
        for (int i = 0; i < n; ++i) {
            si.p = Vec3((i % 200) * 0.013f, (i / 200) * 0.017f, 0.5f);
            si.wo = normalize(Vec3(0.1f * (i % 7), 0.2f, 1));
            const Material* c = m.choose(si);
            ASSERT_TRUE(c == a.get() || c == b.get());
            second += c == b.get();
            ASSERT_EQ(m.choose(si), c);  // the same point and direction, the same choice
        }
        double p = double(second) / n;
        EXPECT_NEAR(p, amount, 4 * std::sqrt(amount * (1 - amount) / n) + 1e-9);
    }
}

TEST(MixMaterial, NeedsTwoDefinedMaterials) {
    ml::test::expect_scene_error(
        "WorldBegin\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
        "Material \"mix\" \"string materials\" [ \"a\" ]\n",
        3, 16, "must name two materials, got 1");
    ml::test::expect_scene_error(
        "WorldBegin\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
        "Material \"mix\" \"string materials\" [ \"a\" \"b\" ]\n",
        3, 16, "undefined named material \"b\"");
}

namespace {

// A quad under a distant light of radiance pi from straight above, seen from above: at max
// depth 1 a diffuse point's radiance is its albedo.
std::string lit_quad(const std::string& material) {
    return ml::test::lit_from_above(
        "LookAt 0 0 3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 30 ]", 16, 16, 16,
        "MakeNamedMaterial \"light\" \"string type\" \"diffuse\"\n"
        "  \"rgb reflectance\" [ 0.8 0.8 0.8 ]\n"
        "MakeNamedMaterial \"dark\" \"string type\" \"diffuse\"\n"
        "  \"rgb reflectance\" [ 0.2 0.2 0.2 ]\n" +
            material +
            "\nShape \"trianglemesh\" \"point3 P\" [ -2 -2 0  2 -2 0  2 2 0  -2 2 0 ]\n"
            "  \"integer indices\" [ 0 1 2  0 2 3 ]");
}

}  // namespace

TEST(MixMaterial, RendersTheBlendOfItsMaterials) {
    // amount 0.25 of albedo 0.2 and 0.75 of 0.8: radiance 0.65 on average over each pixel.
    const std::string scene = lit_quad(
        "Material \"mix\" \"string materials\" [ \"light\" \"dark\" ] "
        "\"float amount\" [ 0.25 ]");
    for (const char* integrator : {"path", "bdpt", "lightcuts", "vpl"}) {
        RenderOptions opt;
        opt.integrator = integrator;
        opt.seed = 2;
        Image img = ml::test::render_text(scene, opt).image;
        ml::test::ChannelStats st = ml::test::channel_stats(img, 1);
        EXPECT_NEAR(st.mean, 0.65, 5 * st.stderr_of_mean + 2e-3) << integrator;
    }
}

// Disabled: path and bdpt agree with each other (0.784 and 0.778) but not with this expectation
// (0.701). pbrt-v4 (5f7a606) renders this very scene at 4096 spp to 0.7826 at max depth 3 (ours
// 0.7827), 0.8081 at 5 and 0.8089 at 20 (ours 0.8084 and 0.8092): the expectation, not the
// transport, misses a term, not found yet. The sheet's reflectance and transmittance alone are
// checked against the Fresnel series above, and its images against pbrt-v4's in
// PbrtReference.ThinDielectricMaterial.
TEST(ThinDielectric, DISABLED_ReflectsAndPassesTheSkyAsItsFresnelSeriesSays) {
    // A thin sheet (eta 1.5) at height 1 over a quad of albedo 0.8, under a uniform sky of
    // radiance 1, seen from straight above through it, at max depth 3. The camera sees the sky
    // reflected, R(0), and through the sheet the quad, which sees the sky through the sheet
    // (its shadow rays stop at the sheet; the distant light adds nothing below it):
    // R(0) + T(0) 0.8 H, with H = 2 int T(theta) cos sin dtheta over the hemisphere and
    // T = 1 - R, R the sheet's reflectance from the Fresnel equations (numerically here).
    const std::string scene = lit_quad(R"(
LightSource "infinite" "rgb L" [ 1 1 1 ]
AttributeBegin
  Material "thindielectric" "float eta" [ 1.5 ]
  Shape "trianglemesh" "point3 P" [ -300 -300 1  300 -300 1  300 300 1  -300 300 1 ] "integer indices" [ 0 1 2  0 2 3 ]
AttributeEnd
NamedMaterial "light"
)");
    auto sheet_r = [](double cos_t) {
        double r = fresnel(cos_t, 1.5);
        return r + (1 - r) * (1 - r) * r / (1 - r * r);
    };
    double h = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        double theta = (i + 0.5) / n * kPi / 2;
        h += 2 * (1 - sheet_r(std::cos(theta))) * std::cos(theta) * std::sin(theta) * kPi / 2 / n;
    }
    const double r0 = sheet_r(1), expected = r0 + (1 - r0) * 0.8 * h;
    for (const char* integrator : {"path", "bdpt"}) {
        RenderOptions opt;
        opt.integrator = integrator;
        opt.max_depth = 3;
        opt.seed = 2;
        Image img = ml::test::render_text(scene, opt).image;
        ml::test::ChannelStats st = ml::test::channel_stats(img, 1);
        // The view is within 21 degrees of the normal, where R stays within 1e-3 of R(0).
        EXPECT_NEAR(st.mean, expected, 5 * st.stderr_of_mean + 3e-3) << integrator;
    }
}

TEST(Lightcuts, BoundsHoldOnThinDielectricAndMixMaterials) {
    // The mixed quad (diffuse and rough metal) under a thin glass sheet, lit by a spot through
    // the sheet: glossy VPLs on the metal, none on the sheet; every clustered node's error
    // within its bound.
    const std::string scene = R"(
LookAt 0 -3 3  0 0 0  0 0 1
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 24 ] "integer yresolution" [ 24 ]
Sampler "independent" "integer pixelsamples" [ 1 ]
Integrator "path" "integer maxdepth" [ 4 ]
WorldBegin
LightSource "spot" "point3 from" [ 0.5 0.5 2.5 ] "point3 to" [ 0 0 0 ] "float coneangle" [ 60 ] "rgb I" [ 20 20 20 ]
MakeNamedMaterial "matte" "string type" "diffuse" "rgb reflectance" [ 0.7 0.7 0.7 ]
MakeNamedMaterial "metal" "string type" "conductor" "rgb reflectance" [ 0.9 0.9 0.9 ] "float roughness" [ 0.2 ]
AttributeBegin
  Material "mix" "string materials" [ "matte" "metal" ] "float amount" [ 0.5 ]
  Shape "trianglemesh" "point3 P" [ -2 -2 0  2 -2 0  2 2 0  -2 2 0 ] "integer indices" [ 0 1 2  0 2 3 ]
  Shape "trianglemesh" "point3 P" [ -2 2 0  2 2 0  2 2 2  -2 2 2 ] "integer indices" [ 0 1 2  0 2 3 ]
AttributeEnd
AttributeBegin
  Material "thindielectric"
  Shape "trianglemesh" "point3 P" [ -1 -1 1.2  1 -1 1.2  1 1 1.2  -1 1 1.2 ] "integer indices" [ 0 1 2  0 2 3 ]
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
    EXPECT_GT(json.at("glossy").get<double>(), 10) << "glossy VPLs on the mix's metal";
}
