// Point lights from every light kind and VPLs from light paths (instant radiosity): power and
// irradiance conserved by the conversion, VPL flux per bounce in a furnace, determinism, bounds,
// and instant radiosity converging to the path tracer.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "integrators/path/path.h"
#include "lights/lights.h"
#include "manylight/point_light_set.h"
#include "manylight/vpl_generator.h"
#include "render/settings.h"
#include "sampling/sampler.h"
#include "sampling/warps.h"
#include "scene/default_scene.h"
#include "scene/scene.h"
#include "transport/direct_lighting.h"
#include "vpl_test_scenes.h"

using namespace ml;
using namespace ml::vpl_test;

namespace {

std::vector<PointLight> convert(const Light& light, int n, uint64_t seed) {
    auto sampler = create_sampler("independent", 1, seed);
    sampler->start_pixel_sample({0, 0}, 0);
    std::vector<PointLight> out;
    light.to_point_lights(n, *sampler, out);
    return out;
}

void expect_rgb_near(const RGB& a, const RGB& b, double rel, const std::string& what) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a[c], b[c], rel * std::max(1e-6f, std::abs(b[c]))) << what << " channel " << c;
}

// Total power of point lights in a scene of bounding-sphere radius r (directional: E pi r^2,
// as distant lights define their power).
RGB emitted_power(const PointLightSet& set, const std::vector<PointLight>& pls, float r) {
    RGB sum;
    for (const PointLight& pl : pls) {
        switch (pl.kind) {
            case PointLightKind::Omni: {
                // The cone by quadrature over directions about the axis.
                if (pl.cos_end <= -1) {
                    sum += pl.intensity * (4 * kPi);
                    break;
                }
                Frame f = Frame::from_z(pl.n);
                const int nc = 4000, np = 16;
                for (int i = 0; i < nc; ++i)
                    for (int j = 0; j < np; ++j) {
                        float c = -1 + 2 * (float(i) + 0.5f) / nc, s = safe_sqrt(1 - c * c);
                        float phi = 2 * kPi * (float(j) + 0.5f) / np;
                        Vec3 w = f.to_world({s * std::cos(phi), s * std::sin(phi), c});
                        sum += point_light_intensity(set, pl, w) * (4 * kPi / (nc * np));
                    }
                break;
            }
            case PointLightKind::Oriented:
                sum += pl.intensity * kPi;
                break;
            case PointLightKind::Directional:
                sum += pl.intensity * (kPi * r * r);
                break;
            case PointLightKind::Glossy:  // made by light paths only, never by emitters
                ADD_FAILURE() << "a glossy VPL among the emitters' point lights";
                break;
        }
    }
    return sum;
}

}  // namespace

