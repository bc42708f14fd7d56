// The pbrt-v4 parser on good input: transforms, scopes, shapes, orientation, Include, instancing.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "geometry/shapes.h"
#include "parser_test_helpers.h"
#include "scene/scene_desc.h"

using namespace ml;
using ml::test::ScratchDir;

namespace {

void expect_near(const Vec3& a, const Vec3& b, float eps = 1e-4f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

double total_area(const TriangleMesh& m) {
    double a = 0;
    for (size_t t = 0; t < m.triangle_count(); ++t) a += m.triangle_area(t);
    return a;
}

const char* kTriangle =
    "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\n";

}  // namespace

TEST(ParserTransforms, LookAtIsWorldToCamera) {
    SceneDesc d = parse_scene_string(
        "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [45]\nWorldBegin\n",
        ".");
    expect_near(d.world_to_camera.point({0, 0, 0}), {0, 0, 5});
    expect_near(d.world_to_camera.point({0, 1, -5}), {0, 1, 0});
    EXPECT_EQ(d.camera.name, "perspective");
    // Header entities are kept for the renderer, their parameters unread.
    EXPECT_FLOAT_EQ(d.camera.params.get_float("fov", 0), 45.f);
    EXPECT_EQ(d.camera.loc.line, 2);
}

TEST(ParserTransforms, TransformIsTransposed) {
    // pbrt writes matrices column by column: the translation is in the last four numbers.
    SceneDesc d = parse_scene_string(
        "Transform [1 0 0 0  0 1 0 0  0 0 1 0  1 2 3 1]\nCamera \"perspective\"\n", ".");
    expect_near(d.world_to_camera.point({0, 0, 0}), {1, 2, 3});
    SceneDesc c = parse_scene_string(
        "Scale 2 2 2\nConcatTransform [1 0 0 0  0 1 0 0  0 0 1 0  1 2 3 1]\nCamera "
        "\"perspective\"\n",
        ".");
    expect_near(c.world_to_camera.point({0, 0, 0}), {2, 4, 6});
}

TEST(ParserTransforms, NestedScopesRestoreTheTransform) {
    SceneDesc d = parse_scene_string(
        "Translate 1 0 0\nAttributeBegin\n  Translate 0 1 0\n  TransformBegin\n    Scale 3 3 3\n"
        "  TransformEnd\nAttributeEnd\nCamera \"perspective\"\n",
        ".");
    expect_near(d.world_to_camera.point({0, 0, 0}), {1, 0, 0});
    SceneDesc e = parse_scene_string(
        "Translate 1 0 0\nAttributeBegin\n  Rotate 90 0 0 1\n  Identity\n  Translate 0 5 0\n"
        "  Camera \"perspective\"\nAttributeEnd\n",
        ".");
    expect_near(e.world_to_camera.point({0, 0, 0}), {0, 5, 0});
}

TEST(ParserTransforms, CoordSysTransformCamera) {
    SceneDesc d = parse_scene_string(
        "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\nAttributeBegin\n"
        "CoordSysTransform \"camera\"\n" +
            std::string(kTriangle) + "AttributeEnd\n",
        ".");
    ASSERT_EQ(d.meshes.size(), 1u);
    // The camera sits at z = -5: the triangle is placed in its frame.
    expect_near(d.meshes[0]->p[0], {0, 0, -5});
}

TEST(ParserShapes, TriangleMeshInWorldSpace) {
    SceneDesc d = parse_scene_string(
        "WorldBegin\nAttributeBegin\nTranslate 0 0 2\nScale 2 2 2\n"
        "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\n"
        "  \"normal N\" [0 0 1 0 0 1 0 0 1] \"point2 uv\" [0 0 1 0 0 1]\nAttributeEnd\n" +
            std::string(kTriangle),
        ".");
    ASSERT_EQ(d.meshes.size(), 2u);
    const TriangleMesh& m = *d.meshes[0];
    expect_near(m.p[1], {2, 0, 2});
    expect_near(m.n[0], {0, 0, 1});
    EXPECT_EQ(m.uv.size(), 3u);
    EXPECT_FALSE(m.flip_normals);
    ASSERT_NE(m.material, nullptr);  // the default material
    EXPECT_EQ(m.material, d.meshes[1]->material);
    expect_near(d.meshes[1]->p[1], {1, 0, 0});
}

TEST(ParserShapes, ThreeVerticesNeedNoIndices) {
    SceneDesc d = parse_scene_string(
        "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n", ".");
    ASSERT_EQ(d.meshes.size(), 1u);
    EXPECT_EQ(d.meshes[0]->indices.size(), 3u);
}

TEST(ParserShapes, SphereAreaAndNormals) {
    ParameterList p;
    p.add(Param{"float", "radius", {}, {2.0}, {}, {}});
    auto m = make_sphere(p, {});
    EXPECT_NEAR(total_area(*m), 4 * kPi * 4, 4 * kPi * 4 * 2e-3);
    transform_mesh(*m, Transform(), false);
    for (size_t t = 0; t < m->triangle_count(); t += 97) {
        Vec3 c =
            (m->p[m->indices[3 * t]] + m->p[m->indices[3 * t + 1]] + m->p[m->indices[3 * t + 2]]) /
            3.f;
        // Geometric normals face out, as pbrt's sphere.
        EXPECT_GT(dot(m->triangle_normal(t), c), 0.f);
    }
    for (size_t i = 0; i < m->p.size(); i += 31) EXPECT_NEAR(length(m->p[i]), 2.f, 1e-5f);
}

TEST(ParserShapes, PartialSphereArea) {
    ParameterList p;
    p.add(Param{"float", "zmin", {}, {0.0}, {}, {}});
    p.add(Param{"float", "phimax", {}, {180.0}, {}, {}});
    auto m = make_sphere(p, {});
    // A quarter of the unit sphere: the upper half, half way round.
    EXPECT_NEAR(total_area(*m), kPi, kPi * 2e-3);
}

TEST(ParserShapes, DiskArea) {
    ParameterList p;
    p.add(Param{"float", "radius", {}, {3.0}, {}, {}});
    p.add(Param{"float", "innerradius", {}, {1.0}, {}, {}});
    p.add(Param{"float", "height", {}, {0.5}, {}, {}});
    auto m = make_disk(p, {});
    EXPECT_NEAR(total_area(*m), kPi * 8, kPi * 8 * 2e-3);
    transform_mesh(*m, Transform(), false);
    for (size_t t = 0; t < m->triangle_count(); ++t) {
        EXPECT_GT(m->triangle_normal(t).z, 0.99f);
        EXPECT_FLOAT_EQ(m->p[m->indices[3 * t]].z, 0.5f);
    }
}

TEST(ParserShapes, SpheresAndDisksThroughTheParser) {
    SceneDesc d = parse_scene_string(
        "WorldBegin\nTranslate 0 0 1\nShape \"sphere\" \"float radius\" 0.5\n"
        "Shape \"disk\" \"float radius\" [2]\n",
        ".");
    ASSERT_EQ(d.meshes.size(), 2u);
    EXPECT_NEAR(total_area(*d.meshes[0]), kPi, kPi * 2e-3);
    EXPECT_NEAR(total_area(*d.meshes[1]), 4 * kPi, 4 * kPi * 2e-3);
    expect_near(d.meshes[0]->bounds().center(), {0, 0, 1}, 1e-3f);
}

TEST(ParserShapes, ReverseOrientationAndHandedness) {
    auto flips = [](const std::string& prefix) {
        SceneDesc d = parse_scene_string("WorldBegin\n" + prefix + kTriangle, ".");
        return d.meshes.at(0)->flip_normals;
    };
    EXPECT_FALSE(flips(""));
    EXPECT_TRUE(flips("ReverseOrientation\n"));
    EXPECT_TRUE(flips("Scale 1 1 -1\n"));
    EXPECT_FALSE(flips("Scale 1 1 -1\nReverseOrientation\n"));
    EXPECT_FALSE(flips("AttributeBegin ReverseOrientation AttributeEnd\n"));
    // TransformBegin saves only the transform: the orientation flip survives it.
    EXPECT_TRUE(flips("TransformBegin ReverseOrientation TransformEnd\n"));
    // With a sphere: the normals turn inward under ReverseOrientation.
    SceneDesc d = parse_scene_string("WorldBegin\nReverseOrientation\nShape \"sphere\"\n", ".");
    const TriangleMesh& m = *d.meshes.at(0);
    EXPECT_TRUE(m.flip_normals);
    EXPECT_LT(dot(m.triangle_normal(100), m.p[m.indices[300]]), 0.f);
    EXPECT_LT(dot(m.n[100], m.p[100]), 0.f);
}

TEST(ParserInclude, RelativeToTheMainFile) {
    ScratchDir dir;
    std::filesystem::create_directories(dir.file("sub"));
    dir.write("geometry.pbrt", kTriangle);
    // Paths in included files also resolve against the main file's directory (pbrt-v4).
    dir.write("sub/more.pbrt", "Include \"geometry.pbrt\"\n");
    std::string main = dir.write(
        "scene.pbrt",
        "WorldBegin\nInclude \"sub/more.pbrt\"\nTranslate 5 0 0\nImport \"geometry.pbrt\"\n");
    SceneDesc d = parse_scene_file(main);
    ASSERT_EQ(d.meshes.size(), 2u);
    expect_near(d.meshes[1]->p[0], {5, 0, 0});
    EXPECT_EQ(d.base_dir, dir.path());
}

TEST(ParserInstancing, ObjectInstanceCopiesMeshes) {
    SceneDesc d = parse_scene_string(
        "WorldBegin\nObjectBegin \"tri\"\nTranslate 0 0 1\n" + std::string(kTriangle) +
            "ObjectEnd\n"
            "Translate 10 0 0\nObjectInstance \"tri\"\nTranslate 10 0 0\nObjectInstance \"tri\"\n",
        ".");
    ASSERT_EQ(d.meshes.size(), 2u);
    expect_near(d.meshes[0]->p[1], {11, 0, 1});
    expect_near(d.meshes[1]->p[1], {21, 0, 1});
}

TEST(ParserTokens, StringsEscapesCommentsAndNumbers) {
    SceneDesc d = parse_scene_string(
        "# comment\nFilm \"rgb\" \"string filename\" \"a\\\"b\\\\c.exr\" # trailing\n"
        "  \"integer xresolution\" [ +64 ] \"float iso\" -1.5e2 \"bool flag\" true\n"
        "  \"bool other\" \"false\"\n",
        ".");
    EXPECT_EQ(d.film.params.get_string("filename", ""), "a\"b\\c.exr");
    EXPECT_EQ(d.film.params.get_int("xresolution", 0), 64);
    EXPECT_FLOAT_EQ(d.film.params.get_float("iso", 0), -150.f);
    EXPECT_TRUE(d.film.params.get_bool("flag", false));
    EXPECT_FALSE(d.film.params.get_bool("other", true));
    EXPECT_EQ(d.film.params.find("iso")->loc.line, 3);
}

TEST(ParserShapes, BilinearMeshBecomesTwoTriangles) {
    SceneDesc d = parse_scene_string(
        "WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n", ".");
    ASSERT_EQ(d.meshes.size(), 1u);
    EXPECT_EQ(d.meshes[0]->triangle_count(), 2u);
    EXPECT_NEAR(total_area(*d.meshes[0]), 1.0, 1e-6);
    // As pbrt's patch: the normal is cross(p10 - p00, p01 - p00) = +z.
    EXPECT_GT(d.meshes[0]->triangle_normal(0).z, 0.99f);
    EXPECT_GT(d.meshes[0]->triangle_normal(1).z, 0.99f);
}

TEST(ParserInclude, LargeInlineMeshParsesQuickly) {
    // 200k vertices and 100k triangles written inline, as exporters do.
    std::string text = "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [\n";
    const int n = 200000;
    for (int i = 0; i < n; ++i) text += std::to_string(i * 0.001) + " 0.5 -1.25e-1\n";
    text += "] \"integer indices\" [\n";
    for (int i = 0; i + 2 < n; i += 2)
        text +=
            std::to_string(i) + " " + std::to_string(i + 1) + " " + std::to_string(i + 2) + "\n";
    text += "]\n";
    auto t0 = std::chrono::steady_clock::now();
    SceneDesc d = parse_scene_string(text, ".");
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_EQ(d.meshes.size(), 1u);
    EXPECT_EQ(d.meshes[0]->p.size(), size_t(n));
    EXPECT_LT(s, 2.0);
}

TEST(ParserShapes, AttributeGivesDefaultParameters) {
    SceneDesc d = parse_scene_string(
        "WorldBegin\nAttributeBegin\nAttribute \"shape\" \"float radius\" 2 \"float bogus\" 1\n"
        "Shape \"sphere\"\nShape \"sphere\" \"float radius\" 3\nAttributeEnd\nShape \"sphere\"\n",
        ".");
    ASSERT_EQ(d.meshes.size(), 3u);
    EXPECT_NEAR(d.meshes[0]->bounds().hi.z, 2.f, 1e-4f);
    EXPECT_NEAR(d.meshes[1]->bounds().hi.z, 3.f, 1e-4f);
    EXPECT_NEAR(d.meshes[2]->bounds().hi.z, 1.f, 1e-4f);  // the scope ended
}
