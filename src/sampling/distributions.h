// Piecewise-constant distributions: Distribution1D over [0,1] (continuous samples with a density,
// discrete samples with a pmf) and Distribution2D over [0,1]^2 (marginal rows, conditional
// columns). Sampling is a binary search over the CDF: O(log n), no allocation.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/math.h"

namespace ml {

class Distribution1D {
public:
    Distribution1D() = default;
    // Negative values count as zero. When every value is zero the distribution is uniform.
    explicit Distribution1D(std::span<const float> func);

    size_t size() const { return m_func.size(); }
    // The integral of the function over [0,1] (sum / n) before normalisation.
    float integral() const { return m_integral; }
    const std::vector<float>& func() const { return m_func; }

    // A point x in [0,1) with density pdf(x); `offset` receives the bucket.
    float sample_continuous(float u, float* pdf = nullptr, size_t* offset = nullptr) const;
    // Density (over [0,1]) at x.
    float pdf(float x) const;
    // The x that sample_continuous maps u to, inverted: u = invert(x).
    float invert(float x) const;

    // A bucket with probability pmf(i); `u_remapped` receives u rescaled to [0,1) inside it.
    // Buckets of zero weight are never returned (unless all are zero: then uniform).
    size_t sample_discrete(float u, float* pmf = nullptr, float* u_remapped = nullptr) const;
    float pmf(size_t i) const;

private:
    size_t find_bucket(float u) const;

    std::vector<float> m_func;  // clamped to >= 0
    std::vector<float> m_cdf;   // n + 1 entries, m_cdf[0] = 0, m_cdf[n] = 1
    float m_integral = 0;
};

class Distribution2D {
public:
    Distribution2D() = default;
    // func is nu x nv values, row-major (row v holds nu values along u).
    Distribution2D(std::span<const float> func, int nu, int nv);

    // A point (u, v) in [0,1)^2 with density pdf over [0,1]^2.
    Vec2 sample(Vec2 u, float* pdf) const;
    float pdf(Vec2 p) const;
    float integral() const { return m_marginal.integral(); }
    int nu() const { return m_nu; }
    int nv() const { return m_nv; }

private:
    std::vector<Distribution1D> m_conditional;  // one per row v
    Distribution1D m_marginal;                  // over rows
    int m_nu = 0, m_nv = 0;
};

}  // namespace ml
