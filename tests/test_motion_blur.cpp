// Motion blur: pbrt-v4's ActiveTransform and TransformTimes, animated transforms, moving meshes in
// Embree, the moving camera; an analytic check (a black sphere crossing a white background covers
// the centre of the image for a known share of the shutter); and, for every integrator, the
// motion-blurred render against the average of renders frozen at times spread over the shutter.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "bidir_test_helpers.h"
#include "core/animated_transform.h"
#include "core/rng.h"
#include "geometry/embree_scene.h"
#include "parser_test_helpers.h"
#include "render_helpers.h"
#include "shared_files.h"

using namespace ml;
using ml::test::expect_scene_error;

namespace {

void expect_near_transform(const Transform& a, const Transform& b, float tol) {
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(a.m(r, c), b.m(r, c), tol) << r << "," << c;
}

}  // namespace

TEST(AnimatedTransform, KeyframesHoldOutsideTheirTimes) {
    Transform a = Transform::translate({1, 2, 3}) * Transform::rotate(30, {0, 1, 0});
    Transform b = Transform::translate({-1, 0, 5}) * Transform::scale({2, 2, 2});
    AnimatedTransform m(a, 1.f, b, 3.f);
    EXPECT_TRUE(m.is_animated());
    expect_near_transform(m.at(0.f), a, 1e-6f);
    expect_near_transform(m.at(1.f), a, 1e-6f);
    expect_near_transform(m.at(3.f), b, 1e-6f);
    expect_near_transform(m.at(9.f), b, 1e-6f);
    EXPECT_FALSE(AnimatedTransform(a, 0, a, 1).is_animated());
}

TEST(AnimatedTransform, InterpolatesTranslationRotationAndScaleSeparately) {
    // Start: identity; end: a turn of 80 degrees about a tilted axis, a scale and a move. Half
    // way: half the turn (a rotation made independently), the mean scale, the mean move.
    Vec3 axis = normalize(Vec3(1, 2, 0.5f));
    Transform end = Transform::translate({4, -2, 6}) * Transform::rotate(80, axis) *
                    Transform::scale({3, 3, 3});
    AnimatedTransform m(Transform(), 0, end, 1);
    Transform half = Transform::translate({2, -1, 3}) * Transform::rotate(40, axis) *
                     Transform::scale({2, 2, 2});
    expect_near_transform(m.at(0.5f), half, 2e-5f);
    Transform quarter = Transform::translate({1, -0.5f, 1.5f}) * Transform::rotate(20, axis) *
                        Transform::scale({1.5f, 1.5f, 1.5f});
    expect_near_transform(m.at(0.25f), quarter, 2e-5f);
    EXPECT_NEAR(m.rotation_angle(), radians(80.f), 1e-4f);
}

TEST(MotionParser, ActiveTransformSetsEitherEnd) {
    SceneDesc d = parse_scene_string(R"(
TransformTimes 2 4
ActiveTransform StartTime
Translate 1 0 0
ActiveTransform EndTime
Translate 0 3 0
ActiveTransform All
Camera "perspective"
WorldBegin
AttributeBegin
  ActiveTransform EndTime
  Translate 0 0 5
AttributeEnd
Translate 0 0 -1
Shape "sphere" "float radius" 1
)",
                                     ".");
    EXPECT_EQ(d.transform_start_time, 2.f);
    EXPECT_EQ(d.transform_end_time, 4.f);
    EXPECT_NEAR(d.world_to_camera.point({0, 0, 0}).x, 1.f, 1e-6f);
    EXPECT_NEAR(d.world_to_camera_end.point({0, 0, 0}).y, 3.f, 1e-6f);
    // AttributeEnd restored ActiveTransform All, so the sphere moved at both ends: it is still.
    ASSERT_EQ(d.meshes.size(), 1u);
    EXPECT_FALSE(d.meshes[0]->moves());
}