TEST(PointLightConversion, ConservesPower) {
    PointLightSet empty;
    Bounds3 b;
    b.expand(Vec3(-1, -2, 0));
    b.expand(Vec3(3, 1, 1));
    Vec3 center;
    float r;
    b.bounding_sphere(&center, &r);

    auto point = make_point_light({1, 2, 3}, RGB(1, 2, 3));
    auto pls = convert(*point, 1, 1);
    ASSERT_EQ(pls.size(), 1u);
    EXPECT_EQ(pls[0].kind, PointLightKind::Omni);
    expect_rgb_near(emitted_power(empty, pls, r), point->power(), 1e-6, "point");

    auto spot = make_spot_light({0, 1, 0}, {1, 1, 0}, RGB(4, 5, 6), std::cos(0.3f), std::cos(0.5f));
    pls = convert(*spot, 1, 1);
    ASSERT_EQ(pls.size(), 1u);
    expect_rgb_near(emitted_power(empty, pls, r), spot->power(), 2e-3, "spot");

    auto distant = make_distant_light({0, 1, 1}, RGB(2, 1, 0.5f));
    distant->preprocess(b);
    pls = convert(*distant, 1, 1);
    ASSERT_EQ(pls.size(), 1u);
    EXPECT_EQ(pls[0].kind, PointLightKind::Directional);
    EXPECT_NEAR(dot(pls[0].n, normalize(Vec3(0, -1, -1))), 1.f, 1e-6f);
    expect_rgb_near(emitted_power(empty, pls, r), distant->power(), 1e-6, "distant");

    for (bool two_sided : {false, true}) {
        auto scene = make_scene(
            fmt::format(fmt::runtime(kQuadLight), two_sided ? "\"bool twosided\" true" : ""));
        const Light& area = *scene->lights().at(0);
        pls = convert(area, 100, 3);
        ASSERT_EQ(pls.size(), two_sided ? 200u : 100u);
        for (const PointLight& pl : pls) {
            EXPECT_EQ(pl.kind, PointLightKind::Oriented);
            EXPECT_NEAR(pl.p.y, 1.f, 1e-6f);
            EXPECT_LE(std::abs(pl.p.x), 0.5f);
        }
        if (!two_sided) {
            EXPECT_NEAR(pls[0].n.y, -1.f, 1e-6f);
        }
        expect_rgb_near(emitted_power(empty, pls, r), area.power(), 1e-5, "area");
    }

    auto uniform = make_uniform_infinite_light(RGB(0.5f, 1, 2));
    uniform->preprocess(b);
    pls = convert(*uniform, 256, 5);
    ASSERT_EQ(pls.size(), 256u);
    expect_rgb_near(emitted_power(empty, pls, r), uniform->power(), 1e-5, "uniform infinite");

    // An environment map with a bright coloured patch over a gradient: importance sampling
    // makes the luminance almost exact, the colour converges statistically.
    Image img(64, 32);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            RGB c(0.2f + 0.01f * float(x), 0.3f, 0.1f + 0.02f * float(y));
            if (x > 40 && x < 46 && y > 8 && y < 12) c = RGB(50, 20, 5);
            img.at(x, y) = c;
        }
    for (EnvMapping m : {EnvMapping::LatLong, EnvMapping::EqualArea}) {
        Image im = img;
        if (m == EnvMapping::EqualArea) {
            im = Image(32, 32);
            for (int y = 0; y < 32; ++y)
                for (int x = 0; x < 32; ++x) im.at(x, y) = img.at(x, y);
        }
        auto env = make_image_infinite_light(im, m, Transform(), 1.5f);
        env->preprocess(b);
        pls = convert(*env, 4096, 7);
        EXPECT_EQ(pls.size(), 4096u);
        expect_rgb_near(emitted_power(empty, pls, r), env->power(), 0.01, "image infinite");
    }
}

TEST(PointLightConversion, AreaIrradianceConverges) {
    auto scene = make_scene(fmt::format(fmt::runtime(kQuadLight), ""));
    const Light& area = *scene->lights().at(0);
    // Receivers below the light, tilted; reference by a dense midpoint rule over the quad.
    const Vec3 xs[] = {{0.3f, 0, 0.2f}, {-0.8f, 0.4f, 0.1f}};
    const Vec3 ns[] = {normalize(Vec3(0, 1, 0)), normalize(Vec3(1, 1, 0))};
    for (int k = 0; k < 2; ++k) {
        Vec3 x = xs[k], nr = ns[k];
        auto irradiance_from = [&](const Vec3& p, const Vec3& nl) {
            Vec3 d = p - x;
            double d2 = length_squared(d);
            Vec3 w = d / float(std::sqrt(d2));
            return std::max(0.f, dot(nr, w)) * std::max(0.f, -dot(nl, w)) / d2;
        };
        const int m = 1000;
        double exact = 0;
        for (int i = 0; i < m; ++i)
            for (int j = 0; j < m; ++j) {
                Vec3 p(-0.5f + (float(i) + 0.5f) / m, 1, -0.5f + (float(j) + 0.5f) / m);
                exact += irradiance_from(p, {0, -1, 0}) / (double(m) * m);  // L = 1, area 1
            }
        double prev_rms = 0;
        for (int n : {16, 256, 4096}) {
            double se = 0;
            const int seeds = 8;
            for (int s = 0; s < seeds; ++s) {
                double e = 0;
                for (const PointLight& pl : convert(area, n, uint64_t(s) + 100)) {
                    Vec3 d = x - pl.p;
                    double d2 = length_squared(d);
                    e += point_light_intensity(PointLightSet(), pl, d / float(std::sqrt(d2))).r *
                         std::max(0.f, dot(nr, -d / float(std::sqrt(d2)))) / d2;
                }
                se += (e - exact) * (e - exact) / seeds;
            }
            double rms = std::sqrt(se) / exact;
            if (n == 4096) {
                EXPECT_LT(rms, 2e-3) << "receiver " << k;
            }
            if (prev_rms > 0) {
                EXPECT_LT(rms, prev_rms / 4) << "receiver " << k << " n " << n;
            }
            prev_rms = rms;
        }
    }
}

