// Next-event sampling of triangle-mesh area lights: the spherical triangle warp and its inverse,
// the bilinear warp, and the light's sample_li against pdf_li by a chi-square test over the
// light's surface (both converted to area density), in the solid-angle branch (with and without
// the cosine warp) and in the area branch (the light seen tiny).
#include <gtest/gtest.h>

#include "chi2.h"
#include "core/rng.h"
#include "lights/lights.h"
#include "sampling/spherical_triangle.h"

namespace ml {
namespace {

Vec2 next2(Rng& rng) {
    float x = rng.next_float();
    return {x, rng.next_float()};
}

TEST(SphericalTriangle, SolidAngleOfAnOctant) {
    // The triangle through the three axes' unit points, seen from the origin: an eighth of the
    // sphere.
    float omega = spherical_triangle_solid_angle({1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 0});
    EXPECT_NEAR(omega, 4 * kPi / 8, 1e-5f);
}

TEST(SphericalTriangle, SamplesHitTheTriangleAndInvert) {
    struct Case {
        Vec3 v0, v1, v2, p;
    };
    // A general triangle; the square light's triangles (one a sliver) seen from near and aside.
    const Case cases[] = {
        {{-1, 0.2f, 2}, {1.5f, -0.4f, 2.5f}, {0.3f, 1.7f, 1.8f}, {0.1f, 0.2f, -0.3f}},
        {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {0.55f, 0.45f, 0.9f}},
        {{0, 0, 1}, {1, 1, 1}, {0.9f, 0, 1}, {0.55f, 0.45f, 0.9f}},
        {{0.9f, 0, 1}, {1, 1, 1}, {1, 0, 1}, {0.55f, 0.45f, 0.9f}},
        {{0, 0, 1}, {1, 1, 1}, {0.9f, 0, 1}, {0.7f, -0.2f, 0.4f}},
        {{0.9f, 0, 1}, {1, 1, 1}, {1, 0, 1}, {0.7f, -0.2f, 0.4f}},
    };
    for (const Case& k : cases) {
        Rng rng(3);
        for (int i = 0; i < 2000; ++i) {
            Vec2 u = next2(rng);
            auto w = sample_spherical_triangle(k.v0, k.v1, k.v2, k.p, u);
            ASSERT_TRUE(w);
            // Through the triangle: the ray's barycentrics are all >= 0.
            Vec3 e1 = k.v1 - k.v0, e2 = k.v2 - k.v0, s1 = cross(*w, e2);
            float div = dot(s1, e1);
            Vec3 s = k.p - k.v0;
            float b1 = dot(s, s1) / div, b2 = dot(*w, cross(s, e1)) / div;
            ASSERT_GE(b1, -1e-4f) << i;
            ASSERT_GE(b2, -1e-4f) << i;
            ASSERT_LE(b1 + b2, 1 + 1e-4f) << i;
            Vec2 back = invert_spherical_triangle(k.v0, k.v1, k.v2, k.p, *w);
            ASSERT_NEAR(back.x, u.x, 1e-3f) << i << " " << u.y;
            ASSERT_NEAR(back.y, u.y, 1e-3f) << i << " " << u.x;
        }
    }
}

TEST(SphericalTriangle, BilinearWarpMatchesItsPdf) {
    const float w[4] = {0.2f, 1.5f, 0.05f, 3};
    // Counts over a 10 x 10 grid against the pdf's midpoint quadrature.
    const int g = 10, n = 200000;
    std::vector<double> count(g * g, 0);
    Rng rng(5);
    for (int i = 0; i < n; ++i) {
        Vec2 p = sample_bilinear(next2(rng), w);
        count[size_t(std::min(g - 1, int(p.y * g)) * g + std::min(g - 1, int(p.x * g)))] += 1;
    }
    double stat = 0;
    for (int j = 0; j < g; ++j)
        for (int i = 0; i < g; ++i) {
            double e = 0;
            for (int b = 0; b < 4; ++b)
                for (int a = 0; a < 4; ++a)
                    e += pdf_bilinear_area({(i + (a + 0.5f) / 4) / g, (j + (b + 0.5f) / 4) / g}, w);
            e *= double(n) / (16 * g * g);
            double diff = count[size_t(j * g + i)] - e;
            stat += diff * diff / e;
        }
    EXPECT_GT(chi2::chi2_survival(stat, g * g - 1), 0.001) << stat;
}

// The unit square at z = 1 facing -z: in three triangles, one a sliver (cells = 0), or a grid of
// cells x cells squares (2 cells^2 triangles).
TriangleMesh square_mesh(int cells = 0) {
    TriangleMesh m;
    if (cells == 0) {
        m.p = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {0.9f, 0, 1}};
        m.indices = {0, 3, 2, 0, 2, 4, 4, 2, 1};
        return m;
    }
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i) m.p.push_back({float(i) / cells, float(j) / cells, 1});
    auto at = [&](int i, int j) { return uint32_t(j * (cells + 1) + i); };
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i)
            for (uint32_t k : {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1),
                               at(i + 1, j)})
                m.indices.push_back(k);
    return m;
}

