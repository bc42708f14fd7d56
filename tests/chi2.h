// Chi-square goodness-of-fit of a direction sampler against its claimed density on the sphere
// (after pbrt-v4's bsdfs_test.cpp and Mitsuba's chi2 module). Shared by the BSDF, warp and light
// tests.
//
// Usage:
//   auto r = ml::chi2::test([&](ml::Rng& rng) -> std::optional<ml::Vec3> { ... },
//                           [&](const ml::Vec3& w) -> double { return pdf(w); }, options);
//   EXPECT_GT(r.p_value, ml::chi2::sidak_alpha(0.01, number_of_tests)) << r.message;
//
// Directions are binned by (theta, phi); expected counts are the density integrated over each bin
// by adaptive Simpson quadrature. Samples the sampler rejects (nullopt) form one more bin whose
// expected count is the probability the density leaves unaccounted for (1 - its integral), so a
// sampler that can fail, or that has delta lobes it reports as nullopt, is tested for its
// failure rate too. Bins with small expected counts are pooled before the statistic is formed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/rng.h"

namespace ml::chi2 {

// Regularised upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a).
inline double gamma_q(double a, double x) {
    if (x <= 0) return 1;
    double log_prefix = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1) {
        // Series for P(a, x).
        double term = 1 / a, sum = term;
        for (int n = 1; n < 10000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-15) break;
        }
        return std::max(0.0, 1 - sum * std::exp(log_prefix));
    }
    // Continued fraction for Q(a, x) (modified Lentz).
    const double tiny = 1e-300;
    double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1 / d;
        double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1) < 1e-15) break;
    }
    return std::exp(log_prefix) * h;
}

// Probability that a chi-square variable with `dof` degrees of freedom exceeds `stat`.
inline double chi2_survival(double stat, int dof) {
    if (dof <= 0) return 1;
    return gamma_q(0.5 * dof, 0.5 * stat);
}

// Per-test significance that keeps the family-wise false-failure rate at `alpha` over `tests`.
inline double sidak_alpha(double alpha, int tests) {
    return 1 - std::pow(1 - alpha, 1.0 / std::max(1, tests));
}

namespace detail {

template <typename F>
double simpson_1d(const F& f, double a, double b, double fa, double fm, double fb, double whole,
                  double eps, int depth) {
    double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    double flm = f(lm), frm = f(rm);
    double left = (m - a) / 6 * (fa + 4 * flm + fm), right = (b - m) / 6 * (fm + 4 * frm + fb);
    double delta = left + right - whole;
    if (depth <= 0 || std::abs(delta) <= 15 * eps) return left + right + delta / 15;
    return simpson_1d(f, a, m, fa, flm, fm, left, eps / 2, depth - 1) +
           simpson_1d(f, m, b, fm, frm, fb, right, eps / 2, depth - 1);
}

template <typename F>
double adaptive_simpson(const F& f, double a, double b, double eps, int depth) {
    double fa = f(a), fb = f(b), fm = f(0.5 * (a + b));
    double whole = (b - a) / 6 * (fa + 4 * fm + fb);
    return simpson_1d(f, a, b, fa, fm, fb, whole, eps, depth);
}

// Integral over [x0, x1] x [y0, y1] as nested adaptive Simpson rules.
template <typename F>
double adaptive_simpson_2d(const F& f, double x0, double y0, double x1, double y1, double eps,
                           int depth) {
    auto inner = [&](double x) {
        return adaptive_simpson([&](double y) { return f(x, y); }, y0, y1, eps, depth);
    };
    return adaptive_simpson(inner, x0, x1, eps, depth);
}

}  // namespace detail

struct Options {
    int theta_res = 10;
    int phi_res = 20;
    int sample_count = 200000;
    double min_expected = 5;  // bins expecting fewer samples are pooled
    uint64_t seed = 1;
    double quadrature_eps = 1e-7;
    int quadrature_depth = 8;
};

struct Result {
    double p_value = 0;
    double statistic = 0;
    int dof = 0;
    std::string message;  // why it failed, or a summary
};

