// Lights: Monte Carlo irradiance from sample_li against independent estimates, pdf_li against
// sample_li, power() against emitted radiance integrated through sample_le, image environment
// maps by chi-square, the light sampler's pmf, and bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "chi2.h"
#include "core/rng.h"
#include "lights/create.h"
#include "lights/light_sampler.h"
#include "lights/lights.h"
#include "sampling/warps.h"
#include "shared_files.h"
#include "transport/mis.h"

namespace ml {
namespace {

Vec2 next2(Rng& rng) {
    float x = rng.next_float();
    return {x, rng.next_float()};
}

Param num_param(const std::string& type, const std::string& name, std::vector<double> v) {
    Param p;
    p.type = type;
    p.name = name;
    p.numbers = std::move(v);
    return p;
}
Param str_param(const std::string& name, const std::string& v) {
    Param p;
    p.type = "string";
    p.name = name;
    p.strings = {v};
    return p;
}
ParameterList params(std::vector<Param> ps) {
    ParameterList pl;
    for (auto& p : ps) pl.add(std::move(p));
    return pl;
}

// Irradiance at ctx (normal ctx.ng) estimated through sample_li.
RGB irradiance_li(const Light& light, const LightSampleContext& ctx, int n, uint64_t seed = 1) {
    Rng rng(seed);
    RGB sum;
    for (int i = 0; i < n; ++i) {
        auto s = light.sample_li(ctx, next2(rng));
        if (!s || s->pdf_solid_angle == 0) continue;
        float c = dot(s->wi, ctx.ng);
        if (c > 0) sum += s->L * (c / s->pdf_solid_angle);
    }
    return sum / float(n);
}

// Power through sample_le: E[L |cos| / (pdf_pos pdf_dir)] (cos only for area lights).
RGB power_le(const Light& light, int n) {
    Rng rng(5);
    RGB sum;
    for (int i = 0; i < n; ++i) {
        Vec2 u0 = next2(rng), u1 = next2(rng);
        auto s = light.sample_le(u0, u1);
        if (!s || s->pdf_dir == 0 || s->pdf_pos == 0) continue;
        float c = light.type() == LightType::Area ? abs_dot(s->n_light, s->ray.d) : 1.f;
        sum += s->L * (c / (s->pdf_pos * s->pdf_dir));
    }
    return sum / float(n);
}

void expect_rgb_near(const RGB& a, const RGB& b, float rel, const char* what) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a[c], b[c], rel * std::max(1e-6f, std::abs(b[c]))) << what << " channel " << c;
}

TEST(Lights, PointLightIrradianceAndPower) {
    Transform t = Transform::translate({1, 2, 3});
    auto l = create_light(
        "point",
        params({num_param("rgb", "I", {1, 2, 3}), num_param("point3", "from", {0, 0, 1}),
                num_param("float", "scale", {2})}),
        t, "", {});
    LightSampleContext ctx{{1, 2, 0}, {0, 0, 1}, {0, 0, 1}};
    // Light at (1,2,4): straight above at distance 4.
    expect_rgb_near(irradiance_li(*l, ctx, 4), RGB(2, 4, 6) / 16.f, 1e-5f, "point E");
    expect_rgb_near(l->power(), RGB(2, 4, 6) * (4 * kPi), 1e-5f, "point power");
    expect_rgb_near(power_le(*l, 1000), l->power(), 1e-4f, "point power le");
    auto p =
        create_light("point", params({num_param("float", "power", {100})}), Transform(), "", {});
    expect_rgb_near(p->power(), RGB(100), 1e-5f, "point power param");
}

