// Bidirectional path tracing: the white furnace, agreement with path (area, point and spot
// lights; glass and mirror), MIS weights that sum to one over the strategies of random paths,
// strategy images that add up to the image, the same image for any thread count, and the
// path-of-depth estimator Metropolis integrators use.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "bidir/bdpt_estimator.h"
#include "bidir/connect.h"
#include "bidir/subpaths.h"
#include "bidir_test_helpers.h"
#include "lights/light_sampler.h"
#include "materials/material.h"
#include "render/settings.h"
#include "sampling/sampler.h"

using namespace ml;

TEST(Bdpt, WhiteFurnaceHoldsAtEachDepth) {
    for (int depth : {0, 1, 4}) {
        RenderOptions opt;
        opt.integrator = "bdpt";
        opt.spp = 32;
        opt.seed = 5;
        test::expect_furnace(opt, depth);
    }
}

TEST(Bdpt, AgreesWithPathOnTheCornellBox) {
    std::string scene = test::cornell_variant();
    auto b = test::render_twice(scene, "bdpt", 32, 5, 32);
    auto p = test::render_twice(scene, "path", 64, 5, 32);
    test::expect_agreement(b, p, 8, "bdpt vs path, area light");
}

TEST(Bdpt, AgreesWithPathUnderPointAndSpotLights) {
    for (const std::string& light : {test::kCornellPointLight, test::kCornellSpotLight}) {
        std::string scene = test::cornell_variant("", light);
        auto b = test::render_twice(scene, "bdpt", 16, 3, 32);
        auto p = test::render_twice(scene, "path", 32, 3, 32);
        test::expect_agreement(b, p, 8, "bdpt vs path: " + light);
    }
}

TEST(Bdpt, AgreesWithPathThroughGlassAndMirrors) {
    // Delta BSDFs under an area light: caustics through the glass sphere reach the camera only
    // by s = 0 and by light subpaths ending on diffuse surfaces.
    std::string scene = test::cornell_variant(test::glass_and_mirror());
    auto b = test::render_twice(scene, "bdpt", 64, 5, 32);
    auto p = test::render_twice(scene, "path", 256, 5, 32);
    test::expect_agreement(b, p, 8, "bdpt vs path, glass and mirror");
}

TEST(Bdpt, AgreesWithPathUnderEnvironmentAndDistantLights) {
    // Infinite lights: escaped camera rays (s = 0), light subpaths from the scene's bounding
    // disk, and their densities per solid angle; a distant light is a delta direction.
    for (const std::string light :
         {R"(LightSource "infinite" "rgb L" [ 0.8 0.9 1.0 ])",
          R"(LightSource "distant" "point3 from" [ 1 3 2 ] "point3 to" [ 0 0 0 ]
               "rgb L" [ 3 3 2.5 ])"}) {
        std::string scene = fmt::format(R"(
LookAt 0 1.5 5  0 0.4 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 32 ]
Sampler "independent"
WorldBegin
{}
Material "diffuse" "rgb reflectance" [ 0.6 0.5 0.4 ]
Shape "trianglemesh" "point3 P" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ]
  "integer indices" [ 0 1 2 0 2 3 ]
AttributeBegin
  Translate 0 0.6 0
  Material "diffuse" "rgb reflectance" [ 0.3 0.6 0.3 ]
  Shape "sphere" "float radius" [ 0.6 ]
AttributeEnd
)",
                                        light);
        auto b = test::render_twice(scene, "bdpt", 32, 4, 32);
        auto p = test::render_twice(scene, "path", 64, 4, 32);
        test::expect_agreement(b, p, 8, "bdpt vs path: " + light);
    }
}

TEST(Bdpt, AgreesWithPathThroughAThinLens) {
    // Depth of field: t = 1 strategies sample the lens, camera importance spreads over it.
    std::string scene = test::cornell_variant();
    size_t at = scene.find("\"float fov\" [ 39.3077 ]");
    ASSERT_NE(at, std::string::npos);
    scene.insert(at, "\"float lensradius\" [ 25 ] \"float focaldistance\" [ 1000 ] ");
    auto p = test::render_twice(scene, "path", 64, 4, 32);
    auto b = test::render_twice(scene, "bdpt", 32, 4, 32);
    test::expect_agreement(b, p, 8, "bdpt vs path, thin lens");
    auto l = test::render_twice(scene, "lighttracer", 64, 4, 32);
    test::expect_agreement(l, p, 8, "lighttracer vs path, thin lens");
}

