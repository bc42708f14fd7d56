// Multidimensional Lightcuts against the exact sum (DESIGN.md section 4): on the same point-light
// set and the same gather points, the `mdlightcuts` image is within (a few times) the chosen
// error of the brute-force `vpl` image in nearly every pixel, and its mean within the noise; the
// product cut's bounds hold for every pair; renders repeat for a seed whatever the threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "camera/camera.h"
#include "core/rng.h"
#include "manylight/gather_tree.h"
#include "manylight/product_cut.h"
#include "render/settings.h"
#include "render_helpers.h"
#include "scene/default_scene.h"
#include "scene/scene.h"
#include "shared_files.h"

using namespace ml;

namespace {

SceneDesc cornell() { return parse_scene_string(default_scene_text(), "."); }
SceneDesc cornell_4096() {
    return parse_scene_file(ml::test::shared_dir() +
                            "/scenes/cornell-box/scene-pointlights-4096.pbrt");
}

RenderOptions many_light_options(const std::string& integrator, int res, int spp) {
    RenderOptions opt;
    opt.integrator = integrator;
    opt.spp = spp;
    opt.width = res;
    opt.height = res;
    opt.seed = 5;
    opt.progress = false;
    opt.set["vpl.count"] = "2000";
    opt.set["lights.area_count"] = "256";
    // One VPL set and tree whatever the render's seed (vpl.seed's default before it followed
    // --seed): the per-pixel fractions these tests check move from one VPL set to another by
    // about as much as their margin (lightcuts at 16 spp on cornell_4096: 98.6% to 100% of
    // pixels within 2% over 13 sets, the old and the new estimator alike).
    opt.set["vpl.seed"] = "0";
    // The cut against the brute-force sum needs both on the same VPLs: one set per render.
    opt.set["vpl.sets"] = "one";
    // The settings these thresholds were set on: the defaults before issue 13.
    opt.set["vpl.glossy"] = "bsdf";
    opt.set["lights.direct"] = "points";
    opt.set["vpl.clamp"] = "0";
    if (integrator == "mdlightcuts") {
        opt.set["mdlightcuts.samples"] = "16";
        opt.set["mdlightcuts.error"] = "0.02";
        opt.set["mdlightcuts.max_cut"] = "2000";
        // These thresholds are on the relative error Walter et al.'s criterion bounds; the
        // floor, which relaxes it in dark pixels, is tested on its own.
        opt.set["mdlightcuts.floor"] = "0";
    }
    return opt;
}

struct Agreement {
    std::vector<double> rel;  // per pixel, sorted: |mdlightcuts - exact| / exact (luminance)
    double percentile(double p) const { return rel[size_t(p * double(rel.size() - 1))]; }
    double fraction_within(double e) const {
        return double(std::count_if(rel.begin(), rel.end(), [&](double r) { return r <= e; })) /
               double(rel.size());
    }
    test::MeanDifference mean;            // of the luminance images
    std::vector<double> exact, estimate;  // per pixel luminance, in pixel order
    nlohmann::json stats;                 // mdlightcuts' --stats figures
};

Image luminance_image(const Image& img) {
    Image l(img.width, img.height);
    for (size_t i = 0; i < img.pixels.size(); ++i) l.pixels[i] = RGB(img.pixels[i].luminance());
    return l;
}

template <typename Load>
Agreement compare_with_exact(Load load, int res, int spp, float error,
                             const std::string& criterion = "max", int max_cut = 2000,
                             float floor = 0) {
    RenderOutput exact = render_scene(load(), many_light_options("vpl", res, spp));
    RenderOptions opt = many_light_options("mdlightcuts", res, spp);
    opt.set["mdlightcuts.floor"] = fmt::format("{}", floor);
    opt.set["mdlightcuts.error"] = fmt::format("{}", error);
    opt.set["mdlightcuts.criterion"] = criterion;
    opt.set["mdlightcuts.max_cut"] = std::to_string(max_cut);
    RenderOutput md = render_scene(load(), opt);
    EXPECT_EQ(exact.figures.point_lights, md.figures.point_lights);
    EXPECT_EQ(exact.figures.spp, md.figures.spp);
    Agreement a;
    for (size_t i = 0; i < exact.image.pixels.size(); ++i) {
        double e = exact.image.pixels[i].luminance(), c = md.image.pixels[i].luminance();
        a.rel.push_back(std::abs(c - e) / std::max(e, 1e-6));
        a.exact.push_back(e);
        a.estimate.push_back(c);
    }
    std::sort(a.rel.begin(), a.rel.end());
    a.stats = md.figures.integrator_stats.at("mdlightcuts");
    a.mean = test::mean_difference(luminance_image(md.image), luminance_image(exact.image), 0);
    std::printf(
        "lights %zu (vpls %zu), %s error %.3f, %d spp: per-pixel relative difference p50 %.4f p90 "
        "%.4f p99 %.4f max %.4f; %.1f%% within the error, %.1f%% within 2.5x; image mean "
        "%+.3f%% (standard error %.3f%%)\n%s\n",
        exact.figures.point_lights, exact.figures.vpls, criterion.c_str(), error, spp,
        a.percentile(0.5), a.percentile(0.9), a.percentile(0.99), a.rel.back(),
        100 * a.fraction_within(error), 100 * a.fraction_within(2.5 * error),
        100 * a.mean.mean / a.mean.reference_mean,
        100 * a.mean.stderr_of_mean / a.mean.reference_mean,
        md.figures.integrator_stats.dump().c_str());
    return a;
}

}  // namespace