TEST(Lights, SpotLightFalloffAndPower) {
    auto l = create_light(
        "spot",
        params({num_param("float", "coneangle", {40}), num_param("float", "conedeltaangle", {15}),
                num_param("point3", "to", {0, 0, -1})}),
        Transform(), "", {});
    // Inside the full-intensity cone and outside the cone.
    LightSampleContext below{{0, 0, -2}, {0, 0, 1}, {0, 0, 1}};
    expect_rgb_near(irradiance_li(*l, below, 1), RGB(0.25f), 1e-5f, "spot centre");
    LightSampleContext outside{{2, 0, -1}, {-1, 0, 1}, {0, 0, 1}};
    EXPECT_FALSE(l->sample_li(outside, {0.5f, 0.5f}));
    float cs = std::cos(radians(25)), ce = std::cos(radians(40));
    expect_rgb_near(l->power(), RGB(2 * kPi * (1 - 0.5f * (cs + ce))), 1e-5f, "spot power");
    expect_rgb_near(power_le(*l, 200000), l->power(), 0.01f, "spot power le");
    auto p = create_light("spot", params({num_param("float", "power", {10})}), Transform(), "", {});
    expect_rgb_near(p->power(), RGB(10), 1e-4f, "spot power param");
}

TEST(Lights, DistantLightIrradianceAndPower) {
    auto l = create_light(
        "distant",
        params({num_param("rgb", "L", {3, 3, 3}), num_param("point3", "from", {0, 0, 1}),
                num_param("point3", "to", {0, 0, 0})}),
        Transform(), "", {});
    Bounds3 b;
    b.expand({-1, -1, -1});
    b.expand({1, 1, 1});
    l->preprocess(b);
    LightSampleContext ctx{{0, 0, 0}, normalize(Vec3(1, 0, 1)), {0, 0, 1}};
    expect_rgb_near(irradiance_li(*l, ctx, 1), RGB(3 * std::sqrt(0.5f)), 1e-5f, "distant E");
    expect_rgb_near(l->power(), RGB(3 * kPi * 3), 1e-5f, "distant power");  // r^2 = 3
    expect_rgb_near(power_le(*l, 1000), l->power(), 1e-4f, "distant power le");
}

// A unit square at z = 1 split into triangles of unequal area (plus a sliver), facing -z.
TriangleMesh square_mesh() {
    TriangleMesh m;
    m.p = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {0.9f, 0, 1}};
    // Winding chosen so cross(b - a, c - a) points to -z.
    m.indices = {0, 3, 2, 0, 2, 4, 4, 2, 1};
    return m;
}

