// pbrt-v4's "measured" material: the piecewise-linear warps it is built of, its sampling against
// its pdf (chi-square), its Lightcuts bound, damaged files, and the spectra's colour. Its image
// against pbrt-v4's is in tests/test_pbrt_reference.cpp (mat_measured).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "chi2.h"
#include "core/rng.h"
#include "core/spectrum.h"
#include "integrators/render_job.h"
#include "materials/measured.h"
#include "parser_test_helpers.h"
#include "scene/scene_desc.h"

using namespace ml;

namespace {

const std::string kScenes = MANYLIGHT_SOURCE_DIR "/tests/scenes/";

// A density of 5 x 4 values per point of a 3 x 2 parameter lattice.
PiecewiseLinear2D test_warp(bool density) {
    Rng rng(11);
    std::vector<float> v(3 * 2 * 5 * 4);
    for (float& x : v) x = 0.05f + rng.next_float();
    return PiecewiseLinear2D(v, 5, 4, {{0.f, 1.f, 3.f}, {-1.f, 2.f}}, density);
}

}  // namespace

TEST(PiecewiseLinear2D, SampleAndInvertAgree) {
    PiecewiseLinear2D w = test_warp(true);
    Rng rng(3);
    for (int i = 0; i < 20000; ++i) {
        const float params[2] = {-0.5f + 4 * rng.next_float(), -2 + 5 * rng.next_float()};
        const Vec2 u(rng.next_float(), rng.next_float());
        const PiecewiseLinear2D::Point s = w.sample(u, params);
        const PiecewiseLinear2D::Point back = w.invert(s.p, params);
        ASSERT_NEAR(back.p.x, u.x, 2e-4f);
        ASSERT_NEAR(back.p.y, u.y, 2e-4f);
        ASSERT_NEAR(s.pdf, w.eval(s.p, params), 1e-3f * s.pdf);
        ASSERT_NEAR(back.pdf, s.pdf, 1e-3f * s.pdf);
    }
}

// Samples binned on a 10 x 10 grid against the density integrated over each bin, at a parameter
// point between slices (each parameter interpolated).
TEST(PiecewiseLinear2D, DrawsItsDensity) {
    PiecewiseLinear2D w = test_warp(true);
    const float params[2] = {1.7f, 0.4f};
    constexpr int kBins = 10, kSub = 40, kN = 200000;
    std::vector<double> expected(kBins * kBins, 0), seen(kBins * kBins, 0);
    double total = 0;
    for (int by = 0; by < kBins; ++by)
        for (int bx = 0; bx < kBins; ++bx)
            for (int j = 0; j < kSub; ++j)
                for (int i = 0; i < kSub; ++i) {
                    const Vec2 p((bx + (i + 0.5f) / kSub) / kBins,
                                 (by + (j + 0.5f) / kSub) / kBins);
                    const double mass = w.eval(p, params) / double(kBins * kSub * kBins * kSub);
                    expected[by * kBins + bx] += mass;
                    total += mass;
                }
    EXPECT_NEAR(total, 1.0, 1e-3);
    Rng rng(5);
    for (int i = 0; i < kN; ++i) {
        const Vec2 p = w.sample(Vec2(rng.next_float(), rng.next_float()), params).p;
        seen[std::min(kBins - 1, int(p.y * kBins)) * kBins +
             std::min(kBins - 1, int(p.x * kBins))]++;
    }
    double stat = 0;
    for (int b = 0; b < kBins * kBins; ++b) {
        const double e = expected[b] * kN;
        stat += (seen[b] - e) * (seen[b] - e) / e;
    }
    EXPECT_GT(chi2::chi2_survival(stat, kBins * kBins - 1), 0.001) << "statistic " << stat;
}

TEST(PiecewiseLinear2D, PlainTableInterpolates) {
    const std::vector<float> v = {1, 2, 3, 5};  // 2 x 2
    PiecewiseLinear2D t(v, 2, 2, {}, false);
    EXPECT_FLOAT_EQ(t.eval(Vec2(0, 0), {}), 1);
    EXPECT_FLOAT_EQ(t.eval(Vec2(1, 1), {}), 5);
    EXPECT_FLOAT_EQ(t.eval(Vec2(0.5f, 0.5f), {}), 2.75f);
    EXPECT_FLOAT_EQ(t.max_value(), 5);
}

