// Lightcuts against the exact sum (DESIGN.md section 4): on the same point-light set, every
// pixel's lightcut estimate is within the chosen relative error of the brute-force `vpl` image in
// at least 99% of pixels. The bound is conservative; the percentiles reached are printed.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/error.h"
#include "manylight/light_tree.h"
#include "render_helpers.h"
#include "scene/default_scene.h"
#include "shared_files.h"

using namespace ml;

namespace {

struct CutOptions {
    float error = 0.02f;
    std::string criterion = "max";
    int max_cut = 1000;
    int spp = 2;
    int reps = kLightTreeReps;
    // These tests check the relative error Walter et al.'s criterion bounds; the floor, which
    // relaxes it in dark pixels, is tested on its own.
    float floor = 0;
};

RenderOutput render_many(const std::string& integrator, SceneDesc desc, int vpls, int res,
                         const CutOptions& cut) {
    RenderOptions opt;
    opt.integrator = integrator;
    opt.spp = cut.spp;
    opt.width = res;
    opt.height = res;
    opt.seed = 5;
    opt.progress = false;
    opt.set["vpl.count"] = std::to_string(vpls);
    opt.set["lights.area_count"] = "256";
    // One VPL set and tree whatever the render's seed (vpl.seed's default before it followed
    // --seed): the per-pixel fractions these tests check move from one VPL set to another by
    // about as much as their margin (lightcuts at 16 spp on cornell_4096: 98.6% to 100% of
    // pixels within 2% over 13 sets, the old and the new estimator alike).
    opt.set["vpl.seed"] = "0";
    // The light set these thresholds were set on: the defaults before issue 13.
    opt.set["vpl.glossy"] = "bsdf";
    opt.set["lights.direct"] = "points";
    opt.set["vpl.clamp"] = "0";
    if (integrator == "lightcuts") {
        opt.set["lightcuts.error"] = std::to_string(cut.error);
        opt.set["lightcuts.criterion"] = cut.criterion;
        opt.set["lightcuts.max_cut"] = std::to_string(cut.max_cut);
        opt.set["lightcuts.reps"] = std::to_string(cut.reps);
        opt.set["lightcuts.floor"] = std::to_string(cut.floor);
    }
    return render_scene(std::move(desc), opt);
}

struct ErrorFigures {
    std::vector<double> rel;  // per pixel, sorted: |lightcuts - exact| / exact (luminance)
    double mean_rel = 0;      // of the image means
    double avg_cut = 0;
    double floor_luminance = 0;
    std::vector<double> exact, estimate;  // per pixel luminance, in pixel order
    double percentile(double p) const { return rel[size_t(p * (rel.size() - 1))]; }
    double fraction_within(double e) const {
        return double(std::count_if(rel.begin(), rel.end(), [&](double r) { return r <= e; })) /
               double(rel.size());
    }
};

template <typename Load>
ErrorFigures compare_with_exact(Load load, int vpls, int res, const CutOptions& cut) {
    RenderOutput exact = render_many("vpl", load(), vpls, res, cut);
    RenderOutput lc = render_many("lightcuts", load(), vpls, res, cut);
    EXPECT_EQ(exact.figures.point_lights, lc.figures.point_lights);
    ErrorFigures f;
    double se = 0, sc = 0;
    for (size_t i = 0; i < exact.image.pixels.size(); ++i) {
        double e = exact.image.pixels[i].luminance(), c = lc.image.pixels[i].luminance();
        f.rel.push_back(std::abs(c - e) / std::max(e, 1e-6));
        f.exact.push_back(e);
        f.estimate.push_back(c);
        se += e;
        sc += c;
    }
    std::sort(f.rel.begin(), f.rel.end());
    f.mean_rel = (sc - se) / se;
    f.avg_cut = lc.figures.integrator_stats.at("lightcuts").at("avg_cut_size").get<double>();
    f.floor_luminance =
        lc.figures.integrator_stats.at("lightcuts").at("floor_luminance").get<double>();
    std::printf(
        "lights %zu (vpls %zu), %s error %.3f, %d spp, %d reps: per-pixel relative error p50 "
        "%.4f p90 %.4f p99 %.4f max %.4f; %.1f%% of pixels within the error; image mean "
        "%+.3f%%; average cut %.1f\n",
        exact.figures.point_lights, exact.figures.vpls, cut.criterion.c_str(), cut.error, cut.spp,
        cut.reps, f.percentile(0.5), f.percentile(0.9), f.percentile(0.99), f.rel.back(),
        100 * f.fraction_within(cut.error), 100 * f.mean_rel, f.avg_cut);
    return f;
}

SceneDesc cornell() { return parse_scene_string(default_scene_text(), "."); }
SceneDesc cornell_4096() {
    return parse_scene_file(ml::test::shared_dir() +
                            "/scenes/cornell-box/scene-pointlights-4096.pbrt");
}

}  // namespace