TEST(Lights, AreaLightIrradianceMatchesQuadrature) {
    TriangleMesh mesh = square_mesh();
    ASSERT_LT(mesh.triangle_normal(0).z, 0.f);
    auto l = create_area_light("diffuse", params({num_param("rgb", "L", {2, 1, 0.5f})}), &mesh, {});
    LightSampleContext ctx{{0.2f, 0.3f, 0}, normalize(Vec3(0.3f, 0, 1)), {0, 0, 1}};
    // Independent estimate: midpoint quadrature of L cos cos' / d^2 over the square.
    const int g = 400;
    double e = 0;
    for (int j = 0; j < g; ++j)
        for (int i = 0; i < g; ++i) {
            Vec3 q((i + 0.5f) / g, (j + 0.5f) / g, 1);
            Vec3 d = q - ctx.p;
            float d2 = length_squared(d);
            Vec3 w = d / std::sqrt(d2);
            e += std::max(0.f, dot(w, ctx.ng)) * w.z / d2 / (g * g);
        }
    expect_rgb_near(irradiance_li(*l, ctx, 400000), RGB(2, 1, 0.5f) * float(e), 0.01f, "area E");
    // pdf_li from the hit point and its normal equals the sample's pdf.
    Rng rng(4);
    for (int i = 0; i < 100; ++i) {
        auto s = l->sample_li(ctx, next2(rng));
        ASSERT_TRUE(s);
        EXPECT_NEAR(l->pdf_li(ctx, s->wi, s->p_light, s->n_light, s->prim), s->pdf_solid_angle,
                    1e-4f * s->pdf_solid_angle);
        expect_rgb_near(l->radiance(s->p_light, s->n_light, {}, -s->wi), s->L, 1e-6f, "L");
    }
    // One-sided: nothing above; two-sided: the same irradiance mirrored.
    LightSampleContext above{{0.2f, 0.3f, 2}, {0, 0, -1}, {0, 0, -1}};
    EXPECT_FALSE(l->sample_li(above, {0.3f, 0.3f}));
    EXPECT_EQ(l->pdf_li(above, {0, 0, -1}, {0.2f, 0.3f, 1}, {0, 0, -1}, 0), 0.f);
    auto two = create_area_light("diffuse",
                                 params({num_param("rgb", "L", {2, 1, 0.5f}),
                                         [] {
                                             Param p;
                                             p.type = "bool";
                                             p.name = "twosided";
                                             p.bools = {true};
                                             return p;
                                         }()}),
                                 &mesh, {});
    LightSampleContext mirrored{{0.2f, 0.3f, 2}, normalize(Vec3(0.3f, 0, -1)), {0, 0, -1}};
    expect_rgb_near(irradiance_li(*two, mirrored, 400000), RGB(2, 1, 0.5f) * float(e), 0.01f,
                    "two-sided E");
    // Power: pi L A, and twice that two-sided, against sample_le.
    expect_rgb_near(l->power(), RGB(2, 1, 0.5f) * kPi, 1e-5f, "area power");
    expect_rgb_near(two->power(), RGB(2, 1, 0.5f) * (2 * kPi), 1e-5f, "two-sided power");
    expect_rgb_near(power_le(*l, 100000), l->power(), 0.01f, "area power le");
    expect_rgb_near(power_le(*two, 100000), two->power(), 0.01f, "two-sided power le");
    // sample_le and pdf_le agree.
    for (int i = 0; i < 100; ++i) {
        auto s = two->sample_le(next2(rng), next2(rng));
        ASSERT_TRUE(s);
        float pp, pd;
        two->pdf_le(s->ray, s->n_light, &pp, &pd);
        EXPECT_NEAR(pp, s->pdf_pos, 1e-5f);
        EXPECT_NEAR(pd, s->pdf_dir, 1e-4f);
    }
    auto p = create_area_light("diffuse", params({num_param("float", "power", {50})}), &mesh, {});
    expect_rgb_near(p->power(), RGB(50), 1e-4f, "area power param");
}

// Irradiance at ctx by MIS of the light's incomplete density (allow_incomplete_pdf) with cosine-
// weighted hemisphere sampling, n samples of each, power heuristic: the path tracer's estimator
// on a white Lambertian receiver (with radiance_escaped standing for the ray's escape).
RGB irradiance_mis_incomplete(const Light& light, LightSampleContext ctx, int n) {
    ctx.allow_incomplete_pdf = true;
    Rng rng(5);
    RGB e;
    for (int i = 0; i < n; ++i) {
        if (auto s = light.sample_li(ctx, next2(rng)); s && s->pdf_solid_angle > 0) {
            float cos = dot(s->wi, ctx.ns);
            if (cos > 0) {
                float w = power_heuristic(s->pdf_solid_angle, cos * kInvPi);
                e += s->L * (cos * w / s->pdf_solid_angle);
            }
        }
        Vec3 local = sample_cosine_hemisphere(next2(rng));
        Frame f = Frame::from_z(ctx.ns);
        Vec3 wi = f.to_world(local);
        float pdf = local.z * kInvPi;
        if (pdf <= 0) continue;
        float w = power_heuristic(pdf, light.pdf_li(ctx, wi, {}, {}, 0));
        e += light.radiance_escaped({ctx.p, wi}) * (local.z * w / pdf);
    }
    return e / float(n);
}

