// pbrt-v4's "loopsubdiv" shape (src/geometry/loop_subdiv.h) against what its rules imply on
// their own: the limit point of an original vertex, which no number of levels moves (pbrt-v4's
// Warren weights put an octahedron's apex at half its height: Loop's original weights, which
// OpenSubdiv uses, put it at 0.436), the octahedron's symmetry, flat meshes staying flat,
// normals' side, the triangle count, and the errors. tests/test_pbrt_reference.cpp compares a
// render with pbrt-v4's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "geometry/loop_subdiv.h"
#include "parser_test_helpers.h"

using namespace ml;

namespace {

const FileLoc kLoc{"test.pbrt", 1, 1};

const std::vector<Vec3> kOctahedron = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                       {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
const std::vector<uint32_t> kOctahedronFaces = {0, 2, 4, 0, 5, 2, 0, 4, 3, 0, 3, 5,
                                                1, 4, 2, 1, 2, 5, 1, 3, 4, 1, 5, 3};

float max_coordinate(const TriangleMesh& m, int axis) {
    float best = -kInfinity;
    for (const Vec3& p : m.p) best = std::max(best, axis == 0 ? p.x : axis == 1 ? p.y : p.z);
    return best;
}

}  // namespace

TEST(LoopSubdiv, OctahedronApexLimitIsHalfItsHeightAtEveryLevel) {
    // Valence 4: beta = 3/32, gamma = 1 / (4 + 3 / (8 beta)) = 1/8, so the apex's limit is
    // (1 - 4/8) * 1 + 1/8 * (4 equatorial neighbours at height 0) = 0.5; refining first must
    // not move it (the limit masks are the refinement's fixed point).
    for (int levels = 0; levels <= 4; ++levels) {
        SCOPED_TRACE(levels);
        auto m = loop_subdivide(kOctahedron, kOctahedronFaces, levels, kLoc);
        EXPECT_EQ(m->triangle_count(), size_t(8) << (2 * levels));
        for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(max_coordinate(*m, axis), 0.5f, 1e-5f);
        // Convex and centred: every limit normal points in (pbrt-v4's side), unit length.
        for (size_t v = 0; v < m->p.size(); ++v) {
            EXPECT_NEAR(length(m->n[v]), 1.f, 1e-5f);
            ASSERT_LT(dot(m->n[v], normalize(m->p[v])), -0.5f) << v;
        }
    }
}

TEST(LoopSubdiv, LimitNormalsAreTheSurfacesNormals) {
    // At level 4 the surface is smooth: each vertex normal is close to its faces' normals
    // (reversed: pbrt-v4's limit normals face against the winding).
    auto m = loop_subdivide(kOctahedron, kOctahedronFaces, 4, kLoc);
    std::vector<Vec3> face_sum(m->p.size());
    for (size_t t = 0; t < m->triangle_count(); ++t) {
        const Vec3 &a = m->p[m->indices[3 * t]], &b = m->p[m->indices[3 * t + 1]],
                   &c = m->p[m->indices[3 * t + 2]];
        Vec3 n = cross(b - a, c - a);
        for (int k = 0; k < 3; ++k) face_sum[m->indices[3 * t + k]] += n;
    }
    for (size_t v = 0; v < m->p.size(); ++v)
        ASSERT_LT(dot(m->n[v], normalize(face_sum[v])), -0.99f) << v;
}

TEST(LoopSubdiv, FlatMeshStaysFlatWithBoundaries) {
    // A hexagon fan (an interior vertex of valence 6, boundary vertices of valence 3) and a
    // strip beside it: every limit point stays in z = 0, every normal is -z (against the
    // counter-clockwise winding seen from +z), boundary ones included.
    std::vector<Vec3> p = {{0, 0, 0}};
    for (int i = 0; i < 6; ++i) p.push_back({std::cos(kPi * i / 3), std::sin(kPi * i / 3), 0});
    std::vector<uint32_t> idx;
    for (uint32_t i = 0; i < 6; ++i) idx.insert(idx.end(), {0, 1 + i, 1 + (i + 1) % 6});
    p.push_back({2, 0.5f, 0});
    idx.insert(idx.end(), {1, 7, 2});
    for (int levels : {0, 1, 3}) {
        auto m = loop_subdivide(p, idx, levels, kLoc);
        for (size_t v = 0; v < m->p.size(); ++v) {
            ASSERT_EQ(m->p[v].z, 0.f);
            ASSERT_NEAR(m->n[v].z, -1.f, 1e-5f) << levels << " vertex " << v;
        }
    }
}

TEST(LoopSubdiv, BoundaryVertexLimitIsPbrtsRule) {
    // A single triangle: every vertex is on the boundary with its two neighbours; at level 0
    // each goes to 3/5 of itself plus 1/5 of each other vertex.
    auto m = loop_subdivide({{0, 0, 0}, {5, 0, 0}, {0, 5, 0}}, {0, 1, 2}, 0, kLoc);
    ASSERT_EQ(m->p.size(), 3u);
    EXPECT_NEAR(m->p[0].x, 1.f, 1e-6f);
    EXPECT_NEAR(m->p[0].y, 1.f, 1e-6f);
    EXPECT_NEAR(m->p[1].x, 3.f, 1e-6f);
    EXPECT_NEAR(m->p[1].y, 1.f, 1e-6f);
}

TEST(LoopSubdiv, BadMeshesAreErrorsAtTheirPlace) {
    using ml::test::expect_scene_error;
    const std::string head = "WorldBegin\nShape \"loopsubdiv\" \"point3 P\" [ ";
    // Three faces on the edge 0-1.
    expect_scene_error(head +
                           "0 0 0  1 0 0  0 1 0  0 -1 0  0 0 1 ]\n"
                           "  \"integer indices\" [ 0 1 2  1 0 3  0 1 4 ]\n",
                       3, 3, "more than two faces");
    // Two faces wound against each other.
    expect_scene_error(head +
                           "0 0 0  1 0 0  0 1 0  0 -1 0 ]\n"
                           "  \"integer indices\" [ 0 1 2  0 1 3 ]\n",
                       3, 3, "wound in opposite directions");
    expect_scene_error(head + "0 0 0  1 0 0  0 1 0 ]\n  \"integer indices\" [ 0 1 5 ]\n", 3, 3,
                       "out of range");
    expect_scene_error(head +
                           "0 0 0  1 0 0  0 1 0 ]\n  \"integer indices\" [ 0 1 2 ]\n"
                           "  \"integer levels\" [ -1 ]\n",
                       4, 3, "must not be negative");
    expect_scene_error(head +
                           "0 0 0  1 0 0  0 1 0 ]\n  \"integer indices\" [ 0 1 2 ]\n"
                           "  \"string scheme\" \"catmullclark\"\n",
                       4, 3, "scheme \"catmullclark\" is unknown");
}
