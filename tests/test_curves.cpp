// pbrt-v4's "curve" shape through Embree's curves: the (u, v) and the normals pbrt-v4 gives at a
// hit, every basis and degree reaching the same cubic, and the refusals.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "geometry/curves.h"
#include "scene/scene.h"
#include "scene/scene_desc.h"

using namespace ml;

namespace {

std::string scene_with(const std::string& shapes) {
    return "Camera \"perspective\"\nFilm \"rgb\" \"integer xresolution\" [ 2 ] \"integer "
           "yresolution\" [ 2 ]\nWorldBegin\n" +
           shapes + "\n";
}

Scene load(const std::string& shapes) {
    return Scene(parse_scene_string(scene_with(shapes), ".", "test.pbrt"));
}

void expect_error(const std::string& shapes, int line, const std::string& fragment) {
    try {
        parse_scene_string(scene_with(shapes), ".", "test.pbrt");
        ADD_FAILURE() << "accepted: " << shapes;
    } catch (const InputError& e) {
        EXPECT_EQ(e.loc().line, line + 3) << e.formatted();
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.formatted();
    }
}

// A straight curve along x from -1 to 1 at z = 0 (control points evenly spaced: u = (x + 1) / 2).
const char* kStraight = "\"point3 P\" [ -1 0 0  -0.3333333 0 0  0.3333333 0 0  1 0 0 ]";

}  // namespace

TEST(Curves, FlatHitHasPbrtUvAndFacesAlongTheRay) {
    Scene s = load(std::string("Shape \"curve\" ") + kStraight + " \"float width\" [ 0.2 ]");
    SurfaceInteraction si;
    // Seen along +y, 0.05 above the axis at x = 0.5.
    ASSERT_TRUE(s.intersect(Ray{Vec3(0.5f, -5, 0.05f), Vec3(0, 1, 0)}, &si));
    EXPECT_NEAR(si.t, 5, 1e-3);
    EXPECT_NEAR(si.uv.x, 0.75f, 1e-3);
    // pbrt-v4: v grows along cross(d, dp/du) = -z: 0.05 above the axis is v = 0.5 - 0.05 / 0.2.
    EXPECT_NEAR(si.uv.y, 0.25f, 1e-3);
    // n = dp/du x dp/dv, dp/dv along -z: the normal is +y, along the ray.
    EXPECT_NEAR(si.ng.y, 1, 1e-4);
    EXPECT_NEAR(si.ns.y, 1, 1e-4);
    EXPECT_NEAR(si.dpdu.x, 2, 1e-3);
    // Beyond half the width: a miss.
    EXPECT_FALSE(s.intersect(Ray{Vec3(0.5f, -5, 0.11f), Vec3(0, 1, 0)}, &si));
    // Seen from above, it faces the ray there too.
    ASSERT_TRUE(s.intersect(Ray{Vec3(-0.5f, 0.02f, 3), Vec3(0, 0, -1)}, &si));
    EXPECT_NEAR(si.uv.x, 0.25f, 1e-3);
    EXPECT_NEAR(std::abs(si.ng.z), 1, 1e-4);
}

TEST(Curves, CylinderNormalTurnsAcrossTheWidth) {
    Scene s = load(std::string("Shape \"curve\" \"string type\" \"cylinder\" ") + kStraight +
                   " \"float width\" [ 0.2 ]");
    SurfaceInteraction si;
    ASSERT_TRUE(s.intersect(Ray{Vec3(0, -5, 0), Vec3(0, 1, 0)}, &si));
    EXPECT_NEAR(si.uv.y, 0.5f, 1e-3);
    EXPECT_NEAR(si.ng.y, 1, 1e-4);
    // v = 0.25: theta = -45 degrees, dp/dv (-z) turned by +45 degrees about +x.
    ASSERT_TRUE(s.intersect(Ray{Vec3(0, -5, 0.05f), Vec3(0, 1, 0)}, &si));
    EXPECT_NEAR(si.uv.y, 0.25f, 1e-3);
    EXPECT_NEAR(si.ng.y, std::sqrt(0.5f), 1e-3);
    EXPECT_NEAR(std::abs(si.ng.z), std::sqrt(0.5f), 1e-3);
    // The edges' normals lie across the ray: a round tube's silhouette.
    ASSERT_TRUE(s.intersect(Ray{Vec3(0, -5, 0.0999f), Vec3(0, 1, 0)}, &si));
    EXPECT_LT(std::abs(si.ng.y), 0.01f);
}

TEST(Curves, RibbonFollowsItsNormals) {
    // Facing -y at u = 0, turning to +z at u = 1: seen along +y it narrows to nothing.
    Scene s = load(std::string("Shape \"curve\" \"string type\" \"ribbon\" ") + kStraight +
                   " \"normal N\" [ 0 -1 0  0 0 1 ] \"float width\" [ 0.2 ]");
    SurfaceInteraction si;
    ASSERT_TRUE(s.intersect(Ray{Vec3(-0.9f, -5, 0.05f), Vec3(0, 1, 0)}, &si));
    EXPECT_GT(std::abs(si.ng.y), 0.95f);
    EXPECT_FALSE(s.intersect(Ray{Vec3(0.99f, -5, 0.05f), Vec3(0, 1, 0)}, &si));
    // Halfway the ribbon's normal is (0, -1, 1) / sqrt 2.
    ASSERT_TRUE(s.intersect(Ray{Vec3(0, -5, 0.01f), Vec3(0, 1, 0)}, &si));
    EXPECT_NEAR(std::abs(si.ng.y), std::sqrt(0.5f), 2e-2);
    EXPECT_NEAR(std::abs(si.ng.z), std::sqrt(0.5f), 2e-2);
}

