// pbrt-v4's hair BSDF (Chiang et al. 2016): sampling against its pdf (chi-square), sampling
// weights against f / pdf, the white furnace (no absorption: it scatters everything), and the
// many-light integrators' bound.
#include <gtest/gtest.h>

#include <memory>

#include "chi2.h"
#include "core/rng.h"
#include "integrators/render_job.h"
#include "materials/hair.h"
#include "scene/scene_desc.h"

using namespace ml;

namespace {

Vec3 uniform_sphere(Rng& rng) {
    float z = 1 - 2 * rng.next_float(), phi = 2 * kPi * rng.next_float();
    float r = safe_sqrt(1 - z * z);
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

struct HairCase {
    float h, beta_m, beta_n, alpha;
    RGB sigma_a;
};

const HairCase kCases[] = {
    {0.0f, 0.3f, 0.3f, 2, RGB(0)},         {0.5f, 0.3f, 0.5f, 2, RGB(0.2f, 0.5f, 1.0f)},
    {-0.7f, 0.5f, 0.3f, 0, RGB(0)},        {0.9f, 0.8f, 0.8f, 5, RGB(0.1f)},
    {-0.2f, 0.25f, 0.6f, 2, RGB(1, 1, 1)},
};

}  // namespace

TEST(HairBsdf, SamplesMatchPdf) {
    const Vec3 wos[] = {normalize(Vec3(0.3f, 0.4f, 0.8f)), normalize(Vec3(-0.6f, 0.7f, 0.2f)),
                        normalize(Vec3(0.1f, -0.2f, -0.9f))};
    const double alpha = chi2::sidak_alpha(0.01, int(std::size(kCases) * std::size(wos)));
    uint64_t seed = 1;
    for (const HairCase& c : kCases) {
        HairBxdf bxdf(c.h, 1.55f, c.sigma_a, c.beta_m, c.beta_n, c.alpha);
        for (const Vec3& wo : wos) {
            auto sampler = [&](Rng& rng) -> std::optional<Vec3> {
                float uc = rng.next_float();
                Vec2 u(rng.next_float(), rng.next_float());
                auto s = bxdf.sample(wo, uc, u, TransportMode::Radiance);
                if (!s) return std::nullopt;
                return s->wi;
            };
            auto pdf = [&](const Vec3& wi) {
                return bxdf.pdf_solid_angle(wo, wi, TransportMode::Radiance);
            };
            chi2::Options opt;
            opt.seed = seed++;
            opt.theta_res = 20;
            opt.phi_res = 40;
            opt.sample_count = 100000;
            auto r = chi2::test(sampler, pdf, opt);
            EXPECT_GT(r.p_value, alpha) << "h " << c.h << " beta_m " << c.beta_m << " wo (" << wo.x
                                        << ", " << wo.y << ", " << wo.z << "): " << r.message;
        }
    }
}

TEST(HairBsdf, SampleAgreesWithEvalAndPdf) {
    Rng rng(11);
    for (const HairCase& c : kCases) {
        HairBxdf bxdf(c.h, 1.55f, c.sigma_a, c.beta_m, c.beta_n, c.alpha);
        for (int i = 0; i < 3000; ++i) {
            Vec3 wo = uniform_sphere(rng);
            auto s = bxdf.sample(wo, rng.next_float(), Vec2(rng.next_float(), rng.next_float()),
                                 TransportMode::Radiance);
            if (!s) continue;
            RGB f = bxdf.eval(wo, s->wi, TransportMode::Radiance);
            float pdf = bxdf.pdf_solid_angle(wo, s->wi, TransportMode::Radiance);
            ASSERT_NEAR(s->pdf_solid_angle, pdf, 1e-3f * pdf + 1e-6f);
            for (int ch = 0; ch < 3; ++ch) ASSERT_NEAR(s->f[ch], f[ch], 1e-3f * f[ch] + 1e-6f);
            EXPECT_EQ(s->flags, kBxdfGlossyReflection);
        }
    }
}

// Without absorption the lobes' attenuations sum to one and the lobe choice follows them, so
// every sample's weight f |cos| / pdf is 1 (pbrt-v4's HairSamplingWeights).
TEST(HairBsdf, SamplingWeightsAreOneWithoutAbsorption) {
    Rng rng(3);
    for (float beta_m : {0.1f, 0.3f, 0.7f})
        for (float beta_n : {0.1f, 0.4f, 0.9f}) {
            HairBxdf bxdf(-1 + 2 * rng.next_float(), 1.55f, RGB(0), beta_m, beta_n, 2);
            for (int i = 0; i < 2000; ++i) {
                Vec3 wo = uniform_sphere(rng);
                auto s = bxdf.sample(wo, rng.next_float(), Vec2(rng.next_float(), rng.next_float()),
                                     TransportMode::Radiance);
                if (!s) continue;
                float w = s->f.average() * std::abs(s->wi.z) / s->pdf_solid_angle;
                ASSERT_NEAR(w, 1, 2e-3) << "beta_m " << beta_m << " beta_n " << beta_n;
            }
        }
}

// The white furnace (pbrt-v4's HairWhiteFurnace): with sigma_a = 0 the BSDF integrates to 1
// for every wo, by stratified uniform sampling of the sphere (independent of the BSDF's own
// sampling).
TEST(HairBsdf, WhiteFurnace) {
    Rng rng(5);
    auto albedo = [&](const HairBxdf& bxdf, const Vec3& wo) {
        const int nz = 200, nphi = 400;
        double sum = 0;
        for (int i = 0; i < nz; ++i)
            for (int j = 0; j < nphi; ++j) {
                float z = 1 - 2 * (i + rng.next_float()) / nz;
                float phi = 2 * kPi * (j + rng.next_float()) / nphi;
                float r = safe_sqrt(1 - z * z);
                Vec3 wi(r * std::cos(phi), r * std::sin(phi), z);
                sum += bxdf.eval(wo, wi, TransportMode::Radiance).average() * std::abs(z);
            }
        return sum * 4 * kPi / (nz * nphi);
    };
    for (float beta_m : {0.1f, 0.3f, 0.5f, 0.9f})
        for (float beta_n : {0.1f, 0.5f, 0.9f}) {
            Vec3 wo = uniform_sphere(rng);
            HairBxdf bxdf(-1 + 2 * rng.next_float(), 1.55f, RGB(0), beta_m, beta_n, 2);
            EXPECT_NEAR(albedo(bxdf, wo), 1, 0.02) << "beta_m " << beta_m << " beta_n " << beta_n;
        }
    // Absorption takes its share.
    HairBxdf dark(0.2f, 1.55f, RGB(1.5f), 0.3f, 0.3f, 2);
    EXPECT_LT(albedo(dark, normalize(Vec3(0.2f, 0.5f, 0.7f))), 0.5);
}

// The bound of f |cos| over a cone of directions holds at every direction of the cone.
TEST(HairBsdf, BoundHoldsOverCones) {
    Rng rng(9);
    int checked = 0;
    for (const HairCase& c : kCases) {
        HairBxdf bxdf(c.h, 1.55f, c.sigma_a, c.beta_m, c.beta_n, c.alpha);
        for (int k = 0; k < 300; ++k) {
            Vec3 wo = uniform_sphere(rng);
            DirectionCone cone(uniform_sphere(rng), std::cos(rng.next_float() * kPi * 0.5f));
            if (k % 10 == 0) cone = DirectionCone(uniform_sphere(rng));  // a single direction
            RGB bound = bxdf.max_value_bound(wo, cone);
            for (int i = 0; i < 200; ++i) {
                Vec3 wi = uniform_sphere(rng);
                if (k % 10 == 0) wi = cone.axis;
                if (!cone_contains(cone, wi)) continue;
                RGB v = bxdf.eval(wo, wi, TransportMode::Radiance) * std::abs(wi.z);
                for (int ch = 0; ch < 3; ++ch) ASSERT_LE(v[ch], bound[ch]) << "case h " << c.h;
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 10000);
}

TEST(HairBsdf, SigmaAFromPbrtParameters) {
    RGB s = HairBxdf::sigma_a_from_concentration(1.3f, 0);
    EXPECT_NEAR(s.r, 0.419f * 1.3f, 1e-5);
    EXPECT_NEAR(s.b, 1.37f * 1.3f, 1e-5);
    // A white fibre absorbs nothing; a darker one more.
    RGB w = HairBxdf::sigma_a_from_reflectance(RGB(1, 0.5f, 0.1f), 0.3f);
    EXPECT_EQ(w.r, 0);
    EXPECT_GT(w.b, w.g);
}

// Lightcuts on the hair bundle of tests/scenes/mat_hair.pbrt, every clustered node checked
// against the exact sum over its lights (lightcuts.verify): the hair's bound holds, for the
// gather points on hair and for the glossy VPLs left on it.
TEST(HairBsdf, LightcutsBoundsHoldOnHair) {
    for (const char* glossy : {"bsdf", "diffuse"}) {
        RenderOptions opt;
        opt.integrator = "lightcuts";
        opt.spp = 1;
        opt.width = 48;
        opt.height = 32;
        opt.seed = 3;
        opt.progress = false;
        opt.set["vpl.count"] = "2000";
        // The scene's maxdepth is 1, where no VPLs are made unless asked for.
        opt.set["vpl.max_depth"] = "1";
        opt.set["vpl.glossy"] = glossy;
        opt.set["vpl.clamp"] = "0";
        opt.set["lightcuts.verify"] = "true";
        RenderOutput out =
            render_scene(parse_scene_file(MANYLIGHT_SOURCE_DIR "/tests/scenes/mat_hair.pbrt"), opt);
        const nlohmann::json& json = out.figures.integrator_stats.at("lightcuts");
        std::printf("glossy %s: %s\n", glossy, json.dump().c_str());
        EXPECT_GT(json.at("verify").at("nodes").get<double>(), 1000);
        EXPECT_EQ(json.at("verify").at("violations").get<double>(), 0);
        if (std::string(glossy) == "bsdf") {
            EXPECT_GT(json.at("glossy").get<double>(), 10);
        }
    }
}