// Walter et al.'s criterion bounds each node's error by the threshold, not the cut's total:
// the typical pixel is within it, the image mean is close, and the cut converges to the exact
// sum as the threshold shrinks.
TEST(Lightcuts, MaxCriterionConvergesToTheExactSum) {
    ML_NEED_SHARED("scenes/cornell-box/scene-pointlights-4096.pbrt");
    for (auto load : {cornell, cornell_4096}) {
        ErrorFigures coarse = compare_with_exact(load, 2000, 24, {0.02f});
        EXPECT_LE(coarse.percentile(0.5), 0.02);
        EXPECT_LT(std::abs(coarse.mean_rel), 0.01);
        ErrorFigures fine = compare_with_exact(load, 2000, 24, {0.002f});
        EXPECT_GE(fine.fraction_within(0.01), 0.99);
        EXPECT_LT(fine.percentile(0.99), coarse.percentile(0.99));
    }
}

// The issue's requirement: at the default 2%, the image is within the error of the exact sum in
// at least 99% of pixels. Each node's bound is below 2% of the estimate, but a cut of a hundred
// nodes adds their errors; with one fixed representative per node those errors repeat at every
// sample of a pixel (83-89% of pixels within 2% at 2 to 8 spp). Representatives drawn per
// sample (lightcuts.reps) make them independent, so they average out over a pixel's samples.
TEST(Lightcuts, WithinTheErrorInNinetyNinePercentOfPixels) {
    ML_NEED_SHARED("scenes/cornell-box/scene-pointlights-4096.pbrt");
    for (auto load : {cornell, cornell_4096}) {
        CutOptions opt;
        opt.spp = 16;
        ErrorFigures f = compare_with_exact(load, 2000, 24, opt);
        EXPECT_GE(f.fraction_within(0.02), 0.99);
        opt.reps = 1;
        ErrorFigures fixed = compare_with_exact(load, 2000, 24, opt);
        EXPECT_LT(f.percentile(0.99), fixed.percentile(0.99));
    }
}

// With the "sum" criterion (and no cap on the cut) each gather point's error is bounded by the
// threshold for certain: every pixel is within it.
TEST(Lightcuts, SumCriterionBoundsEveryPixel) {
    ML_NEED_SHARED("scenes/cornell-box/scene-pointlights-4096.pbrt");
    for (auto load : {cornell, cornell_4096}) {
        ErrorFigures f = compare_with_exact(load, 1000, 16, {0.02f, "sum", 1 << 20});
        EXPECT_GE(f.fraction_within(0.02 * 1.001), 0.999);
    }
}

// Every clustered node of every cut, checked against the exact sum over its lights (with a
// shadow ray each, `lightcuts.verify`): its error never exceeds its bound. The kitchen has bump
// mapping, coated and metal surfaces, glossy VPLs and area lights close to the worktops.
TEST(Lightcuts, NodeErrorsStayWithinTheirBoundsOnTheKitchen) {
    ML_NEED_SHARED("scenes/kitchen/scene-v4.pbrt");
    for (const char* glossy : {"bsdf", "diffuse", "skip", "clamped"}) {
        RenderOptions opt;
        opt.integrator = "lightcuts";
        opt.spp = 1;
        opt.width = 24;
        opt.height = 14;
        opt.seed = 3;
        opt.progress = false;
        opt.set["vpl.count"] = "2000";
        opt.set["vpl.glossy"] = glossy;
        opt.set["lights.direct"] = "points";  // the area lights' points are checked too
        opt.set["vpl.clamp"] = "0";
        if (std::string(glossy) == "clamped") {
            // Bounds capped by clamping, low enough to matter: a cap of a fifth of n times
            // the clamp makes about 300 violations here.
            opt.set["vpl.glossy"] = "diffuse";
            opt.set["vpl.clamp"] = "0.003";
        }
        opt.set["lightcuts.verify"] = "true";
        RenderOutput out = render_scene(
            parse_scene_file(ml::test::shared_dir() + "/scenes/kitchen/scene-v4.pbrt"), opt);
        const nlohmann::json& json = out.figures.integrator_stats.at("lightcuts");
        std::printf("glossy %s: %s\n", glossy, json.dump().c_str());
        EXPECT_GT(json.at("verify").at("nodes").get<double>(), 10000);
        EXPECT_EQ(json.at("verify").at("violations").get<double>(), 0);
        if (std::string(glossy) == "bsdf") {
            EXPECT_GT(json.at("glossy").get<double>(), 100) << "glossy VPLs";
        }
    }
}

