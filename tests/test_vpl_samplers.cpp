// The VPL samplers (manylight/vpl_sampler.h): one interface, `standard` unchanged behind it, and
// `power` and `bidirectional` consistent with `standard` and with the analytic furnace, within
// tolerances from the spread over seeds (a VPL render's pixels share their VPLs, so the pixels'
// own noise understates it), deterministic at any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "core/error.h"
#include "integrators/render_job.h"
#include "manylight/point_light_set.h"
#include "manylight/vpl_sampler.h"
#include "render_helpers.h"
#include "scene/scene.h"
#include "scene/scene_desc.h"
#include "shared_files.h"
#include "vpl_test_scenes.h"

namespace ml {
namespace {

using test::render_text;

RenderOptions vpl_options(const std::string& sampler, uint64_t seed, int count, int spp = 1) {
    RenderOptions opt;
    opt.integrator = "vpl";
    opt.spp = spp;
    opt.seed = seed;
    opt.set["vpl.sampler"] = sampler;
    opt.set["vpl.count"] = std::to_string(count);
    opt.set["vpl.clamp"] = "0";  // clamping is a bias every sampler shares differently
    return opt;
}

// Per channel: the mean over seeds of a render's mean (over `region` of the image: all of it
// when empty), and its standard error from the spread over the seeds.
struct SeedStats {
    double mean[3] = {}, stderr_of_mean[3] = {};
};

template <typename Render>
SeedStats over_seeds(int seeds, Render&& render) {
    std::vector<std::array<double, 3>> m;
    for (int s = 0; s < seeds; ++s) {
        Image img = render(uint64_t(s + 1));
        std::array<double, 3> v{};
        for (const RGB& p : img.pixels)
            for (int c = 0; c < 3; ++c) v[size_t(c)] += p[c];
        for (double& x : v) x /= double(img.pixels.size());
        m.push_back(v);
    }
    SeedStats st;
    for (int c = 0; c < 3; ++c) {
        double s = 0, s2 = 0;
        for (const auto& v : m) s += v[size_t(c)], s2 += v[size_t(c)] * v[size_t(c)];
        double n = double(m.size()), mean = s / n;
        st.mean[c] = mean;
        st.stderr_of_mean[c] = std::sqrt(std::max(0.0, s2 / n - mean * mean) / (n - 1));
    }
    return st;
}

void expect_same_mean(const SeedStats& a, const SeedStats& b, const std::string& what) {
    for (int c = 0; c < 3; ++c) {
        double tol = 4.5 * std::hypot(a.stderr_of_mean[c], b.stderr_of_mean[c]);
        EXPECT_NEAR(a.mean[c], b.mean[c], tol) << what << " channel " << c;
        // A tolerance that could not fail would make the test worthless.
        EXPECT_LT(tol, 0.25 * b.mean[c]) << what << " channel " << c << ": too noisy to tell";
    }
}

TEST(VplSamplers, NamesAndSettings) {
    EXPECT_EQ(parse_vpl_sampler("standard"), VplSamplerKind::Standard);
    EXPECT_EQ(parse_vpl_sampler("power"), VplSamplerKind::Power);
    EXPECT_EQ(parse_vpl_sampler("bidirectional"), VplSamplerKind::Bidirectional);
    EXPECT_EQ(parse_vpl_sampler("metropolis"), VplSamplerKind::Metropolis);
    EXPECT_THROW(parse_vpl_sampler("keller"), UsageError);
    std::string box = test::furnace_scene(0.5f, 1.f, 4);
    // A setting of a sampler that is not the one chosen is unused: an error.
    RenderOptions opt = vpl_options("power", 1, 16);
    opt.set["vpl.candidates"] = "2";
    EXPECT_THROW(render_text(box, opt), UsageError);
    opt = vpl_options("bidirectional", 1, 16);
    opt.set["vpl.candidates"] = "0";
    EXPECT_THROW(render_text(box, opt), UsageError);
}

// Behind the interface, `standard` is generate_vpls itself: the same lights, bit for bit.
TEST(VplSamplers, StandardIsGenerateVpls) {
    auto scene = vpl_test::make_scene(vpl_test::mixed_box());
    VplOptions o;
    o.count = 300;
    o.max_depth = 3;
    o.seed = 7;
    PointLightSet a, b;
    generate_vpls(*scene, o, a);
    sample_vpls(*scene, nullptr, o, b);
    ASSERT_EQ(a.lights.size(), b.lights.size());
    ASSERT_GE(a.lights.size(), 300u);
    for (size_t i = 0; i < a.lights.size(); ++i) {
        EXPECT_EQ(a.lights[i].p, b.lights[i].p);
        EXPECT_EQ(a.lights[i].intensity, b.lights[i].intensity);
    }
    EXPECT_EQ(a.light_paths, b.light_paths);
    // The other samplers need the camera.
    o.sampler.kind = VplSamplerKind::Bidirectional;
    EXPECT_THROW(sample_vpls(*scene, nullptr, o, b), UsageError);
}

// The furnace: every sampler's image mean is the geometric series (render_helpers.h).
TEST(VplSamplers, FurnaceEverySampler) {
    const int depth = 3;
    double expected = (1 - std::pow(0.5, depth + 1)) / (1 - 0.5);
    for (const char* sampler : {"standard", "power", "bidirectional"}) {
        SeedStats st = over_seeds(6, [&](uint64_t seed) {
            RenderOptions opt = vpl_options(sampler, seed, 64, 2);
            opt.max_depth = depth;
            return render_text(test::furnace_scene(0.5f, 1.f, 8), opt).image;
        });
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(st.mean[c], expected, 4.5 * st.stderr_of_mean[c] + 3e-3 * expected)
                << sampler << " channel " << c;
    }
}

// Two lights, the camera sees the room of one: the pilot gives the other only its defensive
// share (10% of its power share), so its paths become rare.
TEST(VplSamplers, PowerPilotFindsTheVisibleLight) {
    // The camera (at z = -5, looking at +z) sees a floor lit by light A; light B sits inside a
    // closed box off to the side, where nothing it lights can be seen.
    std::string world = std::string(vpl_test::kQuadLight) + R"(
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
    "point3 P" [ -3 -1 -3  -3 -1 3  3 -1 3  3 -1 -3 ]
AttributeEnd
AttributeBegin
  Translate 20 0 0
  AreaLightSource "diffuse" "rgb L" [ 1 2 3 ]
  Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
  Shape "sphere" "float radius" [ 0.5 ]
AttributeEnd
AttributeBegin
  Translate 20 0 0
  ReverseOrientation
  Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
  Shape "sphere" "float radius" [ 1 ]
AttributeEnd
)";
    SceneDesc desc = parse_scene_string(
        "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [ 45 ]\n"
        "Film \"rgb\" \"integer xresolution\" [ 8 ] \"integer yresolution\" [ 8 ]\nWorldBegin\n" +
            world,
        ".");
    Scene scene(desc);
    bool ok = false;
    Transform to_world = Transform::look_at({0, 0, -5}, {0, 0, 0}, {0, 1, 0}, &ok).inverse();
    PerspectiveCamera camera(ParameterList(), to_world, 8, 8);
    ASSERT_EQ(scene.lights().size(), 2u);
    VplOptions o;
    o.count = 256;
    o.max_depth = 2;
    o.seed = 3;
    std::vector<float> pmf = power_light_pmf(scene, camera, o);
    ASSERT_EQ(pmf.size(), 2u);
    double power_a = scene.lights()[0]->power().luminance(),
           power_b = scene.lights()[1]->power().luminance();
    EXPECT_NEAR(pmf[1], 0.1 * power_b / (power_a + power_b), 1e-4);
    EXPECT_NEAR(pmf[0] + pmf[1], 1.0, 1e-5);
}

// The Cornell box (shared) at 16x16: power and bidirectional agree with standard, per channel,
// over the image and over its quarters.
TEST(VplSamplers, CornellBoxAgreesWithStandard) {
    ML_NEED_SHARED("scenes/cornell-box/scene-v4.pbrt");
    SceneDesc desc = parse_scene_file(test::shared_path("scenes/cornell-box/scene-v4.pbrt"));
    auto render = [&](const char* sampler) {
        return over_seeds(8, [&](uint64_t seed) {
            RenderOptions opt = vpl_options(sampler, seed, 128, 1);
            opt.width = opt.height = 16;
            return render_scene(desc, opt).image;
        });
    };
    SeedStats standard = render("standard");
    expect_same_mean(render("power"), standard, "power");
    expect_same_mean(render("bidirectional"), standard, "bidirectional");
}

// Same seed, one thread or two: the same image.
TEST(VplSamplers, DeterministicAtAnyThreadCount) {
    for (const char* sampler : {"power", "bidirectional"}) {
        RenderOptions opt = vpl_options(sampler, 5, 64, 1);
        opt.threads = 1;
        Image a = render_text(test::furnace_scene(0.5f, 1.f, 8), opt).image;
        opt.threads = 2;
        Image b = render_text(test::furnace_scene(0.5f, 1.f, 8), opt).image;
        ASSERT_EQ(a.pixels.size(), b.pixels.size());
        for (size_t i = 0; i < a.pixels.size(); ++i) EXPECT_EQ(a.pixels[i], b.pixels[i]) << sampler;
    }
}

}  // namespace
}  // namespace ml
