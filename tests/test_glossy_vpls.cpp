// Glossy VPLs: their falloff's storage, their clusters' bounds with real Bxdfs, and what
// vpl.glossy=skip|diffuse leave of them.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "manylight/bounds.h"
#include "manylight/light_tree.h"
#include "materials/bxdfs.h"
#include "sampling/warps.h"
#include "vpl_test_scenes.h"

using namespace ml;
using namespace ml::vpl_test;

// Clusters of glossy VPLs (the mixed box's conductor floor and coated wall, with their Bxdfs):
// for random nodes, receivers and receiving BSDFs, a node's bound is at least the exact sum of
// its lights' contributions without visibility.
TEST(Vpl, GlossyClusterBoundsHoldTheirLights) {
    auto scene = make_scene(mixed_box());
    PointLightSet set = vpls_only(*scene, 20000, 5, 7);
    LightTree tree(set.lights);
    int32_t root = tree.root(PointLightKind::Glossy);
    ASSERT_GE(root, 0);
    std::vector<int32_t> nodes{root};
    for (size_t i = 0; i < nodes.size(); ++i)
        if (!tree.node(nodes[i]).is_leaf())
            for (int32_t c : tree.node(nodes[i]).children()) nodes.push_back(c);
    auto leaves_of = [&](int32_t n) {
        std::vector<int32_t> out, stack{n};
        while (!stack.empty()) {
            int32_t m = stack.back();
            stack.pop_back();
            if (tree.node(m).is_leaf())
                out.push_back(tree.light(m));
            else
                stack.insert(stack.end(), {tree.node(m).children()[0], tree.node(m).children()[1]});
        }
        return out;
    };
    DiffuseBxdf diffuse(RGB(0.8f));
    ConductorBxdf metal(TrowbridgeReitz(0.1f, 0.1f), RGB(0.2f, 0.9f, 1.1f), RGB(3.9f, 2.4f, 2.2f));
    Rng rng(3);
    int finite = 0, checked = 0;
    for (int q = 0; q < 3000; ++q) {
        int32_t n = nodes[rng.next_u32() % nodes.size()];
        Vec3 x(-1.9f + 3.8f * rng.next_float(), 0.05f + 1.4f * rng.next_float(),
               -1.9f + 4.8f * rng.next_float());
        Vec3 axis = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        Frame frame = Frame::from_z(axis);
        Bsdf bsdf(frame, frame.n, q % 2 ? static_cast<const Bxdf*>(&metal) : &diffuse);
        Vec3 wo = sample_uniform_sphere({rng.next_float(), rng.next_float()});
        RGB exact;
        for (int32_t id : leaves_of(n)) {
            const PointLight& pl = set.lights[size_t(id)];
            Vec3 d = pl.p - x;
            float d2 = length_squared(d);
            Vec3 wi = d / std::sqrt(d2);
            exact +=
                bsdf.eval(wo, wi) * abs_dot(wi, frame.n) * point_light_intensity(set, pl, -wi) / d2;
        }
        RGB bound = node_error_bound(tree.ref(n), x, bsdf, wo);
        for (int c = 0; c < 3; ++c)
            ASSERT_LE(exact[c], bound[c] * 1.0001f + 1e-12f)
                << "node " << n << " channel " << c << " lights " << leaves_of(n).size();
        finite += std::isfinite(bound.max_component());
        ++checked;
    }
    EXPECT_GT(finite, checked / 2);
}

// A glossy light's falloff is stored rounded up: never below the value it stands for, and less
// than one step (2^(1/16)) above it.
TEST(Vpl, FalloffQuantizedUpward) {
    EXPECT_EQ(quantize_falloff(1.f), 0);
    EXPECT_EQ(quantize_falloff(2.f), 0);
    EXPECT_EQ(quantize_falloff(0.f), 255);
    for (int i = 0; i < 10000; ++i) {
        float t = std::exp2(-16.f * float(i) / 10000);
        uint8_t q = quantize_falloff(t);
        ASSERT_GE(falloff_value(q), t) << t;
        ASSERT_LE(falloff_value(q), t * std::exp2(1.f / 16) * 1.0001f) << t;
    }
    for (int k = 1; k < kFalloffBins; ++k) EXPECT_LT(kFalloffCos[k], kFalloffCos[k - 1]);
}

