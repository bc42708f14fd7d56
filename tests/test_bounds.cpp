// Property tests of Lightcuts' bounds: cone helpers hold what they should, every Bxdf's
// max_value_bound is at least eval * |cos| inside the cone, and a node's error bound is at least
// the exact (unoccluded) contribution of its lights, over many random configurations.
//
// Tightness (printed by BoundNode.AtLeastExactContribution; seed fixed): median of exact / bound
// over random nodes of random trees, BSDFs and shading points, 0.385 for clusters and 0.998 for
// single lights (about 10% of the nodes get +infinity: x inside a box, or rough glass whose cone
// crosses the surface). BoundBxdf.AtLeastEvalTimesCosInCone prints the per-Bxdf median of
// (largest of 64 sampled eval * cos) / bound: ~1.0 diffuse, 0.6-0.9 for alpha >= 0.3, lower for
// sharp lobes, where 64 samples rarely hit the peak.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <memory>
#include <vector>

#include "core/cone.h"
#include "core/rng.h"
#include "manylight/bounds.h"
#include "manylight/light_tree.h"
#include "materials/bxdfs.h"
#include "materials/fresnel.h"
#include "tree_test_helpers.h"

using namespace ml;
using namespace ml::tree_test;

namespace {

// A direction in the cone: uniform in solid angle, or on its rim when `rim`.
Vec3 sample_in_cone(const DirectionCone& c, Rng& rng, bool rim) {
    float cos_t = c.is_entire_sphere() ? -1.f : c.cos_theta;
    float z = rim ? cos_t : 1 - rng.next_float() * (1 - cos_t);
    float r = safe_sqrt(1 - z * z), phi = 2 * kPi * rng.next_float();
    Frame f = Frame::from_z(c.axis);
    return normalize(f.to_world(Vec3(r * std::cos(phi), r * std::sin(phi), z)));
}

DirectionCone random_cone(Rng& rng) {
    float u = rng.next_float();
    // Half-angles from 0 to pi, many of them small (what the deep nodes of a tree have).
    float theta = u < 0.1f ? 0.f : (u < 0.5f ? 0.05f * rng.next_float() : kPi * rng.next_float());
    return {random_unit(rng), theta >= kPi ? -1.f : std::cos(theta)};
}

using BxdfMaker = std::function<std::unique_ptr<Bxdf>(float alpha_x, float alpha_y)>;

struct NamedBxdf {
    const char* name;
    BxdfMaker make;
};

std::vector<NamedBxdf> bxdf_makers() {
    return {
        {"diffuse",
         [](float, float) { return std::make_unique<DiffuseBxdf>(RGB(0.8f, .5f, .2f)); }},
        {"diffuse_transmission",
         [](float, float) {
             return std::make_unique<DiffuseTransmissionBxdf>(RGB(.3f, .6f, .2f),
                                                              RGB(.5f, .1f, .7f));
         }},
        {"conductor",
         [](float ax, float ay) {
             return std::make_unique<ConductorBxdf>(TrowbridgeReitz(ax, ay), RGB(0.2f, 0.9f, 1.5f),
                                                    RGB(3.9f, 2.4f, 1.9f));
         }},
        {"dielectric",
         [](float ax, float ay) {
             return std::make_unique<DielectricBxdf>(TrowbridgeReitz(ax, ay), 1.5f);
         }},
        {"coated_diffuse",
         [](float ax, float ay) {
             return std::make_unique<CoatedDiffuseBxdf>(
                 TrowbridgeReitz(ax, ay), 1.5f, RGB(.7f, .4f, .2f),
                 CoatLayer{0.01f, coat_internal_round_trip(1.5f, 0.01f), 5});
         }},
        {"coated_conductor",
         [](float ax, float ay) {
             CoatedConductorLayers l;
             l.base = TrowbridgeReitz(ax, ay);
             l.base_eta = RGB(0.2f, 0.9f, 1.5f) / 1.5f;
             l.base_k = RGB(3.9f, 2.4f, 1.9f) / 1.5f;
             return std::make_unique<CoatedConductorBxdf>(l);
         }},
        {"coated_conductor_rc",  // rough coat
         [](float ax, float ay) {
             CoatedConductorLayers l;
             l.coat = TrowbridgeReitz(ax, ay);
             l.base = TrowbridgeReitz(0.2f, 0.2f);
             l.eta = 1.33f;
             l.base_eta = RGB(1.f) / 1.33f;
             l.base_k = RGB(4.f, 3.f, 2.f) / 1.33f;
             l.thickness = 0.1f;
             return std::make_unique<CoatedConductorBxdf>(l);
         }},
    };
}

const float kAlphas[][2] = {{0, 0},       {0.001f, 0.001f}, {0.01f, 0.01f}, {0.05f, 0.2f},
                            {0.3f, 0.3f}, {0.7f, 0.4f},     {1.f, 1.f},     {1.6f, 1.2f}};

bool at_most(const RGB& value, const RGB& bound) {
    for (int c = 0; c < 3; ++c)
        if (!(value[c] <= bound[c] * (1 + 1e-4f) + 1e-12f)) return false;
    return true;
}

}  // namespace