TEST(Lights, UniformInfiniteIrradianceIsPiL) {
    auto l = create_light("infinite", params({num_param("rgb", "L", {0.5f, 1, 2})}), Transform(),
                          "", {});
    Bounds3 b;
    b.expand({0, 0, 0});
    b.expand({2, 0, 0});
    l->preprocess(b);
    LightSampleContext ctx{{0, 0, 0}, normalize(Vec3(1, 1, 1)), {0, 0, 1}};
    expect_rgb_near(irradiance_li(*l, ctx, 200000), RGB(0.5f, 1, 2) * kPi, 0.01f, "env E");
    expect_rgb_near(l->power(), RGB(0.5f, 1, 2) * (4 * kPi * kPi), 1e-5f, "env power");
    expect_rgb_near(power_le(*l, 1000), l->power(), 1e-4f, "env power le");
    auto e = create_light("infinite", params({num_param("float", "illuminance", {10})}),
                          Transform(), "", {});
    expect_rgb_near(irradiance_li(*e, ctx, 200000), RGB(10), 0.01f, "env illuminance");
    // With MIS against the BSDF allowed to be incomplete, a constant sky is left to the BSDF.
    LightSampleContext mis = ctx;
    mis.allow_incomplete_pdf = true;
    EXPECT_FALSE(l->sample_li(mis, {0.3f, 0.7f}));
    EXPECT_EQ(l->pdf_li(mis, Vec3(0, 0, 1), {}, {}, 0), 0.f);
    expect_rgb_near(irradiance_mis_incomplete(*l, ctx, 200000), RGB(0.5f, 1, 2) * kPi, 0.01f,
                    "env E by MIS");
}

// A spiky map: dim everywhere, one small very bright patch, a coloured band.
Image spiky_image(int w, int h, float peak) {
    Image im(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            RGB c(0.02f);
            if (y == h / 3 && x >= w / 4 && x < w / 4 + 2) c = RGB(5, 4, 3) * (peak / 5);
            if (y == 2 * h / 3) c = RGB(0, 0, 1);  // blue only: low luminance, not zero
            im.at(x, y) = c;
        }
    return im;
}

// This process's scratch folder for the images below, removed when the tests end.
std::filesystem::path temp_folder() {
    return std::filesystem::temp_directory_path() /
           ("manylight_test_lights_" + std::to_string(::getpid()));
}
struct RemoveTempFolder : ::testing::Environment {
    void TearDown() override { std::filesystem::remove_all(temp_folder()); }
};
[[maybe_unused]] ::testing::Environment* const kRemoveTempFolder =
    ::testing::AddGlobalTestEnvironment(new RemoveTempFolder);

std::string write_temp(const Image& im, const std::string& name) {
    auto dir = temp_folder();
    std::filesystem::create_directories(dir);
    std::string path = (dir / name).string();
    // Written by hand (little-endian colour PFM, bottom row first) to depend only on reading.
    FILE* f = std::fopen(path.c_str(), "wb");
    EXPECT_TRUE(f);
    std::fprintf(f, "PF\n%d %d\n-1\n", im.width, im.height);
    for (int y = im.height - 1; y >= 0; --y)
        for (int x = 0; x < im.width; ++x) {
            const RGB& c = im.at(x, y);
            float v[3] = {c.r, c.g, c.b};
            std::fwrite(v, sizeof(float), 3, f);
        }
    std::fclose(f);
    return path;
}