TEST(Spectrum, ReflectanceUnderD65) {
    const RGB white = reflectance_srgb([](double) { return 1.0; });
    EXPECT_NEAR(white.r, 1, 1e-6);
    EXPECT_NEAR(white.g, 1, 1e-6);
    EXPECT_NEAR(white.b, 1, 1e-6);
    const RGB half = reflectance_srgb([](double) { return 0.5; });
    EXPECT_NEAR(half.g, 0.5, 1e-6);
    // Long wavelengths only: red, some green, no blue to speak of.
    const RGB red = reflectance_srgb([](double l) { return l > 600 ? 1.0 : 0.0; });
    EXPECT_GT(red.r, 0.5f);
    EXPECT_LT(red.g, 0.2f);
    EXPECT_LT(std::abs(red.b), 0.05f);
}

namespace {

struct MeasuredCase {
    std::string file;
    std::shared_ptr<const MeasuredBrdf> brdf;
};

std::vector<MeasuredCase> measured_cases() {
    std::vector<MeasuredCase> out;
    for (const char* f : {"mat_measured.bsdf", "measured_aniso.bsdf"})
        out.push_back({f, load_measured_brdf(kScenes + f, FileLoc{"test.pbrt", 1, 1})});
    return out;
}

std::vector<Vec3> measured_wos() {
    std::vector<Vec3> wos;
    for (auto [deg, phi] :
         {std::pair{5.f, 0.7f}, {35.f, 2.f}, {62.f, -1.2f}, {84.f, 0.3f}, {130.f, 2.6f}}) {
        const float t = radians(deg);
        wos.push_back(Vec3(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t)));
    }
    return wos;
}

}  // namespace

TEST(MeasuredBsdf, SamplesMatchPdf) {
    const auto cases = measured_cases();
    const double alpha = chi2::sidak_alpha(0.01, int(cases.size() * measured_wos().size()));
    uint64_t seed = 1;
    for (const MeasuredCase& c : cases) {
        MeasuredBxdf bxdf(c.brdf.get());
        for (Vec3 wo : measured_wos()) {
            auto sampler = [&](Rng& rng) -> std::optional<Vec3> {
                auto s = bxdf.sample(wo, rng.next_float(), Vec2(rng.next_float(), rng.next_float()),
                                     TransportMode::Radiance);
                if (!s || s->pdf_solid_angle == 0) return std::nullopt;
                return s->wi;
            };
            auto pdf = [&](const Vec3& wi) {
                return bxdf.pdf_solid_angle(wo, wi, TransportMode::Radiance);
            };
            chi2::Options opt;
            opt.seed = seed++;
            auto r = chi2::test(sampler, pdf, opt);
            EXPECT_GT(r.p_value, alpha)
                << c.file << " wo=(" << wo.x << ", " << wo.y << ", " << wo.z << "): " << r.message;
        }
    }
}

TEST(MeasuredBsdf, SampleAgreesWithEvalAndPdf) {
    for (const MeasuredCase& c : measured_cases()) {
        MeasuredBxdf bxdf(c.brdf.get());
        Rng rng(17);
        int sampled = 0;
        for (Vec3 wo : measured_wos())
            for (int i = 0; i < 3000; ++i) {
                auto s = bxdf.sample(wo, 0.5f, Vec2(rng.next_float(), rng.next_float()),
                                     TransportMode::Radiance);
                if (!s) continue;
                ++sampled;
                EXPECT_TRUE(same_hemisphere(wo, s->wi));
                const RGB f = bxdf.eval(wo, s->wi, TransportMode::Radiance);
                const float pdf = bxdf.pdf_solid_angle(wo, s->wi, TransportMode::Radiance);
                ASSERT_NEAR(s->pdf_solid_angle, pdf, 2e-3f * pdf + 1e-6f) << c.file;
                for (int ch = 0; ch < 3; ++ch)
                    ASSERT_NEAR(s->f[ch], f[ch], 2e-3f * f[ch] + 1e-6f) << c.file;
            }
        EXPECT_GT(sampled, 12000) << c.file;  // of 15000: grazing wo loses some below
        // Nothing goes through.
        EXPECT_TRUE(bxdf.eval(Vec3(0, 0.6f, 0.8f), Vec3(0, 0.6f, -0.8f), TransportMode::Radiance)
                        .is_black());
    }
}

