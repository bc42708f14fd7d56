// pbrt-v4's image-driven lights: goniometric and projection lights (their frames, intensities,
// "power", sample_le by chi-square against pdf_le and power through sample_le) and area lights
// with an image (radiance at the surface's (u, 1 - v), samples carrying their texture
// coordinates); then the many-light integrators on the goniometric and projection reference
// scenes against the path tracer, and Lightcuts' bounds (lightcuts.verify) on all three.
#include <gtest/gtest.h>

#include "chi2.h"
#include "core/rng.h"
#include "lights/create.h"
#include "lights/lights.h"
#include "lights/point_lights.h"
#include "parser_test_helpers.h"
#include "render_helpers.h"
#include "sampling/sampler.h"
#include "sampling/warps.h"

using namespace ml;
using ml::test::ScratchDir;

namespace {

const std::string kScenes = MANYLIGHT_SOURCE_DIR "/tests/scenes/";

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

// Power through sample_le, E[L / (pdf_pos pdf_dir)], for point-like lights.
RGB power_le(const Light& light, int n) {
    Rng rng(5);
    RGB sum;
    for (int i = 0; i < n; ++i) {
        Vec2 u0 = next2(rng), u1 = next2(rng);
        auto s = light.sample_le(u0, u1);
        if (!s || s->pdf_dir == 0 || s->pdf_pos == 0) continue;
        sum += s->L / (s->pdf_pos * s->pdf_dir);
    }
    return sum / float(n);
}

// sample_le's directions against pdf_le, and each sample's L against emitted_intensity and
// sample_li at a point along its ray.
void check_point_like_sampling(const Light& l, const char* what) {
    auto r = chi2::test(
        [&](Rng& rng) -> std::optional<Vec3> {
            auto s = l.sample_le(next2(rng), next2(rng));
            if (!s) return std::nullopt;
            return s->ray.d;
        },
        [&](const Vec3& w) {
            float pp, pd;
            l.pdf_le(Ray{Vec3(), w}, Vec3(), &pp, &pd);
            return double(pd);
        },
        {.theta_res = 24, .phi_res = 48, .sample_count = 400000, .quadrature_depth = 6});
    EXPECT_GT(r.p_value, 0.001) << what << ": " << r.message;
    Rng rng(11);
    for (int i = 0; i < 200; ++i) {
        auto s = l.sample_le(next2(rng), next2(rng));
        ASSERT_TRUE(s) << what;
        float pp, pd;
        l.pdf_le(s->ray, Vec3(), &pp, &pd);
        EXPECT_NEAR(pd, s->pdf_dir, 2e-3f * s->pdf_dir) << what;
        RGB I = l.emitted_intensity(s->ray.d);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(I[c], s->L[c], 1e-4f * (1 + I[c])) << what;
        LightSampleContext ctx{s->ray.o + s->ray.d * 2.f, {}, {}};
        if (auto li = l.sample_li(ctx, {0.5f, 0.5f})) {
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(li->L[c] * 4.f, I[c], 1e-3f * (1 + I[c])) << what;
        }
    }
}

// A smooth, lopsided grey equal-area map brightest near its centre (res x res).
Image smooth_map(int res) {
    Image im(res, res);
    for (int y = 0; y < res; ++y)
        for (int x = 0; x < res; ++x) {
            float u = (float(x) + 0.5f) / float(res), v = (float(y) + 0.5f) / float(res);
            float d2 = sqr(u - 0.5f) + sqr(v - 0.5f);
            im.at(x, y) = RGB(0.2f + 2 * std::exp(-d2 * 8) + 0.5f * u);
        }
    return im;
}

}  // namespace

TEST(ImageLights, GoniometricFramePowerAndSampling) {
    ScratchDir dir;
    write_image(dir.file("g.pfm"), smooth_map(32));
    // Untransformed, the map's centre (its brightest) is the light's +y, pbrt-v4's frame.
    auto l = create_light(
        "goniometric",
        params({str_param("filename", "g.pfm"), num_param("rgb", "I", {1, 0.5, 0.25})}),
        Transform(), dir.path(), {});
    float up = l->emitted_intensity({0, 1, 0}).r;
    float side = l->emitted_intensity({0, 0, 1}).r;
    EXPECT_GT(up, 2.f * side);
    EXPECT_NEAR(up, 0.2f + 2 * std::exp(-8 * 2 * sqr(0.5f / 32)) + 0.5f * (16.5f / 32), 1e-3f);
    RGB I = l->emitted_intensity(normalize(Vec3(0.3f, 0.2f, -0.9f)));
    EXPECT_NEAR(I.g, 0.5f * I.r, 1e-6f);
    // Rotated 90 degrees about x, the light's +y is world +z.
    auto r = create_light("goniometric", params({str_param("filename", "g.pfm")}),
                          Transform::rotate(90, {1, 0, 0}), dir.path(), {});
    EXPECT_NEAR(r->emitted_intensity({0, 0, 1}).r, up, 1e-5f);
    // power() is I times the map's integral; sample_le integrates to it.
    RGB p = l->power();
    RGB q = power_le(*l, 100000);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(q[c], p[c], 1e-3f * p[c]);
    check_point_like_sampling(*r, "goniometric");
    // "power" rescales the emitted flux to the target.
    auto n = create_light(
        "goniometric", params({str_param("filename", "g.pfm"), num_param("float", "power", {100})}),
        Transform(), dir.path(), {});
    EXPECT_NEAR(n->power().r, 100.f, 0.05f);
    EXPECT_THROW(create_light("goniometric", params({}), Transform(), dir.path(), {}), InputError);
    write_image(dir.file("wide.pfm"), Image(8, 4));
    EXPECT_THROW(create_light("goniometric", params({str_param("filename", "wide.pfm")}),
                              Transform(), dir.path(), {}),
                 InputError);
}