TEST(Cone, SubtendedDirectionsHoldTheBox) {
    Rng rng(1);
    for (int t = 0; t < 2000; ++t) {
        Bounds3 b;
        Vec3 c =
            (Vec3(rng.next_float(), rng.next_float(), rng.next_float()) - Vec3(.5f, .5f, .5f)) * 20;
        float s = std::pow(10.f, 3 * rng.next_float() - 3);
        b.expand(c);
        b.expand(c + Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * s);
        Vec3 x =
            (Vec3(rng.next_float(), rng.next_float(), rng.next_float()) - Vec3(.5f, .5f, .5f)) * 40;
        DirectionCone cone = bound_subtended_directions(b, x);
        for (int k = 0; k < 20; ++k) {
            Vec3 p(lerp(rng.next_float(), b.lo.x, b.hi.x), lerp(rng.next_float(), b.lo.y, b.hi.y),
                   lerp(rng.next_float(), b.lo.z, b.hi.z));
            if (k < 8)
                p = Vec3(k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z);
            if (p == x) continue;
            ASSERT_TRUE(cone_contains(cone, normalize(p - x)));
        }
    }
    Bounds3 b;
    b.expand(Vec3(0, 0, 0)), b.expand(Vec3(1, 1, 1));
    EXPECT_TRUE(bound_subtended_directions(b, Vec3(.5f, .5f, .5f)).is_entire_sphere());
}

TEST(Cone, UnionHoldsBoth) {
    Rng rng(2);
    for (int t = 0; t < 5000; ++t) {
        DirectionCone a = random_cone(rng), b = random_cone(rng);
        DirectionCone u = union_cones(a, b);
        for (int k = 0; k < 20; ++k) {
            ASSERT_TRUE(cone_contains(u, sample_in_cone(a, rng, k % 2)));
            ASSERT_TRUE(cone_contains(u, sample_in_cone(b, rng, k % 2)));
        }
        // Never wider than the larger cone or the cone spanning both from rim to rim.
        float ta = cone_angle(a), tb = cone_angle(b);
        float spanning = (ta + tb + angle_between(a.axis, b.axis)) / 2;
        EXPECT_LE(cone_angle(u), std::min(kPi, std::max({ta, tb, spanning}) + 1e-4f) + 1e-6f);
    }
    DirectionCone e = DirectionCone::empty_cone(), a(Vec3(0, 0, 1));
    EXPECT_EQ(union_cones(e, a).cos_theta, a.cos_theta);
}

TEST(Cone, MinAngleAndMaxCos) {
    Rng rng(3);
    for (int t = 0; t < 5000; ++t) {
        DirectionCone c = random_cone(rng);
        Vec3 w = random_unit(rng);
        float ma = min_angle(c, w), mc = max_cos(c, w), mac = max_abs_cos(c, w);
        for (int k = 0; k < 20; ++k) {
            Vec3 v = sample_in_cone(c, rng, k % 2);
            ASSERT_LE(ma, angle_between(v, w) + 1e-6f);
            ASSERT_GE(mc, dot(v, w) - 1e-6f);
            ASSERT_GE(mac, std::abs(dot(v, w)) - 1e-6f);
        }
        if (cone_contains(c, w)) {
            EXPECT_EQ(ma, 0.f);
        }
    }
}