namespace {

// For a camera subpath whose first n vertices end on an emitter, the MIS weights of every
// strategy (s, n - s) that could have made that path, computed as if each had made it.
// Returns the sum over the strategies whose connection is possible.
double weight_sum(const BdptScene& ctx, std::vector<PathVertex> cam, int n) {
    // The densities from the vertices' positions, as the weights recompute them at the
    // connection (the walk's use the sampled directions, which differ by the ray origins'
    // offsets off the surfaces: up to a percent in the box's corners).
    for (int k = 1; k < n; ++k)
        cam[k].pdf_fwd = cam[k - 1].pdf_area(ctx, k >= 2 ? &cam[k - 2] : nullptr, cam[k]);
    for (int k = 0; k + 2 < n; ++k) cam[k].pdf_rev = cam[k + 1].pdf_area(ctx, &cam[k + 2], cam[k]);
    const PathVertex& e = cam[n - 1];
    // The light subpath that walks the same vertices backwards.
    std::vector<PathVertex> light(static_cast<size_t>(n), PathVertex());
    for (int j = 0; j < n; ++j) {
        PathVertex v = cam[n - 1 - j];
        std::swap(v.pdf_fwd, v.pdf_rev);
        light[j] = v;
    }
    light[0] = PathVertex::light_endpoint(e.si.area_light, e.p(), e.ng(), RGB(1.f), 0);
    light[0].pdf_fwd = light[0].pdf_light_origin(ctx, cam[n - 2]);
    light[0].pdf_rev = e.pdf_fwd;
    light[1].pdf_fwd = light[0].pdf_light(ctx, light[1]);
    PathVertex lens = PathVertex::camera(cam[0].p(), ctx.camera.forward(0.f), RGB(1.f));
    double sum = 0;
    for (int s = 0; s < n; ++s) {
        int t = n - s;
        bool possible = s == 0 ? true
                               : light[s - 1].is_connectible() && cam[t - 1].is_connectible() &&
                                     (t > 1 || light[s - 1].kind == VertexKind::Surface);
        if (!possible) continue;
        const PathVertex& sampled = s == 1 ? light[0] : lens;
        sum += mis_weight(ctx, light.data(), cam.data(), sampled, s, t);
    }
    return sum;
}

void expect_weights_sum_to_one(const std::string& text, int paths_wanted) {
    test::Bench b(text, 32);
    auto sampler = create_sampler("independent", 1, 7);
    ScratchBuffer scratch;
    std::vector<PathVertex> cam(8);
    int checked = 0;
    for (int i = 0; i < 200000 && checked < paths_wanted; ++i) {
        sampler->start_pixel_sample(Point2i{i % 32, (i / 32) % 32}, i);
        CameraSample cs{Vec2(32 * sampler->get_1d(), 32 * sampler->get_1d()), sampler->get_2d(), 0};
        int nc = generate_camera_subpath(*b.ctx, b.camera->generate_ray(cs), *sampler, scratch, 8,
                                         cam.data());
        for (int n = 3; n <= nc; ++n) {
            const PathVertex& e = cam[n - 1];
            if (e.kind != VertexKind::Surface || !e.si.area_light || e.beta.is_black()) continue;
            double sum = weight_sum(*b.ctx, cam, n);
            ASSERT_NEAR(sum, 1.0, 1e-4) << "path of " << n << " vertices, sample " << i;
            ++checked;
        }
        scratch.reset();
    }
    EXPECT_GE(checked, paths_wanted);
}

// True for blocks where some pixel sees a delta-only BSDF first (light tracing cannot see
// through those).
std::function<bool(int, int)> blocks_seeing_specular(const std::string& text, int res, int block) {
    test::Bench b(text, res);
    std::vector<bool> bad(size_t(res / block) * (res / block), false);
    ScratchBuffer scratch;
    for (int y = 0; y < res; ++y)
        for (int x = 0; x < res; ++x)
            for (Vec2 o : {Vec2(0.01f, 0.01f), Vec2(0.99f, 0.01f), Vec2(0.01f, 0.99f),
                           Vec2(0.99f, 0.99f), Vec2(0.5f, 0.5f)}) {
                SurfaceInteraction si;
                Ray r = b.camera->generate_ray({Vec2(x + o.x, y + o.y), Vec2(0.5f, 0.5f), 0});
                if (!b.scene->intersect(r, &si) || !si.material) continue;
                if (hit_bsdf(si, scratch).is_specular_only())
                    bad[size_t(y / block) * (res / block) + x / block] = true;
                scratch.reset();
            }
    return [bad, res, block](int x0, int y0) {
        return bool(bad[size_t(y0 / block) * (res / block) + x0 / block]);
    };
}

}  // namespace

TEST(Bdpt, AgreesWithLightTracingForPointLightCausticsThroughGlassAndMirrors) {
    // A point light and delta BSDFs: path tracing cannot find the caustics (no strategy of it
    // samples them), light tracing can, wherever the camera sees a diffuse surface first.
    std::string scene = test::cornell_variant(test::glass_and_mirror(), test::kCornellPointLight);
    auto b = test::render_twice(scene, "bdpt", 32, 4, 32);
    auto l = test::render_twice(scene, "lighttracer", 128, 4, 32);
    test::expect_agreement(b, l, 8, "bdpt vs lighttracer, point light, glass and mirror",
                           blocks_seeing_specular(scene, 32, 8));
}