void check_image_light(int w, int h, const char* what) {
    Transform rot = Transform::rotate(30, normalize(Vec3(1, 1, 0)));
    // Directions of sample_li against pdf_li, on a smooth map (the quadrature of the expected
    // counts cannot resolve the jumps of a spiky one).
    Image gradient(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            gradient.at(x, y) = RGB(0.5f + float(x) / w + 2 * sqr(float(y) / h), 1, 0.2f);
    std::string mild = write_temp(gradient, std::string("mild_") + what + ".pfm");
    auto lm = create_light("infinite", params({str_param("filename", mild)}), rot, "", {});
    LightSampleContext ctx{{0, 0, 0}, {0, 0, 1}, {0, 0, 1}};
    auto r = chi2::test(
        [&](Rng& rng) -> std::optional<Vec3> {
            auto s = lm->sample_li(ctx, next2(rng));
            if (!s) return std::nullopt;
            return s->wi;
        },
        [&](const Vec3& w) { return double(lm->pdf_li(ctx, w, {}, {}, 0)); },
        {.theta_res = 16, .phi_res = 32, .sample_count = 400000, .quadrature_depth = 5});
    EXPECT_GT(r.p_value, 0.001) << what << ": " << r.message;
    // The compensated density (allow_incomplete_pdf): its samples follow its pdf, it leaves out
    // directions darker than the map's mean, and keeps those brighter.
    LightSampleContext inc = ctx;
    inc.allow_incomplete_pdf = true;
    auto rc = chi2::test(
        [&](Rng& rng) -> std::optional<Vec3> {
            auto s = lm->sample_li(inc, next2(rng));
            if (!s) return std::nullopt;
            return s->wi;
        },
        [&](const Vec3& w) { return double(lm->pdf_li(inc, w, {}, {}, 0)); },
        {.theta_res = 16, .phi_res = 32, .sample_count = 400000, .quadrature_depth = 5});
    EXPECT_GT(rc.p_value, 0.001) << what << " (compensated): " << rc.message;
    {
        // The map's mean luminance over the sphere, by uniform directions.
        Rng rng(3);
        double mean = 0;
        const int nm = 200000;
        for (int i = 0; i < nm; ++i)
            mean += lm->radiance_escaped({ctx.p, sample_uniform_sphere(next2(rng))}).luminance();
        mean /= nm;
        int zero = 0, kept = 0;
        for (int i = 0; i < 4000; ++i) {
            Vec3 w = sample_uniform_sphere(next2(rng));
            float pc = lm->pdf_li(inc, w, {}, {}, 0), pf = lm->pdf_li(ctx, w, {}, {}, 0);
            ASSERT_GT(pf, 0.f) << what;
            (pc == 0 ? zero : kept) += 1;
            double lum = lm->radiance_escaped({ctx.p, w}).luminance();
            if (lum < 0.98 * mean) {
                EXPECT_EQ(pc, 0.f) << what << " lum " << lum << " mean " << mean;
            }
            if (lum > 1.02 * mean) {
                EXPECT_GT(pc, 0.f) << what << " lum " << lum << " mean " << mean;
            }
        }
        EXPECT_GT(zero, 200) << what;
        EXPECT_GT(kept, 200) << what;
    }
    std::string path = write_temp(spiky_image(w, h, 500), std::string("env_") + what + ".pfm");
    auto l = create_light("infinite", params({str_param("filename", path)}), rot, "", {});
    Bounds3 b;
    b.expand({-1, 0, 0});
    b.expand({1, 0, 0});
    l->preprocess(b);
    // pdf_li agrees with the sample, radiance_escaped with L, and L / pdf is nearly constant.
    Rng rng(8);
    double sum = 0, sum2 = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        auto s = l->sample_li(ctx, next2(rng));
        ASSERT_TRUE(s);
        float pdf = l->pdf_li(ctx, s->wi, {}, {}, 0);
        EXPECT_NEAR(pdf, s->pdf_solid_angle, 2e-3f * s->pdf_solid_angle) << what;
        Ray ray{ctx.p, s->wi};
        expect_rgb_near(l->radiance_escaped(ray), s->L, 1e-6f, what);
        double v = s->L.luminance() / s->pdf_solid_angle;
        sum += v;
        sum2 += v * v;
    }
    double mean = sum / n, rel_std = std::sqrt(std::max(0.0, sum2 / n - mean * mean)) / mean;
    EXPECT_LT(rel_std, 0.2) << what;
    // Irradiance against uniform sphere sampling of radiance_escaped.
    RGB e_uniform;
    const int m = 2000000;
    for (int i = 0; i < m; ++i) {
        Vec3 w = sample_uniform_sphere(next2(rng));
        if (w.z > 0) e_uniform += l->radiance_escaped({ctx.p, w}) * (w.z / pdf_uniform_sphere());
    }
    e_uniform = e_uniform / float(m);
    RGB e_li = irradiance_li(*l, ctx, 200000);
    expect_rgb_near(e_li, e_uniform, 0.03f, what);
    // MIS of the compensated density with cosine sampling has the same expectation.
    expect_rgb_near(irradiance_mis_incomplete(*l, ctx, 400000), e_uniform, 0.03f,
                    (std::string(what) + " by MIS, compensated").c_str());
    // Power against sample_le, and pdf_le against sample_le.
    expect_rgb_near(power_le(*l, 200000), l->power(), 0.01f, what);
    auto s = l->sample_le({0.3f, 0.6f}, {0.4f, 0.2f});
    ASSERT_TRUE(s);
    float pp, pd;
    l->pdf_le(s->ray, {}, &pp, &pd);
    EXPECT_NEAR(pd, s->pdf_dir, 1e-3f * pd);
    EXPECT_NEAR(pp, s->pdf_pos, 1e-6f);
}