TEST(MotionParser, MovingShapesAndInstancesGetTimeSteps) {
    SceneDesc d = parse_scene_string(R"(
Camera "perspective"
WorldBegin
AttributeBegin
  ActiveTransform EndTime
  Translate 2 0 0
  Shape "sphere" "float radius" 1
AttributeEnd
ObjectBegin "ball"
  Shape "sphere" "float radius" 0.5
ObjectEnd
AttributeBegin
  ActiveTransform EndTime
  Rotate 90 0 0 1
  ActiveTransform All
  Translate 3 0 0
  ObjectInstance "ball"
AttributeEnd
)",
                                     ".");
    ASSERT_EQ(d.meshes.size(), 2u);
    const TriangleMesh& a = *d.meshes[0];
    ASSERT_TRUE(a.moves());
    EXPECT_EQ(a.motion_steps, 2);  // a translation is exact in one segment
    const size_t nv = a.p.size();
    EXPECT_NEAR(a.motion_p[nv + 0].x - a.motion_p[0].x, 2.f, 1e-5f);
    // The instance turns 90 degrees about z around the world origin: 45 segments of 2 degrees.
    // Its end transform R T(3, 0, 0) decomposes into the translation (0, 3, 0) and R, and pbrt's
    // AnimatedTransform moves translations linearly: the centre follows the chord from (3, 0, 0)
    // to (0, 3, 0), not the arc.
    const TriangleMesh& b = *d.meshes[1];
    ASSERT_TRUE(b.moves());
    EXPECT_EQ(b.motion_steps, 46);
    auto centre = [&](int step) {
        Bounds3 bb;
        for (size_t i = 0; i < b.p.size(); ++i)
            bb.expand(b.motion_p[size_t(step) * b.p.size() + i]);
        return bb.center();
    };
    EXPECT_NEAR(centre(0).x, 3.f, 1e-3f);
    EXPECT_NEAR(centre(45).y, 3.f, 1e-3f);
    Vec3 c20 = centre(20);
    EXPECT_NEAR(c20.x, 3.f * 25 / 45, 1e-3f);
    EXPECT_NEAR(c20.y, 3.f * 20 / 45, 1e-3f);
}

TEST(MotionParser, BadInput) {
    expect_scene_error("ActiveTransform Sometimes\n", 1, 17, "expected StartTime, EndTime or All");
    expect_scene_error("ActiveTransform \"All\"\n", 1, 17, "expects StartTime, EndTime or All");
    expect_scene_error("TransformTimes 1 0.5\n", 1, 1,
                       "the end time must be greater than the start time");
    expect_scene_error("WorldBegin\nTransformTimes 0 1\n", 2, 1, "not allowed after WorldBegin");
    expect_scene_error(
        "WorldBegin\nActiveTransform EndTime\nTranslate 1 0 0\nLightSource \"point\"\n", 4, 1,
        "moving lights are not supported");
    expect_scene_error(
        "WorldBegin\nAttributeBegin\nAreaLightSource \"diffuse\"\nActiveTransform EndTime\n"
        "Translate 1 0 0\nShape \"sphere\"\nAttributeEnd\n",
        6, 1, "cannot be an area light");
    // The camera's parameters are read when the render starts.
    ml::test::expect_input_error(
        [] {
            test::render_text(
                "Camera \"perspective\" \"float shutteropen\" 1 "
                "\"float shutterclose\" 0\nWorldBegin\n",
                RenderOptions());
        },
        "<string>", 1, 1, "must not be less than");
}

TEST(MotionEmbree, RaysSeeTheMeshWhereItIsAtTheirTime) {
    // A unit quad in the plane z = 0 moving from x = 0 to x = 4 over the times [1, 3].
    TriangleMesh m;
    m.p = {{-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0}};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.motion_steps = 2;
    for (int k = 0; k < 2; ++k)
        for (const Vec3& p : m.p) m.motion_p.push_back(p + Vec3(4.f * k, 0, 0));
    EmbreeScene scene({&m}, 1.f, 3.f);
    auto hit_at = [&](float x, float time) {
        SurfaceInteraction si;
        bool hit = scene.intersect(Ray{{x, 0.25f, 5}, {0, 0, -1}, kInfinity, time}, &si);
        if (hit) {
            EXPECT_NEAR(si.p.x, x, 1e-5f);
            EXPECT_NEAR(si.p.z, 0.f, 1e-5f);
            EXPECT_EQ(si.time, time);
        }
        EXPECT_EQ(hit, scene.occluded(Ray{{x, 0.25f, 5}, {0, 0, -1}, kInfinity, time}));
        return hit;
    };
    EXPECT_TRUE(hit_at(0.f, 0.f));  // before the start time: where it starts
    EXPECT_TRUE(hit_at(0.f, 1.f));
    EXPECT_FALSE(hit_at(0.f, 2.f));  // at 2 the quad spans x in [1.5, 2.5]
    EXPECT_TRUE(hit_at(2.4f, 2.f));
    EXPECT_FALSE(hit_at(2.6f, 2.f));
    EXPECT_TRUE(hit_at(4.f, 3.f));
    EXPECT_TRUE(hit_at(4.f, 7.f));  // after the end time: where it ends
    EXPECT_FALSE(hit_at(0.f, 7.f));
    EXPECT_GE(scene.bounds().hi.x, 4.5f);
}