namespace {

// Emitted flux of diffuse VPLs: pi times the peak of their cosine lobe.
double diffuse_vpl_flux(const PointLightSet& set) {
    double sum = 0;
    for (const PointLight& pl : set.lights) {
        EXPECT_TRUE(pl.is_vpl);
        EXPECT_EQ(pl.kind, PointLightKind::Oriented);
        EXPECT_LT(pl.surface, 0);
        sum += kPi * pl.intensity.r;
    }
    return sum;
}

}  // namespace

TEST(Vpl, FurnaceFluxPerBounce) {
    // A closed sphere emitting L on both sides with albedo a: the half of its power sent inwards
    // lands on the inside, and bounce k sends on P_in a^k. VPLs with max_depth k hold bounces
    // 1..k, so the difference of two depths isolates one bounce.
    const float a = 0.5f;
    auto scene = make_scene(fmt::format(R"(
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 1 1 1 ] "bool twosided" true
  Material "diffuse" "rgb reflectance" [ {0} {0} {0} ]
  Shape "sphere" "float radius" [ 3 ]
AttributeEnd
)",
                                        a));
    double p_in = 0.5 * double(scene->lights().at(0)->power().r);
    double prev = 0;
    for (int k = 1; k <= 3; ++k) {
        PointLightSet set = vpls_only(*scene, 100000, k, 11);
        EXPECT_GE(set.vpls, 100000u);
        EXPECT_EQ(set.lights.size(), set.vpls);
        double total = diffuse_vpl_flux(set);
        double bounce = total - prev;
        // About 1/sqrt(paths) relative noise on each total (which paths go inwards).
        double tol = 4 * p_in * a * (1 + k) / std::sqrt(double(set.light_paths));
        EXPECT_NEAR(bounce, p_in * std::pow(a, k), tol) << "bounce " << k;
        prev = total;
    }
}

TEST(Vpl, DeterministicAndThreadIndependent) {
    auto scene = make_scene(mixed_box());
    auto build = [&](int threads, uint64_t seed) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        return vpls_only(*scene, 15000, 5, seed);
    };
    PointLightSet a = build(1, 3), b = build(4, 3), c = build(2, 4);
    ASSERT_EQ(a.lights.size(), b.lights.size());
    ASSERT_EQ(a.surfaces.size(), b.surfaces.size());
    EXPECT_EQ(a.light_paths, b.light_paths);
    for (size_t i = 0; i < a.lights.size(); ++i) {
        const PointLight &x = a.lights[i], &y = b.lights[i];
        ASSERT_TRUE(x.p == y.p && x.n == y.n && x.kind == y.kind && x.surface == y.surface &&
                    x.intensity.r == y.intensity.r && x.intensity.b == y.intensity.b)
            << "VPL " << i;
    }
    for (size_t i = 0; i < a.surfaces.size(); ++i) {
        EXPECT_TRUE(a.surfaces[i].wi == b.surfaces[i].wi);
        EXPECT_EQ(a.surfaces[i].flux.g, b.surfaces[i].flux.g);
    }
    bool differs = a.lights.size() != c.lights.size() || !(a.lights[0].p == c.lights[0].p);
    EXPECT_TRUE(differs) << "another seed gives another set";
}