TEST(Curves, BasesAndDegreesGiveTheSameCubic) {
    // One parabola z = 1 - x^2 over [-1, 1] written four ways: quadratic Bezier, quadratic
    // B-spline (de Boor points whose midpoints are the Bezier ends), and as a cubic.
    const char* forms[] = {
        "\"integer degree\" [ 2 ] \"point3 P\" [ -1 0 0  0 0 2  1 0 0 ]",
        "\"integer degree\" [ 2 ] \"string basis\" \"bspline\" \"point3 P\" [ -2 0 -2  0 0 2  2 0 "
        "-2 ]",
        "\"point3 P\" [ -1 0 0  -0.3333333 0 1.3333333  0.3333333 0 1.3333333  1 0 0 ]",
    };
    for (const char* f : forms) {
        SCOPED_TRACE(f);
        Scene s = load(std::string("Shape \"curve\" ") + f + " \"float width\" [ 0.05 ]");
        SurfaceInteraction si;
        for (float x : {-0.6f, 0.f, 0.3f}) {
            ASSERT_TRUE(s.intersect(Ray{Vec3(x, -5, 1 - x * x), Vec3(0, 1, 0)}, &si));
            EXPECT_NEAR(si.p.z, 1 - x * x, 2e-3);
            EXPECT_NEAR(si.uv.x, (x + 1) / 2, 2e-3);
        }
    }
    // A cubic B-spline of five points: two segments, u restarting at each.
    Scene s = load(
        "Shape \"curve\" \"string basis\" \"bspline\" \"point3 P\" [ -2 0 0  -1 0 0  0 0 0  1 0 0 "
        " 2 0 0 ] \"float width\" [ 0.1 ]");
    SurfaceInteraction si;
    ASSERT_TRUE(s.intersect(Ray{Vec3(-0.5f, -5, 0), Vec3(0, 1, 0)}, &si));
    EXPECT_NEAR(si.uv.x, 0.5f, 2e-3);  // the first segment spans x in [-1, 0]
    EXPECT_EQ(si.prim_id, 0u);
    ASSERT_TRUE(s.intersect(Ray{Vec3(0.25f, -5, 0), Vec3(0, 1, 0)}, &si));
    EXPECT_NEAR(si.uv.x, 0.25f, 2e-3);
    EXPECT_EQ(si.prim_id, 1u);
}

TEST(Curves, WidthTapersAndScalesWithTheTransform) {
    // width0 1 to width1 0.2 over two segments: 0.6 in the middle, then doubled by Scale 2.
    Scene s = load(
        "Scale 2 2 2\nShape \"curve\" \"point3 P\" [ -1 0 0  -0.6666667 0 0  -0.3333333 0 0  0 0 0"
        "  0.3333333 0 0  0.6666667 0 0  1 0 0 ] \"float width0\" [ 1 ] \"float width1\" [ 0.2 ]");
    SurfaceInteraction si;
    EXPECT_TRUE(s.intersect(Ray{Vec3(0, -5, 0.59f), Vec3(0, 1, 0)}, &si));
    EXPECT_FALSE(s.intersect(Ray{Vec3(0, -5, 0.61f), Vec3(0, 1, 0)}, &si));
}

TEST(Curves, BadInputIsRefusedAtItsPlace) {
    expect_error("Shape \"curve\" \"point3 P\" [ 0 0 0  1 0 0 ]", 1, "control points");
    expect_error("Shape \"curve\" \"integer degree\" [ 4 ] \"point3 P\" [ 0 0 0  1 0 0  2 0 0 ]", 1,
                 "degree");
    expect_error("Shape \"curve\" \"string basis\" \"hermite\" \"point3 P\" [ 0 0 0  1 0 0 ]", 1,
                 "basis");
    expect_error(std::string("Shape \"curve\" \"string type\" \"tube\" ") + kStraight, 1, "type");
    expect_error(std::string("Shape \"curve\" \"string type\" \"ribbon\" ") + kStraight, 1,
                 "normal N");
    expect_error(std::string("Shape \"curve\" \"string type\" \"ribbon\" ") + kStraight +
                     " \"normal N\" [ 0 1 0 ]",
                 1, "2 are needed");
    expect_error(std::string("Shape \"curve\" \"float width\" [ -1 ] ") + kStraight, 1, "negative");
    expect_error(std::string("AreaLightSource \"diffuse\"\nShape \"curve\" ") + kStraight, 2,
                 "not supported");
    expect_error(std::string("Shape \"curve\" \"texture alpha\" \"holes\" ") + kStraight, 1,
                 "undefined float texture \"holes\"");
    expect_error(std::string("Shape \"curve\" \"float radius\" [ 0.5 ] ") + kStraight, 1, "radius");
}