namespace {

// A black sphere of radius 0.25 crossing a white background (a uniform infinite light) in front
// of a camera with a tiny field of view, from x = -1 to x = 1 over the transform times [0, 1]:
// the single pixel's ray, along the axis, meets it while |x| < 0.25. The pixel's value is the
// share of the shutter during which the sphere is elsewhere.
// With `area_light`, the background is an emitting square (L = 1, facing the camera) behind the
// sphere instead, which every integrator renders (Metropolis ones have no infinite lights).
std::string crossing_scene(float open, float close, bool camera_moves, bool area_light = false) {
    std::string camera = camera_moves ? "ActiveTransform StartTime\nTranslate -1 0 0\n"
                                        "ActiveTransform EndTime\nTranslate 1 0 0\n"
                                        "ActiveTransform All\n"
                                      : "";
    std::string sphere = camera_moves ? ""
                                      : "ActiveTransform StartTime\nTranslate -1 0 0\n"
                                        "ActiveTransform EndTime\nTranslate 1 0 0\n"
                                        "ActiveTransform All\n";
    return fmt::format(R"(
LookAt 0 0 5  0 0 0  0 1 0
{}Camera "perspective" "float fov" [ 0.01 ] "float shutteropen" [ {} ] "float shutterclose" [ {} ]
Film "rgb" "integer xresolution" [ 1 ] "integer yresolution" [ 1 ]
Sampler "independent"
PixelFilter "box"
WorldBegin
{}
AttributeBegin
{}  Material "diffuse" "rgb reflectance" [ 0 0 0 ]
  Shape "sphere" "float radius" 0.25
AttributeEnd
)",
                       camera, open, close,
                       area_light ? "AttributeBegin\n  AreaLightSource \"diffuse\" \"rgb L\" "
                                    "[ 1 1 1 ]\n  Translate 0 0 -2\n  Shape \"bilinearmesh\" "
                                    "\"point3 P\" [ -4 -4 0  4 -4 0  -4 4 0  4 4 0 ]\n"
                                    "AttributeEnd"
                                  : "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]",
                       sphere);
}

}  // namespace

TEST(MotionAnalytic, SphereCoversThePixelForItsShareOfTheShutter) {
    struct Case {
        float open, close, background;
    };
    // [0, 1]: covered for 0.5 of the 2 units it travels, 1/4 of the time. [0, 0.25]: x in
    // [-1, -0.5], never. [0.375, 0.625]: x in [-0.25, 0.25], always. [0.25, 1]: x in [-0.5, 1],
    // covered for 0.5 of 1.5. [1, 2]: after the end time the sphere stays at x = 1.
    const Case cases[] = {
        {0, 1, 0.75f}, {0, 0.25f, 1.f}, {0.375f, 0.625f, 0.f}, {0.25f, 1, 2.f / 3.f}, {1, 2, 1.f}};
    for (bool camera_moves : {false, true})
        for (const Case& c : cases) {
            RenderOptions opt;
            opt.integrator = "path";
            opt.spp = 4096;
            opt.seed = 1;
            Image img = test::render_text(crossing_scene(c.open, c.close, camera_moves), opt).image;
            // Each sample is 0 or 1: the mean of 4096 has a standard error of at most 0.008.
            // The film takes the exposure time, the shutter's length, as pbrt-v4's does.
            EXPECT_NEAR(img.at(0, 0).g / (c.close - c.open), c.background, 0.04f)
                << "shutter [" << c.open << ", " << c.close << "], camera moves " << camera_moves;
        }
}

TEST(MotionAnalytic, EveryIntegratorSeesTheSphereForItsShareOfTheShutter) {
    // The same crossing in front of an emitting square, shutter [0, 1]: 3/4 of the time the
    // pixel sees the square. In a one-pixel image a Metropolis render is its bootstrap's
    // estimate of the image's mean, so this checks that their paths draw their times. (Not the
    // light tracer: its paths would almost never land on a film this narrow.)
    const std::pair<const char*, std::map<std::string, std::string>> cases[] = {
        {"path", {}},
        {"bdpt", {}},
        {"mlt", {{"mlt.bootstrap", "20000"}, {"mlt.chains", "16"}}},
        {"pssmlt", {{"pssmlt.bootstrap", "20000"}, {"pssmlt.chains", "16"}}},
        {"vpl", {{"vpl.count", "100"}}},
        {"lightcuts", {{"vpl.count", "100"}}}};
    for (const auto& [integrator, set] : cases) {
        RenderOptions opt;
        opt.integrator = integrator;
        opt.spp = 4096;
        opt.seed = 1;
        opt.max_depth = 1;
        opt.set = set;
        Image img = test::render_text(crossing_scene(0, 1, false, true), opt).image;
        // Standard error at most 0.008 for 4096 samples of 0 or 1; 0.04 is five of them.
        EXPECT_NEAR(img.at(0, 0).g, 0.75f, 0.04f) << integrator;
    }
}

