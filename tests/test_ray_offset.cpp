// Ray origins off surfaces from floating-point error bounds (offset_ray_origin, segment_ray):
// thin slabs near and far from the origin (the kitchen's blinds are a closed sheet 0.27 mm
// thick, 2.75 units out), boxes touching a floor, lights inside a thin shade, grazing rays on
// a large plane. Each checks both failure modes: leaks (a surface skipped or an occluder
// missed) and self-hits (a ray stopped by the surface it left, or by the light it aims at).
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "core/rng.h"
#include "geometry/embree_scene.h"
#include "lights/lights.h"
#include "lights/point_lights.h"

using namespace ml;

namespace {

// An axis-aligned box as 12 triangles with outward winding.
void add_box(TriangleMesh& m, const Vec3& lo, const Vec3& hi) {
    uint32_t base = uint32_t(m.p.size());
    for (int i = 0; i < 8; ++i)
        m.p.push_back(Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z));
    const uint32_t quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& q : quads) {
        for (uint32_t k : {q[0], q[1], q[2], q[0], q[2], q[3]}) m.indices.push_back(base + k);
    }
}

// A quad in the plane y = `y` over [x0, x1] x [z0, z1], facing +y.
void add_quad_y(TriangleMesh& m, float y, float x0, float x1, float z0, float z1) {
    uint32_t base = uint32_t(m.p.size());
    m.p.insert(m.p.end(), {Vec3(x0, y, z0), Vec3(x0, y, z1), Vec3(x1, y, z1), Vec3(x1, y, z0)});
    for (uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + k);
}

struct Meshes {
    std::vector<std::unique_ptr<TriangleMesh>> owned;
    std::unique_ptr<EmbreeScene> scene;
    TriangleMesh& add() { return *owned.emplace_back(std::make_unique<TriangleMesh>()); }
    void build() {
        std::vector<const TriangleMesh*> m;
        for (auto& o : owned) m.push_back(o.get());
        scene = std::make_unique<EmbreeScene>(m);
    }
};

Vec3 uniform_hemisphere(const Vec3& n, Rng& rng) {
    float z = rng.next_float(), r = std::sqrt(std::max(0.f, 1 - z * z));
    float phi = 2 * kPi * rng.next_float();
    Vec3 s, t;
    coordinate_system(n, &s, &t);
    return s * (r * std::cos(phi)) + t * (r * std::sin(phi)) + n * z;
}

// A closed slab of thickness `thick` (z in [z - thick/2, z + thick/2]) centred at `c`. Rays hit
// its front face (+z) from above; from each hit, a ray transmitted into the slab must stop at
// its back face (leaving from the front face's error box, neither skipping the back face nor
// stopping at the front), and a ray reflected back up must escape.
void check_thin_slab(const Vec3& c, float thick, float half) {
    Meshes ms;
    add_box(ms.add(), c - Vec3(half, half, thick / 2), c + Vec3(half, half, thick / 2));
    ms.build();
    Rng rng(11);
    float back_z = c.z - thick / 2;
    int skipped = 0, self_hits = 0, escaped_wrongly = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        Vec3 target = c + Vec3((2 * rng.next_float() - 1) * half * 0.9f,
                               (2 * rng.next_float() - 1) * half * 0.9f, thick / 2);
        Vec3 w = uniform_hemisphere(Vec3(0, 0, 1), rng);
        w.z = std::max(w.z, 0.05f);
        Vec3 o = target + w * (half * 2);
        SurfaceInteraction si;
        ASSERT_TRUE(ms.scene->intersect(Ray{o, normalize(target - o)}, &si));
        ASSERT_GT(si.ng.z, 0.99f) << "the front face";
        // Through the sheet: the next surface is the back face (z = back_z), not the front
        // face again and not whatever lies beyond.
        Vec3 wt = uniform_hemisphere(Vec3(0, 0, -1), rng);
        SurfaceInteraction next;
        bool hit = ms.scene->intersect(Ray{si.offset_origin(wt), wt}, &next);
        if (!hit) {
            ++skipped;
        } else if (next.ng.z > 0.99f) {
            ++self_hits;
        } else if (next.ng.z < -0.99f) {
            EXPECT_NEAR(next.p.z, back_z, 4 * next.p_error.z + 1e-7f);
        }
        // Reflected: nothing above the slab.
        Vec3 wr = uniform_hemisphere(Vec3(0, 0, 1), rng);
        escaped_wrongly += ms.scene->occluded(Ray{si.offset_origin(wr), wr});
    }
    EXPECT_EQ(skipped, 0) << "rays through the front face that skipped the back face";
    EXPECT_EQ(self_hits, 0) << "transmitted rays that hit the face they left";
    EXPECT_EQ(escaped_wrongly, 0) << "reflected rays that hit the face they left";
}

}  // namespace