TEST(Lights, ImageInfiniteEqualArea) { check_image_light(32, 32, "equal-area"); }
TEST(Lights, ImageInfiniteLatLong) { check_image_light(64, 32, "lat-long"); }

TEST(Lights, ImageInfiniteOrientationAndIlluminance) {
    // Equal-area: the image centre is light-space +z; rotated 90 degrees about x it is world -y.
    Image im(8, 8);
    for (RGB& c : im.pixels) c = RGB(1);
    im.at(4, 4) = RGB(7, 0, 0);
    std::string path = write_temp(im, "orient.pfm");
    auto l = create_light("infinite", params({str_param("filename", path)}),
                          Transform::rotate(90, {1, 0, 0}), "", {});
    Vec3 up = normalize(
        Transform::rotate(90, {1, 0, 0}).vector(equal_area_square_to_sphere({4.5f / 8, 4.5f / 8})));
    EXPECT_EQ(l->radiance_escaped({{0, 0, 0}, up}).r, 7.f);
    // "illuminance" scales the map so the +z hemisphere (light space) gives that illuminance.
    Image flat(16, 16);
    for (RGB& c : flat.pixels) c = RGB(3);
    path = write_temp(flat, "flat.pfm");
    auto e = create_light(
        "infinite", params({str_param("filename", path), num_param("float", "illuminance", {5})}),
        Transform(), "", {});
    LightSampleContext ctx{{0, 0, 0}, {0, 0, 1}, {0, 0, 1}};
    expect_rgb_near(irradiance_li(*e, ctx, 200000), RGB(5), 0.02f, "image illuminance");
}

TEST(Lights, SharedSkydomeLoads) {
    std::string path = ml::test::shared_dir() + "/scenes/classroom/textures/Skydome.pfm";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
    auto l = create_light("infinite", params({str_param("filename", "textures/Skydome.pfm")}),
                          Transform(), ml::test::shared_dir() + "/scenes/classroom", {});
    Bounds3 b;
    b.expand({0, 0, 0});
    b.expand({1, 1, 1});
    l->preprocess(b);
    EXPECT_GT(l->power().luminance(), 0.f);
    LightSampleContext ctx{{0, 0, 0}, {0, 0, 1}, {0, 0, 1}};
    Rng rng(1);
    for (int i = 0; i < 1000; ++i) {
        auto s = l->sample_li(ctx, next2(rng));
        ASSERT_TRUE(s);
        EXPECT_TRUE(s->L.is_finite());
        EXPECT_GT(s->pdf_solid_angle, 0.f);
    }
}