TEST(ImageLights, ProjectionFramePowerAndSampling) {
    ScratchDir dir;
    // 6 x 4: red top rows, blue bottom rows, a green column at the left.
    Image im(6, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 6; ++x)
            im.at(x, y) = x == 0 ? RGB(0, 1, 0) : (y < 2 ? RGB(1, 0, 0) : RGB(0, 0, 1));
    write_image(dir.file("s.pfm"), im);
    auto l = create_light("projection",
                          params({str_param("filename", "s.pfm"), num_param("float", "fov", {60}),
                                  num_param("float", "scale", {2})}),
                          Transform(), dir.path(), {});
    // Along +z; the top row is towards +y, the left column towards -x; fov spans the height.
    float t = std::tan(radians(30.f));
    EXPECT_NEAR(l->emitted_intensity(normalize(Vec3(0.1f, 0.5f * t, 1))).r, 2.f, 1e-6f);
    EXPECT_NEAR(l->emitted_intensity(normalize(Vec3(0.1f, -0.5f * t, 1))).b, 2.f, 1e-6f);
    EXPECT_NEAR(l->emitted_intensity(normalize(Vec3(-1.4f * t, 0, 1))).g, 2.f, 1e-6f);
    EXPECT_TRUE(l->emitted_intensity(normalize(Vec3(0, 1.1f * t, 1))).is_black());
    EXPECT_TRUE(l->emitted_intensity(normalize(Vec3(1.6f * t, 0, 1))).is_black());
    EXPECT_TRUE(l->emitted_intensity({0, 0, -1}).is_black());
    // Every bright direction lies in the cone of the point light's bounds.
    {
        Rng rng(3);
        float cos_e = l->bounds()->cos_theta_e;
        for (int i = 0; i < 20000; ++i) {
            Vec3 w = sample_uniform_sphere(next2(rng));
            if (!l->emitted_intensity(w).is_black()) {
                EXPECT_GE(w.z, cos_e - 1e-6f);
            }
        }
    }
    RGB p = l->power();
    RGB q = power_le(*l, 200000);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(q[c], p[c], 0.03f * p[c]) << c;
    check_point_like_sampling(*l, "projection");
    auto n = create_light("projection",
                          params({str_param("filename", "s.pfm"), num_param("float", "fov", {60}),
                                  num_param("float", "power", {10})}),
                          Transform(), dir.path(), {});
    // pbrt-v4's normalisation: the luminance of the power, by pixel centres.
    EXPECT_NEAR(n->power().luminance(), 10.f, 0.05f);
}

