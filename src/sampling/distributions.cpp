#include "sampling/distributions.h"

#include <algorithm>

namespace ml {

Distribution1D::Distribution1D(std::span<const float> func) : m_func(func.begin(), func.end()) {
    size_t n = m_func.size();
    if (n == 0) return;
    for (float& f : m_func) f = std::isfinite(f) ? std::max(0.f, f) : 0.f;
    // Accumulate in double so that long light lists and large images keep an exact-enough CDF.
    std::vector<double> cdf(n + 1, 0.0);
    for (size_t i = 0; i < n; ++i) cdf[i + 1] = cdf[i] + double(m_func[i]) / double(n);
    m_integral = float(cdf[n]);
    m_cdf.resize(n + 1);
    if (cdf[n] <= 0) {
        for (size_t i = 0; i <= n; ++i) m_cdf[i] = float(double(i) / double(n));
    } else {
        for (size_t i = 0; i <= n; ++i) m_cdf[i] = float(cdf[i] / cdf[n]);
    }
    m_cdf[n] = 1.f;
}

size_t Distribution1D::find_bucket(float u) const {
    // The last i with cdf[i] <= u: buckets of zero width are skipped because a later equal entry
    // also qualifies, and u < 1 = cdf[n] keeps i < n.
    auto it = std::upper_bound(m_cdf.begin(), m_cdf.end(), u);
    size_t i = size_t(it - m_cdf.begin());
    i = i == 0 ? 0 : i - 1;
    return std::min(i, m_func.size() - 1);
}

float Distribution1D::pmf(size_t i) const {
    if (i >= m_func.size()) return 0.f;
    return m_cdf[i + 1] - m_cdf[i];
}

float Distribution1D::sample_continuous(float u, float* pdf, size_t* offset) const {
    size_t i = find_bucket(u);
    if (offset) *offset = i;
    float width = m_cdf[i + 1] - m_cdf[i];
    float du = width > 0 ? (u - m_cdf[i]) / width : 0.f;
    if (pdf) *pdf = width * float(m_func.size());
    float x = (float(i) + du) / float(m_func.size());
    return std::min(x, kOneMinusEpsilon);
}

float Distribution1D::pdf(float x) const {
    size_t n = m_func.size();
    if (n == 0 || !(x >= 0.f && x <= 1.f)) return 0.f;
    size_t i = std::min(size_t(x * float(n)), n - 1);
    return pmf(i) * float(n);
}

float Distribution1D::invert(float x) const {
    size_t n = m_func.size();
    x = std::clamp(x, 0.f, 1.f);
    size_t i = std::min(size_t(x * float(n)), n - 1);
    float t = x * float(n) - float(i);
    return lerp(t, m_cdf[i], m_cdf[i + 1]);
}

size_t Distribution1D::sample_discrete(float u, float* pmf_out, float* u_remapped) const {
    size_t i = find_bucket(u);
    float width = m_cdf[i + 1] - m_cdf[i];
    if (pmf_out) *pmf_out = width;
    if (u_remapped)
        *u_remapped = width > 0 ? std::min((u - m_cdf[i]) / width, kOneMinusEpsilon) : 0.f;
    return i;
}

Distribution2D::Distribution2D(std::span<const float> func, int nu, int nv) : m_nu(nu), m_nv(nv) {
    m_conditional.reserve(size_t(nv));
    std::vector<float> row_integrals(static_cast<size_t>(nv));
    for (int v = 0; v < nv; ++v) {
        m_conditional.emplace_back(func.subspan(size_t(v) * nu, size_t(nu)));
        row_integrals[size_t(v)] = m_conditional.back().integral();
    }
    m_marginal = Distribution1D(row_integrals);
}

Vec2 Distribution2D::sample(Vec2 u, float* pdf) const {
    float pdf_v, pdf_u;
    size_t v;
    float y = m_marginal.sample_continuous(u.y, &pdf_v, &v);
    float x = m_conditional[v].sample_continuous(u.x, &pdf_u);
    if (pdf) *pdf = pdf_u * pdf_v;
    return {x, y};
}

float Distribution2D::pdf(Vec2 p) const {
    if (!(p.x >= 0.f && p.x <= 1.f && p.y >= 0.f && p.y <= 1.f)) return 0.f;
    size_t v = std::min(size_t(p.y * float(m_nv)), size_t(m_nv - 1));
    return m_marginal.pdf(p.y) * m_conditional[v].pdf(p.x);
}

}  // namespace ml