TEST(Vpl, IntensityWithinBound) {
    auto scene = make_scene(mixed_box());
    PointLightSet set = vpls_only(*scene, 20000, 5, 5);
    EXPECT_GE(set.vpls, 20000u);
    EXPECT_EQ(set.oriented + set.omni + set.glossy, set.vpls);
    EXPECT_GT(set.surfaces.size(), 0u);
    auto sampler = create_sampler("independent", 1, 9);
    size_t violations = 0, checked = 0, omni = 0, glossy = 0, sharp = 0;
    for (size_t i = 0; i < set.lights.size(); ++i) {
        const PointLight& pl = set.lights[i];
        if (pl.kind == PointLightKind::Omni) ++omni;
        if (pl.kind == PointLightKind::Glossy) {
            ++glossy;
            sharp += falloff_value(pl.falloff[kFalloffBins - 1]) < 0.05f;
        }
        sampler->start_pixel_sample({int(i), 0}, 0);
        for (int j = 0; j < 96; ++j) {
            Vec3 w = sample_uniform_sphere(sampler->get_2d());
            if (pl.kind == PointLightKind::Glossy && j % 2) {
                // Glossy lobes are narrow: half the directions within 30 degrees of the axis.
                Vec2 u = sampler->get_2d();
                float cos_t = 1 - u.x * (1 - std::cos(0.52f)), sin_t = safe_sqrt(1 - cos_t * cos_t);
                Frame f = Frame::from_z(pl.n);
                w = f.to_world(
                    {sin_t * std::cos(2 * kPi * u.y), sin_t * std::sin(2 * kPi * u.y), cos_t});
            }
            RGB I = point_light_intensity(set, pl, w);
            // Oriented: the cosine lobe; glossy: the falloff away from the axis.
            float cos_w = pl.kind == PointLightKind::Oriented ? std::max(0.f, dot(pl.n, w))
                          : pl.kind == PointLightKind::Glossy
                              ? falloff_bound(pl.falloff, dot(pl.n, w))
                              : 1.f;
            for (int c = 0; c < 3; ++c) {
                ASSERT_TRUE(std::isfinite(I[c]) && I[c] >= 0) << "VPL " << i;
                if (I[c] > pl.intensity[c] * cos_w * (1 + 1e-4f) + 1e-12f) {
                    if (violations < 10)
                        ADD_FAILURE()
                            << "VPL " << i << " kind " << int(pl.kind) << " flags "
                            << int(set.surfaces[size_t(pl.surface)].bsdf.flags()) << " at y "
                            << pl.p.y << ": " << I[c] << " > " << pl.intensity[c] << " * " << cos_w;
                    ++violations;
                }
                ++checked;
            }
        }
    }
    EXPECT_GT(omni, 0u) << "the dielectric pane holds omni VPLs";
    EXPECT_GT(glossy, 1000u) << "the conductor floor and the coated wall hold glossy VPLs";
    EXPECT_GT(sharp, glossy / 4) << "the falloff bounds the conductor's lobes well below the peak";
    EXPECT_EQ(violations, 0u) << "of " << checked;
}

namespace {

struct Estimate {
    double mean = 0, stderr_of_mean = 0;
};

// The surface point of the scene at x (normal n), found by a ray from just off it.
SurfaceInteraction receiver_at(const Scene& scene, const Vec3& x, const Vec3& n) {
    SurfaceInteraction si;
    EXPECT_TRUE(scene.intersect(Ray{x + n * 1.f, -n}, &si));
    EXPECT_LT(distance(si.p, x), 1e-2f);
    return si;
}

// Indirect irradiance (red channel) at si from the VPLs, with shadow rays; the standard error by
// batch means over consecutive VPLs (consecutive light paths, nearly independent).
Estimate vpl_irradiance(const Scene& scene, const PointLightSet& set, const SurfaceInteraction& si,
                        const Vec3& n) {
    const size_t batches = 50;
    std::vector<double> sums(batches, 0.0);
    for (size_t i = 0; i < set.lights.size(); ++i) {
        const PointLight& pl = set.lights[i];
        Vec3 d = pl.p - si.p;
        float d2 = length_squared(d);
        if (d2 == 0) continue;
        Vec3 w = d / std::sqrt(d2);
        float cos_r = dot(n, w);
        if (cos_r <= 0) continue;
        float I = point_light_intensity(set, pl, -w).r;
        if (I <= 0 || !scene.visible(si, pl.p, pl.offset)) continue;
        sums[i * batches / set.lights.size()] += double(I * cos_r / d2);
    }
    Estimate e;
    double s2 = 0;
    for (double s : sums) {
        e.mean += s;
        s2 += s * s;
    }
    double var_batch = (s2 - e.mean * e.mean / batches) / (batches - 1);
    e.stderr_of_mean = std::sqrt(var_batch * batches);
    return e;
}

// Independent reference: cosine-weighted directions from si, the path tracer's radiance along
// them less the emission found at the first hit; pi times the mean.
Estimate path_irradiance(const Scene& scene, const SurfaceInteraction& si, const Vec3& n,
                         int max_depth, int samples) {
    PathIntegrator path(Settings("path", nullptr, {{"path.maxdepth", std::to_string(max_depth)}}));
    path.prepare(scene);
    const int blocks = 64;
    std::vector<double> s(blocks), s2(blocks);
    tbb::parallel_for(0, blocks, [&](int b) {
        auto sampler = create_sampler("independent", 1, 77);
        ScratchBuffer scratch;
        Frame f = Frame::from_z(n);
        for (int i = b; i < samples; i += blocks) {
            sampler->start_pixel_sample({i, 1}, 0);
            Vec3 w = f.to_world(sample_cosine_hemisphere(sampler->get_2d()));
            Ray ray = spawn_ray(si, w);
            double v = path.li(ray, scene, *sampler, scratch, Point2i{0, 0}).r;
            scratch.reset();
            SurfaceInteraction hit;
            if (scene.intersect(ray, &hit) && hit.area_light)
                v -= hit.area_light->radiance(hit.p, hit.ng, hit.uv, hit.wo).r;
            s[size_t(b)] += kPi * v;
            s2[size_t(b)] += kPi * kPi * v * v;
        }
    });
    double sum = 0, sum2 = 0;
    for (int b = 0; b < blocks; ++b) {
        sum += s[size_t(b)];
        sum2 += s2[size_t(b)];
    }
    Estimate e;
    e.mean = sum / samples;
    e.stderr_of_mean = std::sqrt(std::max(0.0, sum2 / samples - e.mean * e.mean) / samples);
    return e;
}

}  // namespace