// The conductor bound takes the Fresnel maximum at the ends of an interval of angles: the
// unpolarised reflectance must have no interior local maximum in angle.
TEST(BoundBxdf, ConductorFresnelEnds) {
    for (float eta = 0.05f; eta < 5; eta *= 1.3f)
        for (float k = 0; k < 10; k = k * 1.5f + 0.05f) {
            const int n = 2000;
            std::vector<float> f(n);  // by increasing angle
            for (int i = 0; i < n; ++i)
                f[i] = fr_complex(std::cos(0.5f * kPi * i / (n - 1)), eta, k);
            size_t m = size_t(std::min_element(f.begin(), f.end()) - f.begin());
            for (size_t i = 1; i <= m; ++i) ASSERT_LE(f[i], f[i - 1] + 1e-6f) << eta << " " << k;
            for (size_t i = m + 1; i < size_t(n); ++i)
                ASSERT_GE(f[i], f[i - 1] - 1e-6f) << eta << " " << k;
        }
}

TEST(BoundBxdf, AtLeastEvalTimesCosInCone) {
    Rng rng(4);
    for (const NamedBxdf& nb : bxdf_makers())
        for (const auto& al : kAlphas) {
            std::unique_ptr<Bxdf> bxdf = nb.make(al[0], al[1]);
            std::vector<double> ratios;
            for (int t = 0; t < 3000; ++t) {
                Vec3 wo = random_unit(rng);
                DirectionCone cone = random_cone(rng);
                // Cones about the mirror direction probe the glossy peaks.
                if (t % 3 == 0)
                    cone.axis = normalize(Vec3(-wo.x, -wo.y, wo.z) + random_unit(rng) * 0.05f);
                RGB bound = bxdf->max_value_bound(wo, cone);
                float worst = 0;
                for (int k = 0; k < 64; ++k) {
                    Vec3 wi = k == 0 ? cone.axis : sample_in_cone(cone, rng, k % 4 == 1);
                    RGB v = bxdf->eval(wo, wi, TransportMode::Radiance) * std::abs(wi.z);
                    ASSERT_TRUE(at_most(v, bound))
                        << nb.name << " alpha " << al[0] << "," << al[1] << " wo " << wo.x << ","
                        << wo.y << "," << wo.z << " v " << v.max_component() << " bound "
                        << bound.max_component();
                    worst = std::max(worst, v.max_component());
                }
                if (worst > 0 && std::isfinite(bound.max_component()))
                    ratios.push_back(worst / bound.max_component());
            }
            if (!ratios.empty()) {
                std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
                std::printf(
                    "[ bound ] %-20s alpha %.3f,%.3f: median max(eval cos) / bound = %.3f\n",
                    nb.name, al[0], al[1], ratios[ratios.size() / 2]);
            }
        }
}

TEST(BoundBxdf, DeltaLobesContributeNothing) {
    DirectionCone all = DirectionCone::entire_sphere();
    Vec3 wo = normalize(Vec3(.3f, .2f, .9f));
    EXPECT_TRUE(
        ConductorBxdf(TrowbridgeReitz(0, 0), RGB(.2f), RGB(3)).max_value_bound(wo, all).is_black());
    EXPECT_TRUE(DielectricBxdf(TrowbridgeReitz(0, 0), 1.5f).max_value_bound(wo, all).is_black());
    // A cone entirely below a reflection-only surface sees nothing.
    DirectionCone below(Vec3(0, 0, -1), 0.5f);
    EXPECT_TRUE(DiffuseBxdf(RGB(1)).max_value_bound(wo, below).is_black());
}

namespace {

// The exact, unoccluded contribution of the node's lights at x: sum of f |cos| I / d^2.
void collect_leaves(const LightTree& tree, int32_t n, std::vector<int32_t>* out) {
    const LightTreeNode& node = tree.node(n);
    if (node.is_leaf()) {
        out->push_back(tree.light(n));
        return;
    }
    collect_leaves(tree, node.children()[0], out);
    collect_leaves(tree, node.children()[1], out);
}

RGB exact_contribution(const PointLightSet& set, const std::vector<int32_t>& ids, const Vec3& x,
                       const Bsdf& bsdf, const Vec3& wo) {
    RGB sum;
    for (int32_t id : ids) {
        const PointLight& pl = set.lights[size_t(id)];
        Vec3 wi;
        float falloff = 1;
        if (pl.kind == PointLightKind::Directional) {
            wi = -pl.n;
        } else {
            Vec3 d = pl.p - x;
            float d2 = length_squared(d);
            if (d2 == 0) continue;
            wi = d / std::sqrt(d2);
            falloff = 1 / d2;
        }
        RGB f = bsdf.eval(wo, wi) * abs_dot(wi, bsdf.frame().n);
        sum += f * point_light_intensity(set, pl, -wi) * falloff;
    }
    return sum;
}

}  // namespace