// The cause of the kitchen blinds' 3.5x: the blind mesh (Mesh110.ply) is a closed sheet
// 0.27 mm thick at |p| ~ 2.75, and the old fixed offset of 1e-4 max(1, |p|) along the normal,
// 0.275 mm there, put transmitted rays' origins beyond the sheet's back face: light crossed one
// sheet (T L) instead of two (T^2 L / (1 - R^2), as pbrt-v4 renders it).
TEST(RayOffset, BlindSheetSecondSurfaceIsHit) {
    const float thick = 2.7e-4f;
    const Vec3 c(0.05f, 2.8f, -2.7485f);
    EXPECT_GT(1e-4f * max_component(vabs(c)), thick) << "the old offset skipped this sheet";
    check_thin_slab(c, thick, 0.15f);
}

TEST(RayOffset, MillimetreSlabNearAndFarFromTheOrigin) {
    check_thin_slab(Vec3(0, 0, 3), 1e-3f, 0.5f);
    check_thin_slab(Vec3(1000, 0, 3), 1e-3f, 0.5f);
    check_thin_slab(Vec3(700, -600, 1000), 1e-3f, 0.5f);
}

// Error bounds grow with the coordinates along the normal (a plane at y = 0.1 against one at
// y = 1000.1), and stay far below a millimetre there.
TEST(RayOffset, ErrorBoundsScaleWithDistanceFromTheOrigin) {
    SurfaceInteraction a, b;
    Meshes ms;
    add_quad_y(ms.add(), 0.1f, -1, 1, -1, 1);
    add_quad_y(ms.add(), 1000.1f, -1, 1, -1, 1);
    ms.build();
    ASSERT_TRUE(ms.scene->intersect(Ray{Vec3(0.3f, 1, 0.2f), Vec3(0, -1, 0)}, &a));
    ASSERT_TRUE(ms.scene->intersect(Ray{Vec3(0.3f, 1001, 0.2f), Vec3(0, -1, 0)}, &b));
    EXPECT_GT(a.p_error.x, 0.f);
    EXPECT_LT(a.offset().y, 1e-6f);
    EXPECT_GT(b.offset().y, 100 * a.offset().y);
    EXPECT_LT(b.offset().y, 1e-3f);
    // A point on no surface stays put.
    EXPECT_EQ(offset_ray_origin(Vec3(1, 2, 3), Vec3(), Vec3(0, 1, 0)), Vec3(1, 2, 3));
}

// Boxes standing on a floor, near the origin and 1000 units out: points on the floor right at
// a box's foot, on the side away from a low light, are in shadow (the shadow ray crosses the
// box's base); on the lit side they are lit, as are points low on the box's lit face.
TEST(RayOffset, BoxesTouchingAFloor) {
    for (Vec3 c : {Vec3(0, 0, 0), Vec3(1000, 0, -500)}) {
        Meshes ms;
        TriangleMesh& floor = ms.add();
        add_quad_y(floor, c.y, c.x - 50, c.x + 50, c.z - 50, c.z + 50);
        add_box(ms.add(), c + Vec3(-1, 0, -1), c + Vec3(1, 2, 1));  // its base on the floor
        add_box(ms.add(), c + Vec3(1, 0, -1), c + Vec3(2, 1, 1));   // touching the first too
        ms.build();
        Vec3 light = c + Vec3(-20, 1, 0);  // low, on the -x side
        Rng rng(5);
        int leaks = 0, false_shadows = 0;
        // A point nearer a box than its own error bound (the floor's, 4e-4 at x = 1000) is not
        // known to be outside it: gaps start above that.
        float min_gap = std::max(1e-6f, 2 * gamma_bound(7) * (std::abs(c.x) + 50));
        float decades = std::log10(1e-2f / min_gap);
        for (int i = 0; i < 4000; ++i) {
            // From min_gap to 1e-2 from the boxes' feet, at x = c.x + 2 (shadow) and x = c.x - 1
            // (lit).
            float gap = min_gap * std::pow(10.f, decades * rng.next_float());
            float z = (2 * rng.next_float() - 1) * 0.9f;
            bool dark = i % 2 == 0;
            Vec3 above = c + Vec3(dark ? 2 + gap : -1 - gap, 1, z);
            SurfaceInteraction si;
            ASSERT_TRUE(ms.scene->intersect(Ray{above, Vec3(0, -1, 0)}, &si));
            bool blocked = ms.scene->occluded(segment_ray(si.p, si.offset(), light, Vec3()));
            if (dark && !blocked) ++leaks;
            if (!dark && blocked) ++false_shadows;
            // Low on the lit face (x = c.x - 1), just above the floor.
            Vec3 side = c + Vec3(-5, gap, z);
            ASSERT_TRUE(ms.scene->intersect(Ray{side, Vec3(1, 0, 0)}, &si));
            false_shadows += ms.scene->occluded(segment_ray(si.p, si.offset(), light, Vec3()));
        }
        EXPECT_EQ(leaks, 0) << "at " << c.x;
        EXPECT_EQ(false_shadows, 0) << "at " << c.x;
    }
}

