#include "sampling/windowed_distribution.h"

#include <algorithm>
#include <cmath>

namespace ml {

WindowedDistribution2D::WindowedDistribution2D(std::span<const float> func, int nu, int nv)
    : m_nu(nu), m_nv(nv), m_func(func.begin(), func.end()) {
    for (float& f : m_func) f = std::isfinite(f) ? std::max(f, 0.f) : 0.f;
    m_sat.assign(size_t(nu + 1) * size_t(nv + 1), 0.0);
    const double cell = 1.0 / (double(nu) * double(nv));
    for (int y = 0; y < nv; ++y) {
        double row = 0;
        for (int x = 0; x < nu; ++x) {
            row += double(m_func[size_t(y) * nu + x]) * cell;
            m_sat[size_t(y + 1) * (nu + 1) + x + 1] = m_sat[size_t(y) * (nu + 1) + x + 1] + row;
        }
    }
}

double WindowedDistribution2D::sat(float u, float v) const {
    const double x = std::clamp(double(u), 0.0, 1.0) * m_nu,
                 y = std::clamp(double(v), 0.0, 1.0) * m_nv;
    const int ix = std::min(int(x), m_nu - 1), iy = std::min(int(y), m_nv - 1);
    const double fx = x - ix, fy = y - iy;
    auto s = [&](int i, int j) { return m_sat[size_t(j) * (m_nu + 1) + i]; };
    return (1 - fx) * (1 - fy) * s(ix, iy) + fx * (1 - fy) * s(ix + 1, iy) +
           (1 - fx) * fy * s(ix, iy + 1) + fx * fy * s(ix + 1, iy + 1);
}

double WindowedDistribution2D::row_prefix(int r, float u) const {
    // Row r's integral over [0, u] x [r / nv, (r + 1) / nv], per unit of v.
    const float v0 = float(r) / float(m_nv), v1 = float(r + 1) / float(m_nv);
    return (sat(u, v1) - sat(u, v0)) * m_nv;
}

double WindowedDistribution2D::integral(const Window2& w) const {
    return sat(w.hi.x, w.hi.y) - sat(w.lo.x, w.hi.y) - sat(w.hi.x, w.lo.y) + sat(w.lo.x, w.lo.y);
}

float WindowedDistribution2D::value(const Vec2& p) const {
    const int x = std::clamp(int(p.x * float(m_nu)), 0, m_nu - 1);
    const int y = std::clamp(int(p.y * float(m_nv)), 0, m_nv - 1);
    return m_func[size_t(y) * m_nu + x];
}

namespace {

// Inverts a continuous, non-decreasing, piecewise-linear F over [lo, hi] whose pieces meet at
// the grid lines k / n: the x with F(x) = target, F(lo) <= target < F(hi). Bisects over the grid
// lines, then solves the piece linearly. `cell` receives the piece's grid cell.
template <typename F>
float invert_piecewise_linear(F f, float lo, float hi, int n, double target, int* cell) {
    int k0 = std::clamp(int(std::floor(lo * float(n))), 0, n - 1);
    int k1 = std::clamp(int(std::ceil(hi * float(n))), k0 + 1, n);
    auto at = [&](int k) { return std::clamp(float(k) / float(n), lo, hi); };
    // The last grid line at or below the target, among k0 .. k1 - 1.
    int a = k0, b = k1 - 1;
    while (a < b) {
        int mid = (a + b + 1) / 2;
        if (f(at(mid)) <= target)
            a = mid;
        else
            b = mid - 1;
    }
    *cell = a;
    const float x0 = at(a), x1 = at(a + 1);
    const double f0 = f(x0), f1 = f(x1);
    float t = f1 > f0 ? float((target - f0) / (f1 - f0)) : 0.5f;
    return std::clamp(x0 + std::clamp(t, 0.f, 1.f) * (x1 - x0), x0, x1);
}

}  // namespace

std::optional<Vec2> WindowedDistribution2D::sample(const Vec2& u, const Window2& w,
                                                   float* pdf) const {
    *pdf = 0;
    const double total = integral(w);
    if (!(total > 0) || w.hi.x <= w.lo.x || w.hi.y <= w.lo.y) return std::nullopt;
    // 1. v from the window's marginal, G(v) = integral over [lo.x, hi.x] x [lo.y, v].
    auto marginal = [&](float v) {
        return sat(w.hi.x, v) - sat(w.lo.x, v) - sat(w.hi.x, w.lo.y) + sat(w.lo.x, w.lo.y);
    };
    int row = 0, col = 0;
    Vec2 p;
    p.y = invert_piecewise_linear(marginal, w.lo.y, w.hi.y, m_nv, double(u.y) * total, &row);
    // 2. u within that row, from its integral over [lo.x, u].
    const double r0 = row_prefix(row, w.lo.x), r1 = row_prefix(row, w.hi.x);
    if (!(r1 > r0)) return std::nullopt;
    p.x = invert_piecewise_linear([&](float x) { return row_prefix(row, x); }, w.lo.x, w.hi.x, m_nu,
                                  r0 + double(u.x) * (r1 - r0), &col);
    // The density at the point returned, as pdf() gives it (a point on a cell's edge belongs
    // to the cell above it, in both).
    *pdf = float(double(value(p)) / total);
    if (!(*pdf > 0)) return std::nullopt;
    return p;
}

float WindowedDistribution2D::pdf(const Vec2& p, const Window2& w) const {
    if (!w.inside(p)) return 0;
    const double total = integral(w);
    return total > 0 ? float(double(value(p)) / total) : 0.f;
}

}  // namespace ml
