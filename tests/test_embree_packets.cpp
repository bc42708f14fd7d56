// Embree packets (EmbreeScene::intersect4/8, occluded4/8) against the single-ray queries, on
// random rays through the Cornell box with glass and mirror spheres, with random lanes inactive.
#include <gtest/gtest.h>

#include "bidir_test_helpers.h"
#include "core/rng.h"
#include "scene/scene.h"

using namespace ml;

namespace {

std::unique_ptr<Scene> make_scene() {
    return std::make_unique<Scene>(
        parse_scene_string(test::cornell_variant(test::glass_and_mirror()), "."));
}

// A ray from a random point of the box's bounds in a random direction, with a random length
// (some rays end before they hit anything).
Ray random_ray(const Bounds3& b, Rng& rng) {
    auto u = [&] { return rng.next_float(); };
    Vec3 o(b.lo.x + u() * (b.hi.x - b.lo.x), b.lo.y + u() * (b.hi.y - b.lo.y),
           b.lo.z + u() * (b.hi.z - b.lo.z));
    float z = 1 - 2 * u(), r = std::sqrt(std::max(0.f, 1 - z * z)), phi = 2 * kPi * u();
    Vec3 d(r * std::cos(phi), r * std::sin(phi), z);
    float tmax = u() < 0.3f ? u() * 300.f : kInfinity;
    return Ray{o, d, tmax};
}

template <int N, typename Intersect, typename Occluded>
void check_packets(const Scene& scene, Intersect intersect_n, Occluded occluded_n) {
    Rng rng(7);
    int hits = 0, blocked = 0;
    for (int round = 0; round < 500; ++round) {
        Ray rays[N];
        bool active[N], hit[N], occ[N];
        SurfaceInteraction si[N];
        for (int i = 0; i < N; ++i) {
            rays[i] = random_ray(scene.bounds(), rng);
            active[i] = rng.next_float() < 0.75f;
            // Sentinels: inactive lanes must keep them.
            hit[i] = occ[i] = true;
            si[i].t = -1;
        }
        intersect_n(rays, active, si, hit);
        occluded_n(rays, active, occ);
        for (int i = 0; i < N; ++i) {
            if (!active[i]) {
                EXPECT_TRUE(hit[i] && occ[i] && si[i].t == -1) << "inactive lane " << i;
                continue;
            }
            SurfaceInteraction one;
            bool h = scene.intersect(rays[i], &one);
            ASSERT_EQ(hit[i], h) << "round " << round << " lane " << i;
            EXPECT_EQ(occ[i], scene.occluded(rays[i])) << "round " << round << " lane " << i;
            if (!h) continue;
            ++hits;
            blocked += occ[i];
            EXPECT_NEAR(si[i].t, one.t, 1e-3f * std::max(1.f, one.t));
            EXPECT_EQ(si[i].prim_id, one.prim_id);
            EXPECT_EQ(si[i].mesh_id, one.mesh_id);
            EXPECT_NEAR(length(si[i].p - one.p), 0.f, 1e-3f * std::max(1.f, one.t));
        }
    }
    EXPECT_GT(hits, 100 * N);  // most rays hit the box
    EXPECT_GT(blocked, 100 * N);
}

}  // namespace

TEST(EmbreePackets, FourRaysAgreeWithSingleRays) {
    auto owned = make_scene();
    const Scene& scene = *owned;
    check_packets<4>(
        scene,
        [&](const Ray* r, const bool* a, SurfaceInteraction* si, bool* h) {
            scene.intersect4(r, a, si, h);
        },
        [&](const Ray* r, const bool* a, bool* o) { scene.occluded4(r, a, o); });
}

TEST(EmbreePackets, EightRaysAgreeWithSingleRays) {
    auto owned = make_scene();
    const Scene& scene = *owned;
    check_packets<8>(
        scene,
        [&](const Ray* r, const bool* a, SurfaceInteraction* si, bool* h) {
            scene.intersect8(r, a, si, h);
        },
        [&](const Ray* r, const bool* a, bool* o) { scene.occluded8(r, a, o); });
}

namespace {

// intersect_emitter (the direct light's BSDF rays): the same hits as intersect, the whole
// interaction where the surface emits, and a null area light elsewhere.
TEST(EmbreeEmitterRays, AgreeWithIntersectAndFillOnlyEmitters) {
    auto scene = make_scene();
    Rng rng(11);
    int emitters = 0, others = 0;
    for (int i = 0; i < 4000; ++i) {
        Ray ray = random_ray(scene->bounds(), rng);
        SurfaceInteraction full, only;
        only.area_light = reinterpret_cast<const Light*>(&full);  // a sentinel to be cleared
        bool h = scene->intersect(ray, &full);
        ASSERT_EQ(scene->intersect_emitter(ray, &only), h) << "ray " << i;
        if (!h) continue;
        if (!full.area_light) {
            EXPECT_EQ(only.area_light, nullptr) << "ray " << i;
            ++others;
            continue;
        }
        ++emitters;
        EXPECT_EQ(only.area_light, full.area_light);
        EXPECT_EQ(only.prim_id, full.prim_id);
        EXPECT_EQ(only.t, full.t);
        EXPECT_EQ(only.p.x, full.p.x);
        EXPECT_EQ(only.ng.y, full.ng.y);
        EXPECT_EQ(only.uv.x, full.uv.x);
    }
    // Both kinds met: the box's light and its walls.
    EXPECT_GT(emitters, 10);
    EXPECT_GT(others, 1000);
}

}  // namespace