TEST(ImageLights, AreaLightImageAtTextureCoordinates) {
    ScratchDir dir;
    // 2 x 2: top-left red, top-right green, bottom-left blue, bottom-right white.
    Image im(2, 2);
    im.at(0, 0) = RGB(1, 0, 0);
    im.at(1, 0) = RGB(0, 1, 0);
    im.at(0, 1) = RGB(0, 0, 1);
    im.at(1, 1) = RGB(1, 1, 1);
    write_image(dir.file("e.pfm"), im);
    TriangleMesh mesh;
    mesh.p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    auto l = create_area_light(
        "diffuse", params({str_param("filename", "e.pfm"), num_param("float", "scale", {3})}),
        &mesh, {}, dir.path());
    Vec3 n(0, 0, 1), w(0, 0, 1);
    // v = 1 is the image's top row: (u, v) near (0, 1) is red, near (0, 0) blue.
    auto near = [](RGB a, RGB b) {
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-5f);
    };
    near(l->radiance({}, n, {0.1f, 0.9f}, w), RGB(3, 0, 0));
    near(l->radiance({}, n, {0.9f, 0.9f}, w), RGB(0, 3, 0));
    near(l->radiance({}, n, {0.1f, 0.1f}, w), RGB(0, 0, 3));
    near(l->radiance({}, n, {0.5f, 0.5f}, w), RGB(1.5f, 1.5f, 1.5f));  // bilinear centre
    EXPECT_TRUE(l->radiance({}, n, {0.5f, 0.5f}, -w).is_black());
    near(l->power(), RGB(1.5f, 1.5f, 1.5f) * kPi);
    // Samples carry the texture coordinates of their point (here uv = p.xy).
    Rng rng(2);
    LightSampleContext ctx{{0.3f, 0.6f, 1}, {0, 0, -1}, {0, 0, -1}};
    for (int i = 0; i < 100; ++i) {
        auto s = l->sample_li(ctx, next2(rng));
        ASSERT_TRUE(s);
        EXPECT_NEAR(s->uv.x, s->p_light.x, 1e-4f);
        EXPECT_NEAR(s->uv.y, s->p_light.y, 1e-4f);
        near(s->L, l->radiance(s->p_light, n, s->uv, -s->wi));
        auto e = l->sample_le(next2(rng), next2(rng));
        ASSERT_TRUE(e);
        EXPECT_NEAR(e->uv.x, e->ray.o.x, 1e-4f);
        EXPECT_NEAR(e->uv.y, e->ray.o.y, 1e-4f);
        near(e->L, l->radiance(e->ray.o, n, e->uv, e->ray.d));
    }
    // The area light's point lights carry the image's radiance at their points.
    std::vector<PointLight> pls;
    auto sampler = create_sampler("independent", 1, 1);
    sampler->start_pixel_sample({0, 0}, 0);
    l->to_point_lights(64, *sampler, pls);
    RGB sum;
    for (const PointLight& pl : pls) sum += pl.intensity;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c] * kPi, l->power()[c], 0.1f * l->power()[c]);
    EXPECT_THROW(
        create_area_light(
            "diffuse", params({str_param("filename", "e.pfm"), num_param("rgb", "L", {1, 1, 1})}),
            &mesh, {}, dir.path()),
        InputError);
}

namespace {

// The scene rendered by `integrator` at depth 2 (the many-light integrators with VPLs from the
// light's sample_le), per channel against the path tracer's: within 4 standard errors and 2%
// (Lightcuts' own error bound).
void expect_agrees_with_path(const std::string& name, const std::string& integrator) {
    SCOPED_TRACE(name + " " + integrator);
    RenderOptions opt;
    opt.progress = false;
    opt.seed = 5;
    opt.max_depth = 2;
    opt.spp = 64;
    RenderOptions path = opt;
    path.integrator = "path";
    Image ref = render_scene(parse_scene_file(kScenes + name + ".pbrt"), path).image;
    opt.integrator = integrator;
    opt.spp = 4;
    opt.set["vpl.count"] = "4000";
    opt.set["vpl.clamp"] = "0";
    Image img = render_scene(parse_scene_file(kScenes + name + ".pbrt"), opt).image;
    for (int c = 0; c < 3; ++c) {
        ml::test::MeanDifference d = ml::test::mean_difference(img, ref, c);
        std::printf("%s %s channel %d: %.5f vs path %.5f (stderr %.5f)\n", name.c_str(),
                    integrator.c_str(), c, d.reference_mean + d.mean, d.reference_mean,
                    d.stderr_of_mean);
        EXPECT_GT(d.reference_mean, 0.001);
        EXPECT_LT(std::abs(d.mean), 4 * d.stderr_of_mean + 0.02 * d.reference_mean);
    }
}

void expect_no_violations(const std::string& name) {
    SCOPED_TRACE(name);
    RenderOptions opt;
    opt.progress = false;
    opt.integrator = "lightcuts";
    opt.seed = 3;
    opt.spp = 1;
    opt.max_depth = 2;
    opt.set["vpl.count"] = "2000";
    opt.set["vpl.clamp"] = "0";
    opt.set["lights.direct"] = "points";
    opt.set["lightcuts.verify"] = "true";
    RenderOutput out = render_scene(parse_scene_file(kScenes + name + ".pbrt"), opt);
    const nlohmann::json& json = out.figures.integrator_stats.at("lightcuts");
    std::printf("%s: %s\n", name.c_str(), json.dump().c_str());
    EXPECT_GT(json.at("verify").at("nodes").get<double>(), 100);
    EXPECT_EQ(json.at("verify").at("violations").get<double>(), 0);
}

}  // namespace

TEST(ImageLightsManyLight, GoniometricLightcutsAndBdlightcutsMatchPath) {
    expect_agrees_with_path("light_goniometric", "lightcuts");
    expect_agrees_with_path("light_goniometric", "bdlightcuts");
}

TEST(ImageLightsManyLight, ProjectionLightcutsAndBdlightcutsMatchPath) {
    expect_agrees_with_path("light_projection", "lightcuts");
    expect_agrees_with_path("light_projection", "bdlightcuts");
}

TEST(ImageLightsManyLight, LightcutsBoundsHoldOnTheImageLightScenes) {
    for (const char* name : {"light_goniometric", "light_projection", "light_area_image"})
        expect_no_violations(name);
}