// The cut's error against the brute-force sum over the same lights at the same gather points.
// Walter et al.'s criterion bounds each pair's error by the threshold, not the pixel's: one cut
// shades all 16 samples, so its pairs' errors add up with nothing to average with, and the
// pixel's error is about the threshold in half the pixels and a few times it in the worst 10%
// (single-point Lightcuts at 16 spp averages 16 independent cuts). The representatives are drawn
// at random, so the image mean agrees within the noise, and the error shrinks with the threshold.
TEST(MdLightcuts, WithinTheErrorOfTheExactSum) {
    ML_NEED_SHARED("scenes/cornell-box/scene-pointlights-4096.pbrt");
    for (auto load : {cornell_4096, cornell}) {
        const float e = 0.02f;
        Agreement a = compare_with_exact(load, 20, 16, e);
        EXPECT_LE(a.percentile(0.5), 1.25 * e);
        EXPECT_GE(a.fraction_within(3 * e), 0.9);
        EXPECT_LE(a.percentile(0.99), 10 * e);
        EXPECT_NEAR(a.mean.mean, 0, 4 * a.mean.stderr_of_mean + 2e-3 * a.mean.reference_mean);
        Agreement fine = compare_with_exact(load, 20, 16, e / 4);
        EXPECT_GE(fine.fraction_within(2.5 * e), 0.98);
        EXPECT_LT(fine.percentile(0.9), a.percentile(0.9));
    }
}

// With the "sum" criterion (and no cap on the cut) each pixel's error is bounded by the
// threshold for certain: every pixel is within it.
TEST(MdLightcuts, SumCriterionBoundsEveryPixel) {
    ML_NEED_SHARED("scenes/cornell-box/scene-pointlights-4096.pbrt");
    Agreement a = compare_with_exact(cornell_4096, 10, 16, 0.05f, "sum", 1 << 24);
    EXPECT_GE(a.fraction_within(0.05 * 1.001), 0.999);
}

// A cut stopped by max_cut is not within the error: --stats counts such pixel passes, and the
// render warns when they are more than 10%.
TEST(MdLightcuts, WarnsWhenCutsReachTheCap) {
    ML_NEED_SHARED("scenes/cornell-box/scene-pointlights-4096.pbrt");
    for (const char* max_cut : {"8", "2000"}) {
        RenderOptions opt = many_light_options("mdlightcuts", 8, 16);
        opt.set["mdlightcuts.max_cut"] = max_cut;
        RenderOutput out = render_scene(cornell_4096(), opt);
        const nlohmann::json& json = out.figures.integrator_stats.at("mdlightcuts");
        double capped = json.at("capped_fraction").get<double>();
        bool warned = !out.figures.warnings.empty() &&
                      out.figures.warnings.back().find("max_cut") != std::string::npos;
        bool small = std::string(max_cut) == "8";
        EXPECT_EQ(warned, small) << json;
        if (small)
            EXPECT_GT(capped, 0.9);
        else
            EXPECT_LT(capped, 0.1);
    }
}