namespace {

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// The shared motion-blur Cornell box, its pixel filter a box (a sample reaches one pixel, which
// keeps per-pixel noise estimates honest) and its shutter [open, close].
std::string motion_box(const std::string& text, float open, float close) {
    std::string t = text;
    auto replace = [&](const std::string& from, const std::string& to) {
        size_t at = t.find(from);
        if (at == std::string::npos) throw std::runtime_error("motion_box: no " + from);
        t.replace(at, from.size(), to);
    };
    replace(R"("float shutteropen" [ 0 ] "float shutterclose" [ 1 ])",
            fmt::format(R"("float shutteropen" [ {} ] "float shutterclose" [ {} ])", open, close));
    replace(R"(PixelFilter "gaussian" "float xradius" [ 1.5 ] "float yradius" [ 1.5 ])",
            R"(PixelFilter "box")");
    return t;
}

struct MotionCase {
    std::string integrator;
    int spp;
    std::map<std::string, std::string> set;
};

// Runs of the motion-blurred render against runs of the average of `frozen` renders, each at a
// time drawn in its own stratum of the shutter (a fresh draw per run), at spp / frozen samples
// each: both estimate the motion-blurred image, so they must agree within noise (the runs'
// spread includes the frozen times' own variance).
void expect_blur_is_average_of_frozen(const MotionCase& mc) {
    const std::string text =
        read_text(test::shared_path("scenes/cornell-box/scene-motion-blur.pbrt"));
    const int res = 16, depth = 3, runs = 3, frozen = 8;
    test::TwoRenders blurred =
        test::render_twice(motion_box(text, 0, 1), mc.integrator, mc.spp, depth, res, mc.set, runs);
    test::TwoRenders average;
    Rng jitter(12345);
    for (int r = 0; r < runs; ++r) {
        Image sum;
        for (int k = 0; k < frozen; ++k) {
            float t = (float(k) + jitter.next_float()) / float(frozen);
            RenderOptions opt;
            opt.integrator = mc.integrator;
            opt.spp = std::max(1, mc.spp / frozen);
            opt.max_depth = depth;
            opt.width = opt.height = res;
            opt.seed = uint64_t(1000 + r * frozen + k);
            opt.sampler = "independent";
            opt.set = mc.set;
            Image img = test::render_text(motion_box(text, t, t), opt).image;
            if (k == 0) {
                sum = img;
            } else {
                for (size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += img.pixels[i];
            }
        }
        for (RGB& p : sum.pixels) p = p / float(frozen);
        if (r == 0)
            average.a = std::move(sum);
        else if (r == 1)
            average.b = std::move(sum);
        else
            average.more.push_back(std::move(sum));
    }
    test::expect_agreement(blurred, average, 8, mc.integrator + ": blurred vs frozen average");
    // And the motion shows: the blurred image differs from the scene frozen at its start.
    test::TwoRenders start =
        test::render_twice(motion_box(text, 0, 0), mc.integrator, mc.spp, depth, res, mc.set, runs);
    test::Agreement a = test::agreement(blurred, start, 8);
    // (Metropolis renders this small are too noisy for it, and so is vpl with the few VPLs that
    // keep it fast: their time is checked by the analytic test above, and lightcuts shades
    // through the same gather code with more VPLs.)
    if (mc.integrator != "mlt" && mc.integrator != "pssmlt" && mc.integrator != "vpl") {
        EXPECT_GT(a.worst_block_z, 6.0) << mc.integrator << ": the blur does not show";
    }
}

}  // namespace

class MotionBlurEveryIntegrator : public ::testing::TestWithParam<MotionCase> {};

TEST_P(MotionBlurEveryIntegrator, BlurredRenderIsTheAverageOfFrozenRenders) {
    ML_NEED_SHARED("scenes/cornell-box/scene-motion-blur.pbrt");
    expect_blur_is_average_of_frozen(GetParam());
}

INSTANTIATE_TEST_SUITE_P(
    Integrators, MotionBlurEveryIntegrator,
    ::testing::Values(MotionCase{"path", 64, {}}, MotionCase{"bdpt", 64, {}},
                      MotionCase{"lighttracer", 64, {}},
                      MotionCase{"mlt", 64, {{"mlt.bootstrap", "20000"}, {"mlt.chains", "64"}}},
                      MotionCase{
                          "pssmlt", 64, {{"pssmlt.bootstrap", "20000"}, {"pssmlt.chains", "64"}}},
                      MotionCase{"vpl", 16, {{"vpl.count", "300"}, {"vpl.clamp", "0"}}},
                      MotionCase{"lightcuts", 16, {{"vpl.count", "1000"}, {"vpl.clamp", "0"}}}),
    [](const ::testing::TestParamInfo<MotionCase>& info) { return info.param.integrator; });