TEST(BoundNode, AtLeastExactContribution) {
    Rng rng(5);
    std::vector<NamedBxdf> makers = bxdf_makers();
    std::vector<double> ratios, leaf_ratios;
    int infinite = 0, checked = 0;
    for (int trial = 0; trial < 60; ++trial) {
        LightMix mix = LightMix(trial % 4);
        PointLightSet set;
        set.lights = random_lights(50 + rng.next_u32() % 400, mix, 1000 + trial);
        LightTree tree(set.lights);
        for (int q = 0; q < 400; ++q) {
            // A random node of the tree.
            int32_t n = int32_t(rng.next_u32() % tree.node_count());
            const LightTreeNode& node = tree.node(n);
            std::vector<int32_t> ids;
            collect_leaves(tree, n, &ids);
            // A shading point near or far, a BSDF, a shading frame and wo.
            float spread = q % 2 ? 15.f : 60.f;
            Vec3 x =
                (Vec3(rng.next_float(), rng.next_float(), rng.next_float()) - Vec3(.5f, .5f, .5f)) *
                spread;
            const NamedBxdf& nb = makers[rng.next_u32() % makers.size()];
            const auto& al = kAlphas[rng.next_u32() % std::size(kAlphas)];
            std::unique_ptr<Bxdf> bxdf = nb.make(al[0], al[1]);
            Frame frame = Frame::from_z(random_unit(rng));
            Bsdf bsdf(frame, frame.n, bxdf.get());
            Vec3 wo = random_unit(rng);
            if (q % 4 == 0) wo = face_forward(wo, frame.n);  // facing the lights more often
            RGB exact = exact_contribution(set, ids, x, bsdf, wo);
            RGB bound = node_error_bound(tree.ref(n), x, bsdf, wo);
            ASSERT_TRUE(at_most(exact, bound))
                << nb.name << " kind " << int(node.kind) << " lights " << ids.size() << " exact "
                << exact.max_component() << " bound " << bound.max_component();
            ++checked;
            if (!std::isfinite(bound.max_component())) {
                ++infinite;
                continue;
            }
            if (exact.max_component() > 0) {
                double r = exact.max_component() / bound.max_component();
                (ids.size() == 1 ? leaf_ratios : ratios).push_back(r);
            }
        }
    }
    auto median = [](std::vector<double> v) {
        if (v.empty()) return 0.0;
        std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
        return v[v.size() / 2];
    };
    std::printf(
        "[ bound ] %d nodes checked, %d infinite bounds; median ratio exact / bound: "
        "clusters %.4f (%zu), single lights %.4f (%zu)\n",
        checked, infinite, median(ratios), ratios.size(), median(leaf_ratios), leaf_ratios.size());
}

TEST(BoundNode, GeometricBoundsPerKind) {
    // A single omni light at distance 2: G = 1/4 exactly (within float padding).
    PointLight pl;
    pl.p = Vec3(0, 0, 2), pl.n = Vec3(0, 0, -1), pl.intensity = RGB(1);
    std::vector<PointLight> lights{pl};
    LightTree omni(lights);
    EXPECT_NEAR(geometric_bound(omni.ref(omni.root(PointLightKind::Omni)), Vec3(0, 0, 0)), 0.25f,
                1e-5f);
    // Oriented, facing x: cos 1; facing away: 0.
    lights[0].kind = PointLightKind::Oriented;
    LightTree ori(lights);
    LightNodeRef on = ori.ref(ori.root(PointLightKind::Oriented));
    EXPECT_NEAR(geometric_bound(on, Vec3(0, 0, 0)), 0.25f, 1e-5f);
    EXPECT_EQ(geometric_bound(on, Vec3(0, 0, 4)), 0.f);
    // Directional: 1, and the direction cone points against the travel direction.
    lights[0].kind = PointLightKind::Directional;
    LightTree dir(lights);
    LightNodeRef dn = dir.ref(dir.root(PointLightKind::Directional));
    EXPECT_EQ(geometric_bound(dn, Vec3(5, 5, 5)), 1.f);
    EXPECT_NEAR(dot(node_direction_cone(dn.node, Vec3(5, 5, 5)).axis, Vec3(0, 0, 1)), 1.f, 1e-6f);
    // Inside the box of a cluster: no bound.
    lights = {pl, pl};
    lights[1].p = Vec3(2, 2, 4);
    LightTree two(lights);
    EXPECT_EQ(geometric_bound(two.ref(two.root(PointLightKind::Omni)), Vec3(1, 1, 3)), kInfinity);
}
