// Warps and distributions: chi-square of every direction warp against its pdf, inverses, and
// discrete/2D distributions against their pmf and pdf.
#include <gtest/gtest.h>

#include "chi2.h"
#include "core/rng.h"
#include "sampling/distributions.h"
#include "sampling/warps.h"

namespace ml {
namespace {

constexpr int kWarpTests = 6;

Vec2 next2(Rng& rng) {
    float x = rng.next_float();
    return {x, rng.next_float()};
}

// Chi-square p-value of observed counts against expected counts (all expected > 0).
double histogram_p(const std::vector<double>& obs, const std::vector<double>& exp) {
    double stat = 0;
    int used = 0;
    for (size_t i = 0; i < obs.size(); ++i) {
        if (exp[i] <= 0) {
            if (obs[i] > 0) return 0;
            continue;
        }
        stat += sqr(float(obs[i] - exp[i])) / exp[i];
        ++used;
    }
    return chi2::chi2_survival(stat, used - 1);
}

TEST(Warps, CosineHemisphereChi2) {
    auto r = chi2::test(
        [](Rng& rng) -> std::optional<Vec3> { return sample_cosine_hemisphere(next2(rng)); },
        [](const Vec3& w) { return double(pdf_cosine_hemisphere(w.z)); });
    EXPECT_GT(r.p_value, chi2::sidak_alpha(0.01, kWarpTests)) << r.message;
}

TEST(Warps, UniformHemisphereSphereConeChi2) {
    double alpha = chi2::sidak_alpha(0.01, kWarpTests);
    auto r = chi2::test(
        [](Rng& rng) -> std::optional<Vec3> { return sample_uniform_hemisphere(next2(rng)); },
        [](const Vec3& w) { return w.z >= 0 ? double(pdf_uniform_hemisphere()) : 0.0; });
    EXPECT_GT(r.p_value, alpha) << r.message;
    r = chi2::test(
        [](Rng& rng) -> std::optional<Vec3> { return sample_uniform_sphere(next2(rng)); },
        [](const Vec3&) { return double(pdf_uniform_sphere()); });
    EXPECT_GT(r.p_value, alpha) << r.message;
    // A 45-degree cone tilted off +z, so it does not line up with the bins.
    float cos_max = std::cos(radians(45));
    Frame f = Frame::from_z(normalize(Vec3(0.3f, -0.2f, 1)));
    r = chi2::test(
        [&](Rng& rng) -> std::optional<Vec3> {
            return f.to_world(sample_uniform_cone(next2(rng), cos_max));
        },
        [&](const Vec3& w) {
            return dot(w, f.n) >= cos_max ? double(pdf_uniform_cone(cos_max)) : 0.0;
        });
    EXPECT_GT(r.p_value, alpha) << r.message;
}

TEST(Warps, EqualAreaSphereIsUniform) {
    auto r = chi2::test(
        [](Rng& rng) -> std::optional<Vec3> { return equal_area_square_to_sphere(next2(rng)); },
        [](const Vec3&) { return double(kInv4Pi); });
    EXPECT_GT(r.p_value, chi2::sidak_alpha(0.01, kWarpTests)) << r.message;
    // The square's centre is +z, its corners -z.
    Vec3 c = equal_area_square_to_sphere({0.5f, 0.5f});
    EXPECT_NEAR(c.z, 1.f, 1e-6f);
    EXPECT_NEAR(equal_area_square_to_sphere({0.f, 0.f}).z, -1.f, 1e-6f);
}

TEST(Warps, InversesRoundTrip) {
    Rng rng(7);
    float cos_max = 0.3f;
    for (int i = 0; i < 10000; ++i) {
        Vec2 u = next2(rng);
        auto near = [&](Vec2 v, const char* what) {
            ASSERT_NEAR(v.x, u.x, 2e-3f) << what << " u=" << u.x << "," << u.y;
            ASSERT_NEAR(v.y, u.y, 2e-3f) << what << " u=" << u.x << "," << u.y;
        };
        near(invert_uniform_disk_concentric(sample_uniform_disk_concentric(u)), "disk");
        near(invert_cosine_hemisphere(sample_cosine_hemisphere(u)), "cosine");
        near(invert_uniform_hemisphere(sample_uniform_hemisphere(u)), "hemisphere");
        near(invert_uniform_sphere(sample_uniform_sphere(u)), "sphere");
        near(invert_uniform_cone(sample_uniform_cone(u, cos_max), cos_max), "cone");
        near(invert_uniform_triangle(sample_uniform_triangle(u)), "triangle");
        near(equal_area_sphere_to_square(equal_area_square_to_sphere(u)), "equal-area");
        Vec3 w = equal_area_square_to_sphere(u);
        EXPECT_NEAR(length(w), 1.f, 1e-4f);
    }
    EXPECT_NEAR(invert_exponential(sample_exponential(0.3f, 2.f), 2.f), 0.3f, 1e-5f);
}

TEST(Warps, DiskIsUniform) {
    // Bins of equal area: 8 rings of equal r^2 width times 16 sectors.
    const int nr = 8, ns = 16, n = 200000;
    std::vector<double> obs(nr * ns, 0), exp(nr * ns, double(n) / (nr * ns));
    Rng rng(3);
    for (int i = 0; i < n; ++i) {
        Vec2 p = sample_uniform_disk_concentric(next2(rng));
        float r2 = p.x * p.x + p.y * p.y;
        ASSERT_LE(r2, 1.f + 1e-5f);
        float phi = std::atan2(p.y, p.x) + kPi;
        int ri = std::min(int(r2 * nr), nr - 1), si = std::min(int(phi / (2 * kPi) * ns), ns - 1);
        obs[ri * ns + si] += 1;
    }
    EXPECT_GT(histogram_p(obs, exp), 0.001);
}

TEST(Warps, TriangleIsUniform) {
    // A 4x4 grid over (b0, b1): cells inside the triangle expect 1/8 of the samples' density
    // share, cells on the diagonal half that, cells outside none.
    const int g = 4, n = 160000;
    std::vector<double> obs(g * g, 0), exp(g * g, 0);
    for (int i = 0; i < g; ++i)
        for (int j = 0; j < g; ++j)
            exp[i * g + j] = i + j < g - 1 ? 2.0 / 16 * n : (i + j == g - 1 ? 1.0 / 16 * n : 0);
    Rng rng(5);
    for (int k = 0; k < n; ++k) {
        Barycentrics b = sample_uniform_triangle(next2(rng));
        ASSERT_GE(b.b2, -1e-6f);
        int i = std::min(int(b.b0 * g), g - 1), j = std::min(int(b.b1 * g), g - 1);
        obs[i * g + j] += 1;
    }
    EXPECT_GT(histogram_p(obs, exp), 0.001);
}

TEST(Distribution, DiscreteFrequenciesMatchPmf) {
    std::vector<float> f = {0, 1, 3, 0, 0.5f, 10, 0};
    Distribution1D d(f);
    const int n = 200000;
    std::vector<double> obs(f.size(), 0), exp(f.size(), 0);
    double total = 0;
    for (float v : f) total += v;
    for (size_t i = 0; i < f.size(); ++i) {
        exp[i] = f[i] / total * n;
        EXPECT_NEAR(d.pmf(i), f[i] / total, 1e-6);
    }
    Rng rng(11);
    for (int k = 0; k < n; ++k) {
        float pmf, ur;
        size_t i = d.sample_discrete(rng.next_float(), &pmf, &ur);
        ASSERT_GT(pmf, 0.f);
        ASSERT_EQ(pmf, d.pmf(i));
        ASSERT_TRUE(ur >= 0 && ur < 1);
        obs[i] += 1;
    }
    EXPECT_GT(histogram_p(obs, exp), 0.001);
    // Edges of u never pick a zero bucket.
    EXPECT_GT(d.pmf(d.sample_discrete(0.f)), 0.f);
    EXPECT_GT(d.pmf(d.sample_discrete(kOneMinusEpsilon)), 0.f);
}

TEST(Distribution, ContinuousPdfIntegratesToOneAndInverts) {
    std::vector<float> f = {0.5f, 0, 2, 7, 1};
    Distribution1D d(f);
    double integral = 0;
    const int m = 100000;
    for (int i = 0; i < m; ++i) integral += d.pdf((i + 0.5f) / m) / m;
    EXPECT_NEAR(integral, 1.0, 1e-4);
    Rng rng(2);
    for (int i = 0; i < 1000; ++i) {
        float u = rng.next_float(), pdf;
        float x = d.sample_continuous(u, &pdf);
        EXPECT_NEAR(pdf, d.pdf(x), 1e-4f);
        EXPECT_GT(pdf, 0.f);
        EXPECT_NEAR(d.invert(x), u, 1e-4f);
    }
    Distribution1D zero(std::vector<float>{0, 0, 0});
    EXPECT_NEAR(zero.pmf(1), 1.f / 3, 1e-6f);
}

TEST(Distribution, TwoDimensionalSamplingMatchesPdf) {
    const int nu = 6, nv = 5;
    std::vector<float> f(nu * nv);
    Rng rng(9);
    for (float& v : f) v = rng.next_float() < 0.2f ? 0.f : rng.next_float() * 4;
    Distribution2D d(f, nu, nv);
    // The pdf integrates to 1 over [0,1]^2.
    double integral = 0;
    for (int y = 0; y < 200; ++y)
        for (int x = 0; x < 200; ++x) integral += d.pdf({(x + 0.5f) / 200, (y + 0.5f) / 200});
    EXPECT_NEAR(integral / (200 * 200), 1.0, 1e-3);
    // Samples per cell against the pdf over each cell (piecewise constant on the same grid).
    const int n = 200000;
    std::vector<double> obs(nu * nv, 0), exp(nu * nv, 0);
    for (int y = 0; y < nv; ++y)
        for (int x = 0; x < nu; ++x)
            exp[y * nu + x] = d.pdf({(x + 0.5f) / nu, (y + 0.5f) / nv}) / (nu * nv) * n;
    for (int k = 0; k < n; ++k) {
        float pdf;
        Vec2 p = d.sample(next2(rng), &pdf);
        ASSERT_NEAR(pdf, d.pdf(p), 1e-3f * pdf);
        obs[std::min(int(p.y * nv), nv - 1) * nu + std::min(int(p.x * nu), nu - 1)] += 1;
    }
    EXPECT_GT(histogram_p(obs, exp), 0.001);
}

}  // namespace
}  // namespace ml