TEST(LightSampler, FrequenciesMatchPowerPmf) {
    std::vector<std::unique_ptr<Light>> lights;
    lights.push_back(make_point_light({0, 0, 0}, RGB(1)));
    lights.push_back(make_point_light({0, 0, 0}, RGB(0)));  // emits nothing
    lights.push_back(make_point_light({0, 0, 0}, RGB(0, 0, 5)));
    lights.push_back(make_point_light({0, 0, 0}, RGB(10, 2, 1)));
    for (size_t i = 0; i < lights.size(); ++i) lights[i]->index = int(i);
    LightSampler s("power", lights);
    double total = 0;
    for (auto& l : lights) total += l->power().luminance();
    for (auto& l : lights) EXPECT_NEAR(s.pmf(l.get()), l->power().luminance() / total, 1e-6);
    EXPECT_EQ(s.pmf(lights[1].get()), 0.f);
    EXPECT_GT(s.pmf(lights[2].get()), 0.f);
    const int n = 200000;
    std::vector<double> obs(lights.size(), 0);
    Rng rng(3);
    for (int i = 0; i < n; ++i) {
        auto sl = s.sample(rng.next_float());
        ASSERT_TRUE(sl);
        ASSERT_EQ(sl->light, lights[size_t(sl->index)].get());
        ASSERT_EQ(sl->pmf, s.pmf(sl->index));
        obs[size_t(sl->index)] += 1;
    }
    double stat = 0;
    int used = 0;
    for (size_t i = 0; i < lights.size(); ++i) {
        double e = s.pmf(int(i)) * n;
        if (e == 0) {
            EXPECT_EQ(obs[i], 0);
            continue;
        }
        stat += (obs[i] - e) * (obs[i] - e) / e;
        ++used;
    }
    EXPECT_GT(chi2::chi2_survival(stat, used - 1), 0.001);
    LightSampler u("uniform", lights);
    EXPECT_EQ(u.pmf(lights[1].get()), 0.25f);
    EXPECT_THROW(LightSampler("bvh2", lights), UsageError);
    LightSampler empty("power", std::vector<std::unique_ptr<Light>>{});
    EXPECT_FALSE(empty.sample(0.5f));
}

TEST(Lights, BadInputs) {
    EXPECT_THROW(create_light("infinite", params({str_param("filename", "/nonexistent/sky.exr")}),
                              Transform(), "", {}),
                 InputError);
    EXPECT_THROW(create_light("laser", params({}), Transform(), "", {}), InputError);
    EXPECT_THROW(
        create_light("spot", params({num_param("float", "coneangle", {190})}), Transform(), "", {}),
        InputError);
    EXPECT_THROW(create_light("spot", params({num_param("float", "conedeltaangle", {-1})}),
                              Transform(), "", {}),
                 InputError);
    EXPECT_THROW(
        create_light("point", params({num_param("float", "power", {-3})}), Transform(), "", {}),
        InputError);
    EXPECT_THROW(
        create_light("point", params({num_param("rgb", "I", {1, -1, 1})}), Transform(), "", {}),
        InputError);
    Image odd(30, 20);
    std::string path = write_temp(odd, "odd.pfm");
    EXPECT_THROW(
        create_light("infinite", params({str_param("filename", path)}), Transform(), "", {}),
        InputError);
    EXPECT_THROW(
        create_light("infinite",
                     params({str_param("filename", path), num_param("rgb", "L", {1, 1, 1})}),
                     Transform(), "", {}),
        InputError);
    TriangleMesh mesh = square_mesh();
    EXPECT_THROW(create_area_light("diffuse", params({str_param("filename", "x.png")}), &mesh, {}),
                 InputError);
    EXPECT_THROW(create_area_light("glow", params({}), &mesh, {}), InputError);
}

}  // namespace
}  // namespace ml