// The triangle of `mesh` containing q (on its plane), or -1.
int triangle_at(const TriangleMesh& mesh, const Vec3& q) {
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        const uint32_t* idx = &mesh.indices[3 * t];
        Vec3 a = mesh.p[idx[0]], b = mesh.p[idx[1]], c = mesh.p[idx[2]];
        Vec3 n = cross(b - a, c - a);
        if (dot(cross(b - a, q - a), n) >= 0 && dot(cross(c - b, q - b), n) >= 0 &&
            dot(cross(a - c, q - c), n) >= 0)
            return int(t);
    }
    return -1;
}

// Chi-square test of sample_li's points on the square against pdf_li (area density
// pdf_li cos_l / d^2), over a g x g grid with k x k midpoint quadrature per cell.
void check_square_light(const LightSampleContext& ctx, const char* what, int cells = 0) {
    TriangleMesh mesh = square_mesh(cells);
    auto light = make_diffuse_area_light(&mesh, RGB(1), false);
    const int g = 16, k = 6, n = 300000;
    std::vector<double> count(g * g, 0);
    Rng rng(11);
    int misses = 0;
    for (int i = 0; i < n; ++i) {
        auto s = light->sample_li(ctx, next2(rng));
        if (!s) {
            ++misses;
            continue;
        }
        // The sample's own pdf is pdf_li's.
        float pdf = light->pdf_li(ctx, s->wi, s->p_light, s->n_light, s->prim);
        ASSERT_NEAR(pdf, s->pdf_solid_angle, 2e-3f * s->pdf_solid_angle) << what;
        // On the triangle it names (points on a shared edge belong to both).
        const uint32_t* idx = &mesh.indices[3 * s->prim];
        Vec3 a = mesh.p[idx[0]], b = mesh.p[idx[1]], c = mesh.p[idx[2]];
        Vec3 nt = normalize(cross(b - a, c - a));
        for (auto [e0, e1] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
            ASSERT_GE(dot(cross(e1 - e0, s->p_light - e0), nt), -1e-5f) << what;
        int x = std::clamp(int(s->p_light.x * g), 0, g - 1);
        int y = std::clamp(int(s->p_light.y * g), 0, g - 1);
        count[size_t(y * g + x)] += 1;
    }
    EXPECT_LT(misses, n / 1000) << what;
    std::vector<double> expected(g * g, 0);
    double total = 0;
    for (int j = 0; j < g; ++j)
        for (int i = 0; i < g; ++i) {
            double e = 0;
            for (int b = 0; b < k; ++b)
                for (int a = 0; a < k; ++a) {
                    Vec3 q((i + (a + 0.5f) / k) / g, (j + (b + 0.5f) / k) / g, 1);
                    int t = triangle_at(mesh, q);
                    if (t < 0) continue;
                    Vec3 d = q - ctx.p;
                    float d2 = length_squared(d);
                    Vec3 wi = d / std::sqrt(d2);
                    float cos_l = std::abs(wi.z);
                    e += light->pdf_li(ctx, wi, q, {0, 0, -1}, uint32_t(t)) * cos_l / d2;
                }
            expected[size_t(j * g + i)] = e / (k * k * g * g);
            total += expected[size_t(j * g + i)];
        }
    // The density integrates to one over the light.
    EXPECT_NEAR(total, 1, 0.01) << what;
    double stat = 0;
    int dof = -1;
    for (size_t c = 0; c < count.size(); ++c) {
        double e = expected[c] * (n - misses);
        if (e < 5) continue;
        double diff = count[c] - e;
        stat += diff * diff / e;
        ++dof;
    }
    double p = chi2::chi2_survival(stat, dof);
    EXPECT_GT(p, 0.001) << what << ": chi2 " << stat << " on " << dof << " dof";
}

TEST(AreaLightSampling, SolidAngleWithCosineWarp) {
    check_square_light(
        {{0.2f, 0.3f, 0}, normalize(Vec3(0.3f, 0, 1)), normalize(Vec3(0.5f, 0.2f, 1))},
        "tilted receiver below");
}
TEST(AreaLightSampling, SolidAngleCloseUp) {
    check_square_light({{0.55f, 0.45f, 0.9f}, {0, 0, 1}, normalize(Vec3(-0.4f, 0.1f, 1))},
                       "close below");
}
TEST(AreaLightSampling, SolidAngleWithoutNormal) {
    check_square_light({{0.7f, -0.2f, 0.4f}, {}, {}}, "point in a medium");
}
TEST(AreaLightSampling, LargeMeshChoosesByArea) {
    // 32 triangles: chosen by area, then each by solid angle.
    check_square_light({{0.2f, 0.3f, 0.5f}, {0, 0, 1}, normalize(Vec3(0.5f, 0.2f, 1))}, "grid mesh",
                       4);
}
TEST(AreaLightSampling, AreaWhenSeenTiny) {
    check_square_light({{0.5f, 0.5f, -150}, {0, 0, 1}, {0, 0, 1}}, "far below");
}

}  // namespace
}  // namespace ml