// A light inside a closed lampshade 0.5 mm thick, the light 1 mm from its inner wall, seen from
// a floor 20 units away: no shadow ray gets out (the old segments, cut 1e-4 of their length short
// of the light, skipped the shade), and without the shade every one gets through (the area
// light's own surface does not block the rays that end on it).
TEST(RayOffset, LightInsideAThinShade) {
    for (bool shade : {true, false}) {
        Meshes ms;
        TriangleMesh& floor = ms.add();
        add_quad_y(floor, 0, -30, 30, -30, 30);
        // A small emitter at y = 20 facing down (two triangles), inside the shade.
        TriangleMesh& emitter = ms.add();
        add_quad_y(emitter, 20, -0.05f, 0.05f, -0.05f, 0.05f);
        emitter.flip_normals = true;
        if (shade) {
            add_box(ms.add(), Vec3(-0.0515f, 19.9985f, -0.0515f), Vec3(0.0515f, 20.0515f, 0.0515f));
            add_box(ms.add(), Vec3(-0.051f, 19.999f, -0.051f), Vec3(0.051f, 20.051f, 0.051f));
        }
        ms.build();
        auto light = make_diffuse_area_light(&emitter, RGB(1.f), true);
        PointLight point;
        point.p = Vec3(0.01f, 19.9995f, 0);  // under the emitter, 0.5 mm off the shade
        Rng rng(3);
        int through = 0;
        const int n = 4000;
        for (int i = 0; i < n; ++i) {
            Vec3 above(40 * rng.next_float() - 20, 1, 40 * rng.next_float() - 20);
            SurfaceInteraction si;
            ASSERT_TRUE(ms.scene->intersect(Ray{above, Vec3(0, -1, 0)}, &si));
            auto ls = light->sample_li(LightSampleContext{si.p, si.ng, si.ns},
                                       Vec2(rng.next_float(), rng.next_float()));
            ASSERT_TRUE(ls);
            through +=
                !ms.scene->occluded(segment_ray(si.p, si.offset(), ls->p_light, ls->offset()));
            through += !ms.scene->occluded(segment_ray(si.p, si.offset(), point.p, point.offset));
        }
        EXPECT_EQ(through, shade ? 0 : 2 * n) << (shade ? "leaks" : "self-occlusion");
    }
}

// Rays leaving a plane 2000 units wide at grazing angles (down to 1e-5 rad above it) do not
// hit it again, wherever on it they start; rays crossing it at grazing angles do not hit it
// again on the far side.
TEST(RayOffset, GrazingRaysOnALargePlane) {
    Meshes ms;
    add_quad_y(ms.add(), 0.5f, -1000, 1000, -1000, 1000);
    ms.build();
    Rng rng(9);
    int self_hits = 0;
    for (int i = 0; i < 20000; ++i) {
        Vec3 above(1900 * rng.next_float() - 950, 2, 1900 * rng.next_float() - 950);
        if (i % 4 == 0) above = above * 1e-3f + Vec3(0, 2, 0);  // near the centre
        SurfaceInteraction si;
        Vec3 down = normalize(Vec3(rng.next_float() - 0.5f, -1, rng.next_float() - 0.5f));
        ASSERT_TRUE(ms.scene->intersect(Ray{above, down}, &si));
        float elevation = std::pow(10.f, -5 + 4 * rng.next_float());
        float phi = 2 * kPi * rng.next_float();
        float h = std::cos(elevation);
        Vec3 up(h * std::cos(phi), std::sin(elevation), h * std::sin(phi));
        self_hits += ms.scene->occluded(Ray{si.offset_origin(up), up});
        Vec3 below(up.x, -up.y, up.z);
        self_hits += ms.scene->occluded(Ray{si.offset_origin(below), below});
    }
    EXPECT_EQ(self_hits, 0);
}