// A cut stopped by max_cut is not within the error: --stats counts such gather points, and the
// render warns when they are more than 10%.
TEST(Lightcuts, WarnsWhenCutsReachTheCap) {
    for (int max_cut : {4, 1000}) {
        CutOptions opt;
        opt.max_cut = max_cut;
        RenderOutput out = render_many("lightcuts", cornell(), 500, 8, opt);
        const nlohmann::json& json = out.figures.integrator_stats.at("lightcuts");
        double capped = json.at("capped_fraction").get<double>();
        bool warned = std::any_of(out.figures.warnings.begin(), out.figures.warnings.end(),
                                  [](const std::string& w) { return w.find("max_cut") != w.npos; });
        if (max_cut == 4) {
            EXPECT_GT(capped, 0.9);
            EXPECT_TRUE(warned);
        } else {
            EXPECT_LT(capped, 0.05);
            EXPECT_FALSE(warned);
        }
    }
}

// lightcuts.reps draws from the tree's representatives (tree.reps): all of them by default, and
// never more than the tree keeps (a k past them would read another node's).
TEST(Lightcuts, RepresentativesComeFromTheTreesOwn) {
    RenderOptions opt;
    opt.integrator = "lightcuts";
    opt.spp = 1;
    opt.width = opt.height = 8;
    opt.set["vpl.count"] = "200";
    opt.set["tree.reps"] = "4";
    RenderOutput out = render_scene(cornell(), opt);
    EXPECT_EQ(out.figures.integrator_stats.at("lightcuts").at("reps").get<int>(), 4);
    opt.set["lightcuts.reps"] = "8";
    try {
        render_scene(cornell(), opt);
        ADD_FAILURE() << "lightcuts.reps 8 accepted with tree.reps 4";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("lightcuts.reps must be 1 to tree.reps (4)"),
                  std::string::npos)
            << e.what();
    }
    // `vpl` builds no tree: the setting is one it does not have.
    opt.integrator = "vpl";
    opt.set.erase("lightcuts.reps");
    try {
        render_scene(cornell(), opt);
        ADD_FAILURE() << "tree.reps accepted by vpl";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("--set tree.reps"), std::string::npos) << e.what();
    }
}

// A smooth coat over a diffuse floor: the gather point takes the base's light from the point
// lights and the camera path also carries on through the coat's mirror lobe, where it sees the
// area light itself. With emitters only (no VPLs), `vpl` and `lightcuts` must then match the
// path tracer's direct light (maxdepth 1), the coat's reflection of the light included.
TEST(Lightcuts, GatherFollowsTheDeltaLobeOfASmoothCoat) {
    const std::string scene = R"(
LookAt 0 1.2 -3  0 0 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 32 ] "integer yresolution" [ 32 ]
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 4 4 4 ]
  Material "diffuse" "rgb reflectance" [ 0 0 0 ]
  Shape "trianglemesh" "integer indices" [ 0 2 1 0 3 2 ]
    "point3 P" [ -1 0.8 1  1 0.8 1  1 1.8 1.2  -1 1.8 1.2 ]
AttributeEnd
AttributeBegin
  Material "coateddiffuse" "float roughness" [ 0 ] "rgb reflectance" [ 0.5 0.5 0.5 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -3 0 -3  3 0 -3  3 0 3  -3 0 3 ]
AttributeEnd
)";
    auto render = [&](const std::string& integrator, int spp) {
        RenderOptions opt;
        opt.integrator = integrator;
        opt.spp = spp;
        opt.seed = 7;
        opt.max_depth = 1;
        if (integrator != "path") {
            opt.set["vpl.count"] = "0";
            opt.set["lights.area_count"] = "1024";
            opt.set["lights.direct"] = "points";
        }
        return test::render_text(scene, opt).image;
    };
    Image ref = render("path", 256);
    for (const char* integrator : {"vpl", "lightcuts"}) {
        Image img = render(integrator, 16);
        test::MeanDifference d = test::mean_difference(img, ref, 1);
        // Lightcuts' own error is within its 2% of each pixel.
        EXPECT_NEAR(d.mean, 0, 4 * d.stderr_of_mean + 0.02 * d.reference_mean) << integrator;
        std::printf("%s: mean difference %+.4f (reference mean %.4f, standard error %.4f)\n",
                    integrator, d.mean, d.reference_mean, d.stderr_of_mean);
    }
}
