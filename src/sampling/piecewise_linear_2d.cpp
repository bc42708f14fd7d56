#include "sampling/piecewise_linear_2d.h"

#include <algorithm>
#include <cmath>

#include "core/assert.h"

namespace ml {

namespace {

// The largest i in [0, size - 2] with below(i) true (below: true, then false), or 0.
template <typename F>
int find_interval(int size, const F& below) {
    int lo = 0, hi = size - 1;  // below(lo) assumed, the answer in [lo, hi)
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (below(mid))
            lo = mid;
        else
            hi = mid;
    }
    return std::clamp(lo, 0, size - 2);
}

// The t in [0, 1] where the integral of the linear density a (1 - t) + b t from 0 reaches y.
float solve_linear_cdf(float a, float b, float y) {
    if (!(a + b > 0)) return 0.5f;
    float t = std::abs(a - b) < 1e-4f * (a + b)
                  ? 2 * y / (a + b)
                  : (a - std::sqrt(std::max(0.f, a * a - 2 * y * (a - b)))) / (a - b);
    return std::clamp(t, 0.f, 1.f);
}

}  // namespace

PiecewiseLinear2D::PiecewiseLinear2D(std::span<const float> values, int nx, int ny,
                                     std::vector<std::vector<float>> params, bool density)
    : m_nx(nx), m_ny(ny), m_params(std::move(params)) {
    ML_ASSERT(nx >= 2 && ny >= 2 && m_params.size() <= 3,
              "a grid of 2 x 2 or more, 3 parameters at most");
    uint32_t slices = 1;
    m_strides.resize(m_params.size());
    for (int d = int(m_params.size()) - 1; d >= 0; --d) {
        ML_ASSERT(!m_params[d].empty(), "a parameter without values");
        m_strides[d] = slices;
        slices *= uint32_t(m_params[d].size());
    }
    const size_t n = size_t(nx) * size_t(ny);
    ML_ASSERT(values.size() == slices * n, "one grid per parameter point");
    m_data.assign(values.begin(), values.end());
    if (density) {
        m_marginal.resize(slices * size_t(ny));
        m_conditional.resize(slices * n);
        for (uint32_t s = 0; s < slices; ++s) {
            float* data = &m_data[s * n];
            float* cond = &m_conditional[s * n];
            float* marg = &m_marginal[s * size_t(ny)];
            // Trapezoid sums with unit spacing: along each row, then over the rows' totals.
            for (int y = 0; y < ny; ++y) {
                double sum = 0;
                cond[y * nx] = 0;
                for (int x = 0; x + 1 < nx; ++x) {
                    sum += 0.5 * (double(data[y * nx + x]) + data[y * nx + x + 1]);
                    cond[y * nx + x + 1] = float(sum);
                }
            }
            double sum = 0;
            marg[0] = 0;
            for (int y = 0; y + 1 < ny; ++y) {
                sum += 0.5 * (double(cond[y * nx + nx - 1]) + cond[(y + 1) * nx + nx - 1]);
                marg[y + 1] = float(sum);
            }
            ML_ASSERT(sum > 0, "a density slice that sums to zero");
            const float norm = float(1 / sum);
            for (size_t i = 0; i < n; ++i) data[i] *= norm, cond[i] *= norm;
            for (int y = 0; y < ny; ++y) marg[y] *= norm;
        }
    }
    const float scale = density ? float(nx - 1) * float(ny - 1) : 1.f;
    for (float& v : m_data) m_max = std::max(m_max, v);
    m_max *= scale;
    m_scale = scale;
}

PiecewiseLinear2D::Slices PiecewiseLinear2D::slices(std::span<const float> params) const {
    ML_ASSERT(params.size() == m_params.size(), "one value per parameter");
    Slices s;
    for (size_t d = 0; d < m_params.size(); ++d) {
        const std::vector<float>& values = m_params[d];
        const int size = int(values.size());
        if (size == 1) continue;
        const float x = params[d];
        const int i = find_interval(size, [&](int k) { return values[k] <= x; });
        const float w1 = std::clamp((x - values[i]) / (values[i + 1] - values[i]), 0.f, 1.f);
        for (int c = 0; c < s.count; ++c) {
            s.index[s.count + c] = s.index[c] + m_strides[d] * uint32_t(i + 1);
            s.weight[s.count + c] = s.weight[c] * w1;
            s.index[c] += m_strides[d] * uint32_t(i);
            s.weight[c] *= 1 - w1;
        }
        s.count *= 2;
    }
    return s;
}

float PiecewiseLinear2D::lookup(const std::vector<float>& table, uint32_t stride, uint32_t at,
                                const Slices& s) const {
    float v = 0;
    for (int c = 0; c < s.count; ++c) v += s.weight[c] * table[s.index[c] * stride + at];
    return v;
}