// sample(Rng&) -> std::optional<Vec3> (unit directions); pdf(const Vec3&) -> density over solid
// angle of the directions sample() returns.
template <typename SampleFn, typename PdfFn>
Result test(SampleFn&& sample, PdfFn&& pdf, const Options& opt = {}) {
    const int nt = opt.theta_res, np = opt.phi_res, n_bins = nt * np;
    std::vector<double> observed(n_bins + 1, 0), expected(n_bins + 1, 0);
    Result res;

    // 1. Histogram of sampled directions; the last bin counts rejections.
    Rng rng(opt.seed);
    for (int i = 0; i < opt.sample_count; ++i) {
        std::optional<Vec3> w = sample(rng);
        if (!w) {
            observed[n_bins] += 1;
            continue;
        }
        Vec3 d = *w;
        double len = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
        if (!(std::abs(len - 1) < 1e-3)) {
            res.message = "sampler returned a direction that is not unit length";
            return res;
        }
        double theta = std::acos(std::clamp(double(d.z) / len, -1.0, 1.0));
        double phi = std::atan2(double(d.y), double(d.x));
        if (phi < 0) phi += 2 * M_PI;
        int ti = std::clamp(int(theta / M_PI * nt), 0, nt - 1);
        int pi = std::clamp(int(phi / (2 * M_PI) * np), 0, np - 1);
        observed[ti * np + pi] += 1;
    }

    // 2. Expected counts: the density integrated over each bin (with the sin(theta) Jacobian).
    auto density = [&](double theta, double phi) {
        double st = std::sin(theta);
        Vec3 w(float(st * std::cos(phi)), float(st * std::sin(phi)), float(std::cos(theta)));
        return double(pdf(w)) * st;
    };
    double total = 0;
    for (int ti = 0; ti < nt; ++ti) {
        for (int pi = 0; pi < np; ++pi) {
            // Bin edges are pulled in by a hair: densities are often discontinuous exactly on
            // an edge (the horizon at theta = pi/2), and the closed Simpson rule would take the
            // value on the wrong side there.
            const double inset = 1e-6;
            double t0 = M_PI * (ti + inset) / nt, t1 = M_PI * (ti + 1 - inset) / nt;
            double p0 = 2 * M_PI * (pi + inset) / np, p1 = 2 * M_PI * (pi + 1 - inset) / np;
            double integral = detail::adaptive_simpson_2d(density, t0, p0, t1, p1,
                                                          opt.quadrature_eps, opt.quadrature_depth);
            expected[ti * np + pi] = integral * opt.sample_count;
            total += integral;
        }
    }
    expected[n_bins] = std::max(0.0, 1 - total) * opt.sample_count;

    // 3. A direction where the density is zero is an outright failure.
    for (int i = 0; i < n_bins; ++i) {
        if (expected[i] == 0 && observed[i] > 0) {
            res.message = "samples fell in bin " + std::to_string(i) + " (theta " +
                          std::to_string(i / np) + ", phi " + std::to_string(i % np) +
                          ") where the density integrates to zero (" + std::to_string(observed[i]) +
                          " samples)";
            return res;
        }
    }

    // 4. Pool bins of small expectation (smallest first), then form the statistic.
    std::vector<int> order(n_bins + 1);
    for (int i = 0; i <= n_bins; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
    double pooled_exp = 0, pooled_obs = 0, stat = 0;
    int used = 0;
    for (int i : order) {
        if (expected[i] == 0) continue;
        if (expected[i] < opt.min_expected) {
            pooled_exp += expected[i];
            pooled_obs += observed[i];
        } else if (pooled_exp > 0 && pooled_exp < opt.min_expected) {
            // Fold a not-yet-large-enough pool into this bin.
            double e = expected[i] + pooled_exp, o = observed[i] + pooled_obs;
            stat += (o - e) * (o - e) / e;
            pooled_exp = pooled_obs = 0;
            ++used;
        } else {
            stat += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
            ++used;
        }
    }
    if (pooled_exp > 0) {
        stat += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        ++used;
    }
    res.statistic = stat;
    res.dof = used - 1;
    if (res.dof < 1) {
        res.message = "too few bins with enough expected samples";
        res.p_value = 1;
        return res;
    }
    res.p_value = chi2_survival(stat, res.dof);
    res.message = "chi2 = " + std::to_string(stat) + ", dof = " + std::to_string(res.dof) +
                  ", p = " + std::to_string(res.p_value) +
                  ", density integral = " + std::to_string(total) + ", rejected " +
                  std::to_string(observed[n_bins]) + " of " + std::to_string(opt.sample_count);
    return res;
}

}  // namespace ml::chi2