TEST(Vpl, InstantRadiosityConvergesToPathTracer) {
    // The built-in Cornell box; receivers on the floor, back wall, green wall and ceiling, away
    // from corners (the VPL sum's variance grows near them without clamping).
    Scene scene(parse_scene_string(default_scene_text(), "."));
    const int depth = 3;
    struct Receiver {
        Vec3 x, n;
    };
    const Receiver receivers[] = {{{150, 0, 450}, {0, 1, 0}},
                                  {{450, 0, 120}, {0, 1, 0}},
                                  {{278, 400, 559.2f}, {0, 0, -1}},
                                  {{0, 300, 300}, {1, 0, 0}},
                                  {{120, 548.8f, 120}, {0, -1, 0}}};
    std::vector<PointLightSet> sets;
    for (int count : {1000, 10000, 100000}) sets.push_back(vpls_only(scene, count, depth, 21));
    for (const Receiver& r : receivers) {
        SurfaceInteraction si = receiver_at(scene, r.x, r.n);
        Estimate ref = path_irradiance(scene, si, r.n, depth, 100000);
        double prev_se = 0;
        for (const PointLightSet& set : sets) {
            Estimate v = vpl_irradiance(scene, set, si, r.n);
            double se = std::sqrt(v.stderr_of_mean * v.stderr_of_mean +
                                  ref.stderr_of_mean * ref.stderr_of_mean);
            EXPECT_NEAR(v.mean, ref.mean, 5 * se + 2e-3 * ref.mean)
                << "receiver " << r.x.x << "," << r.x.y << "," << r.x.z << " with " << set.vpls
                << " VPLs";
            if (prev_se > 0) {
                EXPECT_LT(v.stderr_of_mean, prev_se) << set.vpls << " VPLs";
            }
            prev_se = v.stderr_of_mean;
        }
    }
}

// Timing on a real scene, run by hand:
//   MANYLIGHT_VPL_SCENE=scene.pbrt manylight_tests --gtest_also_run_disabled_tests
//     --gtest_filter='Vpl.DISABLED_BuildTiming'
TEST(Vpl, DISABLED_BuildTiming) {
    const char* path = std::getenv("MANYLIGHT_VPL_SCENE");
    if (!path) GTEST_SKIP() << "set MANYLIGHT_VPL_SCENE";
    Scene scene(parse_scene_file(path));
    for (int count : {100000, 1000000}) {
        PointLightOptions o;
        o.vpl_count = count;
        PointLightSet set = build_point_light_set(scene, o);
        std::printf(
            "%d VPLs target: %zu lights (%zu VPLs, %zu glossy surfaces, %zu omni, %zu "
            "oriented, %zu directional) from %zu paths in %.2f s\n",
            count, set.lights.size(), set.vpls, set.surfaces.size(), set.omni, set.oriented,
            set.directional, set.light_paths, set.seconds);
    }
}