TEST(Bdpt, MisWeightsSumToOneOverStrategies) {
    expect_weights_sum_to_one(test::cornell_variant(), 300);
}

TEST(Bdpt, MisWeightsSumToOneThroughDeltaBsdfs) {
    expect_weights_sum_to_one(test::cornell_variant(test::glass_and_mirror()), 300);
}

TEST(Bdpt, StrategyImagesAddUpToTheImage) {
    RenderOptions opt;
    opt.integrator = "bdpt";
    opt.spp = 4;
    opt.max_depth = 3;
    opt.width = opt.height = 16;
    opt.set["bdpt.strategy_images"] = "true";
    RenderOutput out = test::render_text(test::cornell_variant(), opt);
    // (1 + 3)(6 + 3) / 2 slots, two of them unused: (1, 1) and the depth-0 t = 0.
    EXPECT_EQ(out.debug_images.size(), 18u);
    ASSERT_TRUE(out.debug_images.count("bdpt_s0_t2"));
    ASSERT_TRUE(out.debug_images.count("bdpt_s3_t1"));
    for (size_t i = 0; i < out.image.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            double sum = 0;
            for (auto& [name, img] : out.debug_images) sum += img.pixels[i][c];
            EXPECT_NEAR(sum, out.image.pixels[i][c], 1e-4 * (1 + sum)) << i;
        }
}

TEST(Bdpt, SameImageForAnyThreadCount) {
    std::string scene = test::cornell_variant();
    auto render = [&](int threads) {
        RenderOptions opt;
        opt.integrator = "bdpt";
        opt.spp = 2;
        opt.max_depth = 3;
        opt.width = opt.height = 32;
        opt.threads = threads;
        opt.seed = 3;
        return test::render_text(scene, opt).image;
    };
    Image a = render(1), b = render(2);
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    for (size_t i = 0; i < a.pixels.size(); ++i) ASSERT_TRUE(a.pixels[i] == b.pixels[i]) << i;
}

TEST(Bdpt, PathOfDepthEstimatorMatchesTheImage) {
    // Paths of each depth, strategy and film position drawn by the sampler: the mean
    // contribution over uniformly drawn samples is the mean pixel value of that depth, so the
    // sum over depths 0..3 is the image mean of bdpt at maxdepth 3.
    std::string scene = test::cornell_variant();
    test::Bench b(scene, 32);
    BdptEstimator est(*b.scene, *b.camera);
    auto sampler = create_sampler("independent", 1, 21);
    ScratchBuffer scratch;
    const int n = 40000;
    double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
    int streams_seen = 0;
    for (int i = 0; i < n; ++i) {
        RGB total;
        for (int depth = 0; depth <= 3; ++depth) {
            sampler->start_pixel_sample(Point2i{i % 32, i / 32 % 32}, i * 4 + depth);
            BdptPathSample ps =
                est.sample_depth(*sampler, depth, scratch, [&](BdptStream) { ++streams_seen; });
            EXPECT_TRUE(ps.p_raster.x >= 0 && ps.p_raster.x < 32 && ps.p_raster.y >= 0 &&
                        ps.p_raster.y < 32);
            total += ps.L;
            scratch.reset();
        }
        for (int c = 0; c < 3; ++c) {
            sum[c] += total[c];
            sum2[c] += double(total[c]) * total[c];
        }
    }
    EXPECT_GT(streams_seen, n);
    auto ref = test::render_twice(scene, "path", 64, 3, 32);
    for (int c = 0; c < 3; ++c) {
        double mean = sum[c] / n;
        double se = std::sqrt((sum2[c] / n - mean * mean) / (n - 1));
        test::ChannelStats r1 = test::channel_stats(ref.a, c), r2 = test::channel_stats(ref.b, c);
        double ref_mean = 0.5 * (r1.mean + r2.mean);
        double ref_se = std::abs(r1.mean - r2.mean);  // a crude but honest noise scale
        EXPECT_NEAR(mean, ref_mean, 5 * std::sqrt(se * se + ref_se * ref_se)) << "channel " << c;
    }
}

TEST(Bdpt, BadSettingsAreUsageErrors) {
    for (auto [key, value] : {std::pair<std::string, std::string>{"bdpt.maxdepth", "-1"},
                              {"bdpt.lightsampler", "bvhx"},
                              {"bdpt.strategy_images", "maybe"},
                              {"bdpt.nosuchkey", "1"}}) {
        RenderOptions opt;
        opt.integrator = "bdpt";
        opt.spp = 1;
        opt.width = opt.height = 8;
        opt.set[key] = value;
        EXPECT_THROW(test::render_text(test::cornell_variant(), opt), UsageError) << key;
    }
    RenderOptions opt;
    opt.integrator = "lighttracer";
    opt.spp = 1;
    opt.width = opt.height = 8;
    opt.set["lighttracer.maxdepth"] = "-2";
    EXPECT_THROW(test::render_text(test::cornell_variant(), opt), UsageError);
}