TEST(Vpl, GlossySkipLeavesNoneOnConductor) {
    auto scene = make_scene(mixed_box());
    PointLightSet with = vpls_only(*scene, 10000, 5, 2, GlossyVpls::Bsdf);
    PointLightSet skip = vpls_only(*scene, 10000, 5, 2, GlossyVpls::Skip);
    EXPECT_GE(skip.vpls, 10000u);
    auto on_floor = [](const PointLight& pl) {
        return std::abs(pl.p.y) < 1e-3f && std::abs(pl.p.x) < 1.49f && pl.p.z < 0.99f;
    };
    size_t floor_with = 0, floor_skip = 0;
    for (const PointLight& pl : with.lights) floor_with += on_floor(pl);
    for (const PointLight& pl : skip.lights) {
        floor_skip += on_floor(pl);
        EXPECT_LT(pl.surface, 0);
        EXPECT_EQ(pl.kind, PointLightKind::Oriented);
    }
    EXPECT_GT(floor_with, 0u);
    EXPECT_EQ(floor_skip, 0u);
    EXPECT_TRUE(skip.surfaces.empty());
}

// vpl.glossy=diffuse: no VPL on the conductor or the rough pane (no diffuse part), and the
// coated wall's VPLs re-emit through the base under the coat alone: within their bound, and
// below the whole BSDF towards the coat's highlight.
TEST(Vpl, GlossyDiffuseKeepsOnlyTheCoatedBase) {
    auto scene = make_scene(mixed_box());
    PointLightSet set = vpls_only(*scene, 10000, 5, 2, GlossyVpls::Diffuse);
    EXPECT_GE(set.vpls, 10000u);
    size_t on_coat = 0, dimmer = 0;
    for (const PointLight& pl : set.lights) {
        if (std::abs(pl.p.y - 1.5f) < 1e-3f) continue;  // the diffuse ceiling
        bool floor = std::abs(pl.p.y) < 1e-3f && std::abs(pl.p.x) < 1.49f && pl.p.z < 0.99f;
        bool pane = std::abs(pl.p.z - 1) < 1e-3f && std::abs(pl.p.x) < 1.49f && pl.p.y < 1.49f;
        EXPECT_FALSE(floor || pane) << "VPL on a surface with no diffuse part";
        if (std::abs(pl.p.x + 1.5f) > 1e-3f) continue;
        ++on_coat;
        ASSERT_GE(pl.surface, 0);
        const VplSurface& s = set.surfaces[size_t(pl.surface)];
        EXPECT_TRUE(s.diffuse_only);
        EXPECT_EQ(pl.kind, PointLightKind::Oriented);
        // Towards the mirror direction of the incoming light, where the coat's lobe peaks.
        Vec3 n = s.bsdf.frame().n;
        if (dot(n, s.wi) < 0) n = -n;
        Vec3 w = n * (2 * dot(s.wi, n)) - s.wi;
        RGB I = point_light_intensity(set, pl, w);
        RGB whole = s.flux * s.bsdf.eval(w, s.wi) * abs_dot(w, n);
        EXPECT_LE(I.r, pl.intensity.r * std::max(0.f, dot(pl.n, w)) * 1.0001f + 1e-12f);
        EXPECT_LE(I.g, whole.g * 1.0001f + 1e-12f);
        dimmer += I.g < 0.9f * whole.g;
    }
    EXPECT_GT(on_coat, 100u);
    EXPECT_GT(dimmer, on_coat / 2) << "the coat's highlight is left out";
}