// Two passes of 16 samples (spp 20 rounds up to 32) shade with independent representatives, so
// the error shrinks and stays unbiased.
TEST(MdLightcuts, PassesRoundUpAndAverage) {
    ML_NEED_SHARED("scenes/cornell-box/scene-pointlights-4096.pbrt");
    RenderOptions opt = many_light_options("mdlightcuts", 8, 20);
    RenderOutput out = render_scene(cornell_4096(), opt);
    EXPECT_EQ(out.figures.spp, 32);
    EXPECT_EQ(out.figures.integrator_stats.at("mdlightcuts").at("passes"), 2)
        << out.figures.integrator_stats;
    ASSERT_TRUE(out.aovs.count("cutsize"));
    EXPECT_GT(out.aovs.at("cutsize").pixels[0].r, 1.f);
}

// Every pair of a cut, and random pairs of the product graph, against the exact sum it stands
// for (every member gather point with every light of the node, a shadow ray each): the tight
// bound (RGB, channel by channel) and the loose one the cut starts a pair with are never below
// it, and the pair's error bound holds its estimate's error. A cut stopped at its cap keeps no
// spike.
namespace {

void expect_pair_bounds_hold(SceneDesc desc, int w, int h, int vpls, const char* glossy,
                             const std::vector<Point2i>& pixels) {
    PerspectiveCamera camera(desc.camera.params, desc.world_to_camera.inverse(), w, h);
    Scene scene(std::move(desc));
    ManyLightSettings settings;
    settings.lights.vpl_count = vpls;
    settings.lights.area_count = 256;
    settings.lights.seed = 3;
    settings.lights.vpl_glossy =
        std::string(glossy) == "bsdf" ? GlossyVpls::Bsdf : GlossyVpls::Diffuse;
    PointLightSet set = build_point_light_set(scene, settings.lights);
    LightTreeOptions topt;
    topt.scene_diagonal = length(scene.bounds().diagonal());
    LightTree tree(set.lights, topt);
    ProductCut cut(scene, set, tree, settings);
    auto sampler = create_sampler("independent", 16, 11);
    ScratchBuffer scratch;
    Rng rng(17);
    int checked = 0, clustered = 0, capped_pairs = 0, drawn_shapes = 0;
    for (Point2i pixel : pixels) {
        std::vector<WeightedGatherPoint> points;
        std::vector<Vec3> positions;
        std::vector<RGB> weights;
        std::vector<float> uniforms;
        for (int s = 0; s < 16; ++s) {
            sampler->start_pixel_sample(pixel, s);
            Vec2 u = sampler->get_2d();
            Ray ray =
                camera.generate_ray({Vec2(pixel.x + u.x, pixel.y + u.y), Vec2(0.5f, 0.5f), 0});
            gather_along(scene, ray, *sampler, scratch, settings.max_depth,
                         [&](const GatherPoint& g, float uc) {
                             points.push_back({g, 1.f / 16, g.beta * (1.f / 16)});
                             positions.push_back(g.si.p);
                             weights.push_back(points.back().w);
                             uniforms.push_back(uc);
                             return RGB();
                         });
        }
        if (points.size() < 2) continue;
        GatherTree gtree;
        ASSERT_GE(gtree.build(positions, weights, uniforms), 0);
        // Strengths add up, and a node's representative for a key is one of its children's.
        for (size_t n = 0; n < gtree.node_count(); ++n) {
            const GatherTreeNode& G = gtree.node(int32_t(n));
            if (G.is_leaf()) continue;
            const GatherTreeNode &a = gtree.node(G.children[0]), &b = gtree.node(G.children[1]);
            EXPECT_NEAR(G.strength.luminance(), (a.strength + b.strength).luminance(),
                        1e-5f * G.strength.luminance());
            for (uint32_t key : {0u, 7u, 123u, 4567u}) {
                int32_t r = gtree.rep(int32_t(n), key);
                EXPECT_TRUE(r == gtree.rep(G.children[0], key) ||
                            r == gtree.rep(G.children[1], key));
                // The child that holds it has it as its own (the cut keeps its shadow ray).
                int32_t holder = gtree.holds(G.children[0], r) ? G.children[0] : G.children[1];
                EXPECT_TRUE(gtree.holds(holder, r));
                EXPECT_EQ(gtree.rep(holder, key), r);
            }
        }
        // holds() is membership: every node holds exactly its members.
        for (size_t n = 0; n < gtree.node_count(); ++n) {
            const GatherTreeNode& G = gtree.node(int32_t(n));
            int held = 0;
            for (size_t i = 0; i < positions.size(); ++i)
                held += gtree.holds(int32_t(n), int32_t(i));
            EXPECT_EQ(held, G.end - G.begin);
            for (int32_t m = G.begin; m < G.end; ++m)
                EXPECT_TRUE(gtree.holds(int32_t(n), gtree.members()[size_t(m)]));
        }
        // A cut stopped at a small cap stops there, whatever its pairs' estimates: splitting
        // the pairs whose estimate is a spike would split the high draws and keep the low ones,
        // a cut that is dark on average. Its pairs still cover every light once.
        cut.refine(points, gtree, 0, RGB(), 0.02f, 8, CutCriterion::Max, 1);
        EXPECT_LE(cut.pairs().size(), 8u) << "pixel " << pixel.x << "," << pixel.y;
        capped_pairs += int(cut.pairs().size());
        // With set_draw_free, which pairs a cut splits depends on no draw: other representatives
        // (another k) give a cut of the same pairs, capped or not. Without it they may not.
        for (int cap : {8, 2000}) {
            auto shape = [&](int k, bool draw_free) {
                cut.set_draw_free(draw_free);
                cut.refine(points, gtree, k, RGB(0.01f), 0.02f, cap, CutCriterion::Max, 1);
                cut.set_draw_free(false);
                std::vector<std::pair<int32_t, int32_t>> s;
                for (const ProductPair& p : cut.pairs()) s.emplace_back(p.gather, p.light);
                std::sort(s.begin(), s.end());
                return s;
            };
            EXPECT_EQ(shape(0, true), shape(tree.reps() - 1, true))
                << "pixel " << pixel.x << "," << pixel.y << " cap " << cap;
            drawn_shapes += shape(0, false) != shape(tree.reps() - 1, false);
        }
        cut.refine(points, gtree, 0, RGB(), 0.02f, 2000, CutCriterion::Max, 1);
        std::vector<ProductPair> pairs = cut.pairs();
        // Random pairs: a random gather node with a light node a random number of levels down.
        for (int r = 0; r < 12; ++r) {
            ProductPair p;
            p.gather = int32_t(rng.next_float() * float(gtree.node_count()));
            p.light = tree.root(r % 2 ? PointLightKind::Omni : PointLightKind::Oriented);
            if (p.light < 0) continue;
            int depth = int(rng.next_float() * 14);
            for (int d = 0; d < depth && !tree.node(p.light).is_leaf(); ++d)
                p.light = tree.node(p.light).children()[rng.next_float() < 0.5f ? 0 : 1];
            pairs.push_back(p);
        }
        for (const ProductPair& p : pairs) {
            RGB exact = cut.exact(points, gtree, p.gather, p.light);
            RGB tight = cut.tight_bound(points, gtree, p.gather, p.light);
            RGB loose = cut.loose_bound(points, gtree, p.gather, p.light);
            cut.set_direction_bins(false);
            RGB loose_all = cut.loose_bound(points, gtree, p.gather, p.light);
            cut.set_direction_bins(true);
            if (!gtree.node(p.gather).is_leaf() || !tree.node(p.light).is_leaf()) ++clustered;
            for (int c = 0; c < 3; ++c) {
                EXPECT_GE(tight[c] * 1.0001f + 1e-9f, exact[c])
                    << "pixel " << pixel.x << "," << pixel.y << " gather node " << p.gather
                    << " light node " << p.light << " channel " << c;
                EXPECT_GE(loose[c] * 1.0001f + 1e-9f, tight[c]) << "channel " << c;
                EXPECT_GE(loose_all[c], loose[c]) << "channel " << c;
            }
            if (p.grep >= 0 && p.bound > 0) {  // a pair of the cut: its error within its bound
                EXPECT_GE(p.bound * 1.0001f + 1e-9f,
                          std::abs(p.estimate.luminance() - exact.luminance()));
            }
            ++checked;
        }
        scratch.reset();
    }
    std::printf(
        "%d pairs checked, %d of them clustered; %d pairs of capped cuts; %d cuts whose pairs "
        "follow the draws\n",
        checked, clustered, capped_pairs, drawn_shapes);
    // The estimate-driven refinement does follow them somewhere (what set_draw_free takes away).
    EXPECT_GT(drawn_shapes, 0);
    EXPECT_GT(clustered, 100);
    EXPECT_GT(capped_pairs, 20);
}

}  // namespace

