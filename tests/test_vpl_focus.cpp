// The VPLs' emission focus (vpl.focus, VplOptions::focus_*; on by default for `vpl` and `igi`):
// distant and infinite lights start a share of their light paths on the shadow of a sphere around what the camera sees, and weigh
// every path by the mixture's density. A sphere on a ground plane hundreds of metres across, lit
// by the sun and the sky: without the focus, about one light path in ten thousand lands where the
// camera looks.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
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

namespace ml {
namespace {

using test::render_text;

const char* const kSunlitSphere = R"(
LookAt 0 2.5 -3  0 0.3 0  0 1 0
Camera "perspective" "float fov" [ 50 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 12 ]
Sampler "independent"
PixelFilter "box"
WorldBegin
LightSource "distant" "point3 from" [ 1 3 -1 ] "point3 to" [ 0 0 0 ] "rgb L" [ 3 3 3 ]
LightSource "infinite" "rgb L" [ 0.3 0.4 0.6 ]
Material "diffuse" "rgb reflectance" [ 0.4 0.5 0.6 ]
Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
  "point3 P" [ -200 0 -200  -200 0 200  200 0 200  200 0 -200 ]
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.8 0.5 0.3 ]
  Translate 0 0.5 0
  Shape "sphere" "float radius" [ 0.5 ]
AttributeEnd
)";

// Per seed, the image's mean of each channel.
using SeedMeans = std::vector<std::array<double, 3>>;

SeedMeans image_means(RenderOptions opt, int seeds) {
    SeedMeans m;
    const int first = std::getenv("ML_SEED_BASE") ? std::atoi(std::getenv("ML_SEED_BASE")) : 1;
    for (int s = first; s < first + seeds; ++s) {
        opt.seed = uint64_t(s);
        Image img = render_text(kSunlitSphere, opt).image;
        std::array<double, 3> v{};
        for (const RGB& p : img.pixels)
            for (int c = 0; c < 3; ++c) v[size_t(c)] += p[c];
        for (double& x : v) x /= double(img.pixels.size());
        m.push_back(v);
    }
    return m;
}

// Mean and standard error over the seeds of channel c.
std::pair<double, double> seed_mean(const SeedMeans& a, int c) {
    double s = 0, s2 = 0, n = double(a.size());
    for (const auto& v : a) s += v[size_t(c)], s2 += v[size_t(c)] * v[size_t(c)];
    double mean = s / n;
    return {mean, std::sqrt(std::max(0.0, s2 / n - mean * mean) / (n - 1))};
}

RenderOptions vpl_render(const std::string& focus) {
    RenderOptions opt;
    opt.integrator = "vpl";
    opt.spp = 4;
    opt.max_depth = 2;  // one bounce: the VPLs' light and the direct light
    opt.threads = 2;
    opt.set["vpl.count"] = "2000";
    opt.set["vpl.focus"] = focus;
    return opt;
}

TEST(VplFocus, ShareMustBeBelowOne) {
    for (const char* bad : {"-0.1", "1", "2"}) {
        RenderOptions opt = vpl_render(bad);
        opt.seed = 1;
        EXPECT_THROW(render_text(kSunlitSphere, opt), UsageError) << bad;
    }
}

TEST(VplFocus, FindsWhatTheCameraSees) {
    SceneDesc desc = parse_scene_string(kSunlitSphere, ".");
    AnimatedTransform to_world = desc.camera_to_world();
    ParameterList lens = desc.camera.params;
    Scene scene(std::move(desc));
    PerspectiveCamera camera(lens, to_world, 16, 12);
    Vec3 c;
    float r = 0;
    ASSERT_TRUE(camera_focus_sphere(scene, camera, 1024, 7, &c, &r));
    // The camera sees the sphere and the ground up to about 9.5 m past it (the image's top edge
    // is 11 degrees below the horizon): a sphere of a few metres there, not the ground plane's.
    EXPECT_GT(r, 3.f);
    EXPECT_LT(r, 10.f);
    EXPECT_LT(length(c - Vec3(0, 0, 3)), 2.f);
    // With the camera's default field of view (90 degrees) the image reaches past the horizon:
    // the middle 90% of what it sees spreads further.
    PerspectiveCamera wide(ParameterList(), to_world, 16, 12);
    float r_wide = 0;
    ASSERT_TRUE(camera_focus_sphere(scene, wide, 1024, 7, &c, &r_wide));
    EXPECT_GT(r_wide, 2 * r);
}

// The share of a set's VPLs inside the focus sphere, with and without the focus: half the sun's
// and sky's paths start towards it, where without it about one in ten thousand lands there.
TEST(VplFocus, SendsTheShareOfPathsWhereTheCameraLooks) {
    SceneDesc desc = parse_scene_string(kSunlitSphere, ".");
    AnimatedTransform to_world = desc.camera_to_world();
    ParameterList lens = desc.camera.params;
    Scene scene(std::move(desc));
    PerspectiveCamera camera(lens, to_world, 16, 12);
    Vec3 c;
    float r = 0;
    ASSERT_TRUE(camera_focus_sphere(scene, camera, 1024, 7, &c, &r));
    auto inside_share = [&](float focus) {
        PointLightOptions o;
        o.emitters = false;
        o.vpl_count = 4000;
        o.vpl_max_depth = 1;
        o.seed = 3;
        o.camera = &camera;
        o.vpl_focus = focus;
        PointLightSet set = build_point_light_set(scene, o);
        EXPECT_EQ(set.focus_share, focus);
        size_t inside = 0;
        for (const PointLight& pl : set.lights) inside += length(pl.p - c) < r;
        return double(inside) / double(set.lights.size());
    };
    // The focus sphere's shadow catches a little more than its ground (the sphere's disk over
    // a sun 20 degrees off the vertical), so a little less than half of the paths land inside.
    EXPECT_GT(inside_share(0.5f), 0.3);
    EXPECT_GT(inside_share(0.9f), 0.55);
    EXPECT_LT(inside_share(0.f), 0.01);
}

// The focused VPLs' render against the path tracer's, per channel, over seeds: a wrong mixture
// density (the whole disk's alone, or the focus's alone) is off by orders of magnitude.
TEST(VplFocus, AgreesWithPath) {
    RenderOptions path;
    path.integrator = "path";
    path.spp = 1024;
    path.max_depth = 2;
    path.threads = 2;
    const SeedMeans ref = image_means(path, 4);
    for (const char* share : {"0.5", "0.9"}) {
        const SeedMeans focused = image_means(vpl_render(share), 16);
        for (int c = 0; c < 3; ++c) {
            auto [p, p_se] = seed_mean(ref, c);
            auto [f, f_se] = seed_mean(focused, c);
            std::printf("focus %s channel %d: path %.5f (se %.5f), vpl %.5f (se %.5f)\n", share, c,
                        p, p_se, f, f_se);
            EXPECT_NEAR(f, p, 4 * std::hypot(f_se, p_se)) << share << " channel " << c;
            EXPECT_LT(4 * std::hypot(f_se, p_se), 0.05 * p) << "channel " << c << ": too noisy";
        }
    }
}

}  // namespace
}  // namespace ml