// max_value_bound is at least f |cos wi| for every wi in random cones (what Lightcuts' error
// bounds rest on); a cone on the other side gets nothing, as the BRDF gives nothing there.
TEST(MeasuredBsdf, BoundHoldsInCones) {
    for (const MeasuredCase& c : measured_cases()) {
        MeasuredBxdf bxdf(c.brdf.get());
        Rng rng(23);
        for (Vec3 wo : measured_wos())
            for (int k = 0; k < 200; ++k) {
                const float z = 1 - 2 * rng.next_float(), phi = 2 * kPi * rng.next_float();
                const float r = safe_sqrt(1 - z * z);
                const DirectionCone cone{Vec3(r * std::cos(phi), r * std::sin(phi), z),
                                         std::cos(0.6f * rng.next_float())};
                const RGB bound = bxdf.max_value_bound(wo, cone);
                for (int i = 0; i < 50; ++i) {
                    const float zz = 1 - 2 * rng.next_float(), pp = 2 * kPi * rng.next_float();
                    const float rr = safe_sqrt(1 - zz * zz);
                    const Vec3 wi(rr * std::cos(pp), rr * std::sin(pp), zz);
                    if (dot(wi, cone.axis) < cone.cos_theta) continue;
                    const RGB v = bxdf.eval(wo, wi, TransportMode::Radiance) * std::abs(wi.z);
                    for (int ch = 0; ch < 3; ++ch) ASSERT_LE(v[ch], bound[ch] * 1.0001f) << c.file;
                }
            }
        const DirectionCone below{Vec3(0, 0, -1), std::cos(0.5f)};
        EXPECT_TRUE(bxdf.max_value_bound(Vec3(0, 0.6f, 0.8f), below).is_black());
    }
}

// A cut, a renamed field, a wrong header: each a clear error at the material's place, never a
// crash (every length of the file's header and tables, and some of its data).
TEST(MeasuredBsdf, DamagedFilesAreErrors) {
    test::ScratchDir dir;
    std::ifstream in(kScenes + "mat_measured.bsdf", std::ios::binary);
    const std::string whole((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const FileLoc loc{"scene.pbrt", 4, 10};
    auto expect_error = [&](const std::string& bytes, const std::string& says) {
        const std::string path = dir.write("bad.bsdf", bytes);
        try {
            load_measured_brdf(path, loc);
            ADD_FAILURE() << "no error for " << bytes.size() << " bytes (" << says << ")";
        } catch (const InputError& e) {
            EXPECT_EQ(e.loc().line, 4);
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
        }
    };
    for (size_t n = 0; n < 700; n += 7) expect_error(whole.substr(0, n), "");
    for (size_t n = 700; n < whole.size(); n += 4099) expect_error(whole.substr(0, n), "");
    std::string renamed = whole;
    renamed.replace(renamed.find("sigma"), 5, "sigmo");
    expect_error(renamed, "no field \"sigma\"");
    std::string header = whole;
    header[0] = 'T';
    expect_error(header, "not a tensor file");
    EXPECT_THROW(load_measured_brdf(dir.file("missing.bsdf"), loc), InputError);
    EXPECT_THROW(load_measured_brdf(dir.path(), loc), InputError);  // a folder
}

// Lightcuts on the measured sphere, every clustered node checked against the exact sum over its
// lights: the bound holds for gather points on the sphere and for the glossy VPLs on it.
TEST(MeasuredBsdf, LightcutsBoundsHold) {
    RenderOptions opt;
    opt.integrator = "lightcuts";
    opt.spp = 1;
    opt.width = 48;
    opt.height = 48;
    opt.seed = 3;
    opt.progress = false;
    opt.set["vpl.count"] = "2000";
    opt.set["vpl.glossy"] = "bsdf";
    opt.set["lightcuts.verify"] = "true";
    RenderOutput out = render_scene(parse_scene_file(kScenes + "mat_measured.pbrt"), opt);
    const nlohmann::json& json = out.figures.integrator_stats.at("lightcuts");
    std::printf("%s\n", json.dump().c_str());
    EXPECT_GT(json.at("verify").at("nodes").get<double>(), 1000);
    EXPECT_EQ(json.at("verify").at("violations").get<double>(), 0);
    EXPECT_GT(json.at("glossy").get<double>(), 10);
}