PiecewiseLinear2D::Point PiecewiseLinear2D::sample(Vec2 u, std::span<const float> params) const {
    ML_ASSERT(!m_marginal.empty(), "sampling a table built without its CDFs");
    const Slices s = slices(params);
    const uint32_t nx = uint32_t(m_nx), n = nx * uint32_t(m_ny);
    u.x = std::clamp(u.x, 1e-7f, 1 - 1e-7f);
    u.y = std::clamp(u.y, 1e-7f, 1 - 1e-7f);

    // The row, and where in it, by the marginal.
    auto marginal = [&](int y) { return lookup(m_marginal, uint32_t(m_ny), uint32_t(y), s); };
    const int row = find_interval(m_ny, [&](int y) { return marginal(y) < u.y; });
    const uint32_t off = uint32_t(row) * nx;
    const float r0 = lookup(m_conditional, n, off + nx - 1, s);
    const float r1 = lookup(m_conditional, n, off + 2 * nx - 1, s);
    const float t = solve_linear_cdf(r0, r1, u.y - marginal(row));

    // The column, along the row interpolated at t.
    const float target = u.x * ((1 - t) * r0 + t * r1);
    auto conditional = [&](int x) {
        return (1 - t) * lookup(m_conditional, n, off + uint32_t(x), s) +
               t * lookup(m_conditional, n, off + nx + uint32_t(x), s);
    };
    const int col = find_interval(m_nx, [&](int x) { return conditional(x) < target; });
    const uint32_t at = off + uint32_t(col);
    const float v00 = lookup(m_data, n, at, s), v10 = lookup(m_data, n, at + 1, s);
    const float v01 = lookup(m_data, n, at + nx, s), v11 = lookup(m_data, n, at + nx + 1, s);
    const float c0 = (1 - t) * v00 + t * v01, c1 = (1 - t) * v10 + t * v11;
    const float sx = solve_linear_cdf(c0, c1, target - conditional(col));
    return {Vec2((float(col) + sx) / float(m_nx - 1), (float(row) + t) / float(m_ny - 1)),
            ((1 - sx) * c0 + sx * c1) * m_scale};
}

PiecewiseLinear2D::Patch PiecewiseLinear2D::patch(Vec2 p, const Slices& s) const {
    Patch q;
    const uint32_t nx = uint32_t(m_nx), n = nx * uint32_t(m_ny);
    const float fx = std::clamp(p.x, 0.f, 1.f) * float(m_nx - 1);
    const float fy = std::clamp(p.y, 0.f, 1.f) * float(m_ny - 1);
    q.col = std::min(int(fx), m_nx - 2), q.row = std::min(int(fy), m_ny - 2);
    q.sx = fx - float(q.col), q.ty = fy - float(q.row);
    q.at = uint32_t(q.row) * nx + uint32_t(q.col);
    const float v00 = lookup(m_data, n, q.at, s), v10 = lookup(m_data, n, q.at + 1, s);
    const float v01 = lookup(m_data, n, q.at + nx, s), v11 = lookup(m_data, n, q.at + nx + 1, s);
    q.c0 = (1 - q.ty) * v00 + q.ty * v01, q.c1 = (1 - q.ty) * v10 + q.ty * v11;
    return q;
}

PiecewiseLinear2D::Point PiecewiseLinear2D::invert(Vec2 p, std::span<const float> params) const {
    ML_ASSERT(!m_marginal.empty(), "sampling a table built without its CDFs");
    const Slices s = slices(params);
    const uint32_t nx = uint32_t(m_nx), n = nx * uint32_t(m_ny);
    const Patch q = patch(p, s);
    const float sx = q.sx, ty = q.ty, c0 = q.c0, c1 = q.c1;
    const uint32_t off = uint32_t(q.row) * nx;
    const float r0 = lookup(m_conditional, n, off + nx - 1, s);
    const float r1 = lookup(m_conditional, n, off + 2 * nx - 1, s);
    const float row_total = (1 - ty) * r0 + ty * r1;
    const float along = sx * (c0 + 0.5f * sx * (c1 - c0)) +
                        (1 - ty) * lookup(m_conditional, n, q.at, s) +
                        ty * lookup(m_conditional, n, q.at + nx, s);
    const float ux = row_total > 0 ? along / row_total : 0.f;
    const float uy =
        ty * (r0 + 0.5f * ty * (r1 - r0)) + lookup(m_marginal, uint32_t(m_ny), uint32_t(q.row), s);
    return {Vec2(ux, uy), ((1 - sx) * c0 + sx * c1) * m_scale};
}

float PiecewiseLinear2D::eval(Vec2 p, std::span<const float> params) const {
    const Patch q = patch(p, slices(params));
    return ((1 - q.sx) * q.c0 + q.sx * q.c1) * m_scale;
}

}  // namespace ml