TEST(MdLightcuts, PairBoundsAreUpperBoundsOfTheExactSum) {
    ML_NEED_SHARED("scenes/cornell-box/scene-pointlights-4096.pbrt");
    expect_pair_bounds_hold(cornell_4096(), 16, 16, 500, "bsdf",
                            {{8, 8}, {2, 13}, {14, 3}, {7, 1}});
}

// The kitchen: bump mapping, coated and metal surfaces, glossy VPLs, area lights close to the
// worktops, glass and mirrors (coloured throughputs).
TEST(MdLightcuts, PairBoundsHoldOnTheKitchen) {
    ML_NEED_SHARED("scenes/kitchen/scene-v4.pbrt");
    for (const char* glossy : {"bsdf", "diffuse"})
        expect_pair_bounds_hold(
            parse_scene_file(ml::test::shared_dir() + "/scenes/kitchen/scene-v4.pbrt"), 32, 18,
            1000, glossy, {{16, 9}, {5, 12}, {27, 4}, {10, 15}, {22, 13}});
}

TEST(MdLightcuts, DeterministicForASeedWhateverTheThreads) {
    ML_NEED_SHARED("scenes/cornell-box/scene-pointlights-4096.pbrt");
    RenderOptions opt = many_light_options("mdlightcuts", 16, 32);
    opt.set["mdlightcuts.samples"] = "8";
    opt.threads = 1;
    Image one = render_scene(cornell_4096(), opt).image;
    opt.threads = 2;
    Image two = render_scene(cornell_4096(), opt).image;
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    for (size_t i = 0; i < one.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(one.pixels[i][c], two.pixels[i][c]) << i;
}

TEST(MdLightcuts, BadSettingsAreUsageErrors) {
    auto render = [](const std::string& key, const std::string& value) {
        RenderOptions opt = many_light_options("mdlightcuts", 4, 1);
        opt.set["vpl.count"] = "10";
        opt.set[key] = value;
        render_scene(cornell(), opt);
    };
    EXPECT_THROW(render("mdlightcuts.samples", "0"), UsageError);
    EXPECT_THROW(render("mdlightcuts.error", "-0.1"), UsageError);
    EXPECT_THROW(render("mdlightcuts.error", "nan"), UsageError);
    EXPECT_THROW(render("mdlightcuts.max_cut", "0"), UsageError);
    EXPECT_THROW(render("mdlightcuts.floor", "-1"), UsageError);
    EXPECT_THROW(render("mdlightcuts.samplez", "4"), UsageError);
    EXPECT_THROW(render("mdlightcuts.criterion", "probable"), UsageError);
    EXPECT_THROW(render("lightcuts.criterion", "max"), UsageError);  // not ours
    EXPECT_THROW(render("mdlightcuts.samples", "many"), UsageError);
    EXPECT_NO_THROW(render("mdlightcuts.samples", "4"));
}
