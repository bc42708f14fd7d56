#include "materials/beam_diffusion.h"

#include <algorithm>
#include <cmath>

#include "core/math.h"
#include "materials/fresnel.h"

namespace ml {

namespace {

// The first two moments of the Fresnel reflectance over the hemisphere (polynomial fits, as
// pbrt-v4's FresnelMoment1 and FresnelMoment2).
float fresnel_moment1(float eta) {
    const float e2 = eta * eta, e3 = e2 * eta, e4 = e3 * eta, e5 = e4 * eta;
    if (eta < 1)
        return 0.45966f - 1.73965f * eta + 3.37668f * e2 - 3.904945f * e3 + 2.49277f * e4 -
               0.68441f * e5;
    return -4.61686f + 11.1136f * eta - 10.4646f * e2 + 5.11455f * e3 - 1.27198f * e4 +
           0.12746f * e5;
}

float fresnel_moment2(float eta) {
    const float e2 = eta * eta, e3 = e2 * eta, e4 = e3 * eta, e5 = e4 * eta;
    if (eta < 1)
        return 0.27614f - 0.87350f * eta + 1.12077f * e2 - 0.65095f * e3 + 0.07883f * e4 +
               0.04860f * e5;
    const float r = 1 / eta, r2 = r * r, r3 = r2 * r;
    return -547.033f + 45.3087f * r3 - 218.725f * r2 + 458.843f * r + 404.557f * eta -
           189.519f * e2 + 54.9327f * e3 - 9.00603f * e4 + 0.63942f * e5;
}

// Henyey-Greenstein of the cosine between two directions pointing away from the point.
float henyey_greenstein(float cos_theta, float g) {
    const float denom = 1 + g * g + 2 * g * cos_theta;
    return (1 - g * g) / (4 * kPi * denom * std::sqrt(std::max(denom, 0.f)));
}

// The depth drawn by u from the exponential density a exp(-a x).
float sample_exponential(float u, float a) { return -std::log(1 - u) / a; }

constexpr int kSamples = 100;

float multiple_scattering(float sigma_s, float sigma_a, float g, float eta, float r) {
    // The reduced coefficients, Grosjean's diffusion coefficient, the effective transport
    // coefficient and the boundary's extrapolation distance.
    const float sp_s = sigma_s * (1 - g), sp_t = sigma_a + sp_s, rho_p = sp_s / sp_t;
    const float d_g = (2 * sigma_a + sp_s) / (3 * sp_t * sp_t);
    const float sigma_tr = std::sqrt(std::max(0.f, sigma_a / d_g));
    const float fm1 = fresnel_moment1(eta), fm2 = fresnel_moment2(eta);
    const float ze = -2 * d_g * (1 + 3 * fm2) / (1 - 2 * fm1);
    const float c_phi = 0.25f * (1 - 2 * fm1), c_e = 0.5f * (1 - 3 * fm2);
    float ed = 0;
    for (int i = 0; i < kSamples; ++i) {
        // A real source at depth zr and its virtual mirror at zv.
        const float zr = sample_exponential((float(i) + 0.5f) / kSamples, sp_t);
        const float zv = -zr + 2 * ze;
        const float dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
        const float phi_d =
            1 / (4 * kPi) / d_g * (std::exp(-sigma_tr * dr) / dr - std::exp(-sigma_tr * dv) / dv);
        const float ed_n = 1 / (4 * kPi) *
                           (zr * (1 + sigma_tr * dr) * std::exp(-sigma_tr * dr) / (dr * dr * dr) -
                            zv * (1 + sigma_tr * dv) * std::exp(-sigma_tr * dv) / (dv * dv * dv));
        const float e = phi_d * c_phi + ed_n * c_e;
        const float kappa = 1 - std::exp(-2 * sp_t * (dr + zr));
        ed += kappa * rho_p * rho_p * e;
    }
    return ed / kSamples;
}

float single_scattering(float sigma_s, float sigma_a, float g, float eta, float r) {
    const float sigma_t = sigma_a + sigma_s, rho = sigma_s / sigma_t;
    const float t_crit = r * std::sqrt(std::max(0.f, eta * eta - 1));
    float ess = 0;
    for (int i = 0; i < kSamples; ++i) {
        const float ti = t_crit + sample_exponential((float(i) + 0.5f) / kSamples, sigma_t);
        const float d = std::sqrt(r * r + ti * ti);
        const float cos_o = ti / d;
        ess += rho * std::exp(-sigma_t * (d + t_crit)) / (d * d) * henyey_greenstein(cos_o, g) *
               (1 - fr_dielectric(-cos_o, eta)) * std::abs(cos_o);
    }
    return ess / kSamples;
}

// The spline segment of nodes/f at interval i: its endpoints and finite-difference slopes
// (Catmull-Rom, as pbrt-v4's splines).
struct Segment {
    float x0, width, f0, f1, d0, d1;
};
Segment segment(const std::vector<float>& x, const std::vector<float>& f, size_t i) {
    Segment s{x[i], x[i + 1] - x[i], f[i], f[i + 1], 0, 0};
    s.d0 = i > 0 ? s.width * (s.f1 - f[i - 1]) / (x[i + 1] - x[i - 1]) : s.f1 - s.f0;
    s.d1 = i + 2 < x.size() ? s.width * (f[i + 2] - s.f0) / (x[i + 2] - x[i]) : s.f1 - s.f0;
    return s;
}
float spline_value(const Segment& s, float t) {
    const float t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * s.f0 + (-2 * t3 + 3 * t2) * s.f1 + (t3 - 2 * t2 + t) * s.d0 +
           (t3 - t2) * s.d1;
}
float spline_slope(const Segment& s, float t) {
    const float t2 = t * t;
    return (6 * t2 - 6 * t) * s.f0 + (-6 * t2 + 6 * t) * s.f1 + (3 * t2 - 4 * t + 1) * s.d0 +
           (3 * t2 - 2 * t) * s.d1;
}
// The interval [v[i], v[i + 1]] holding u (v increasing), clamped to the ends.
size_t interval(const std::vector<float>& v, float u) {
    const auto it = std::upper_bound(v.begin(), v.end(), u);
    const size_t i = it == v.begin() ? 0 : size_t(it - v.begin()) - 1;
    return std::min(i, v.size() - 2);
}

}  // namespace

float beam_diffusion_profile(float rho, float g, float eta, float r) {
    return single_scattering(rho, 1 - rho, g, eta, r) +
           multiple_scattering(rho, 1 - rho, g, eta, r);
}

BeamDiffusionTable::BeamDiffusionTable(float g, float eta) {
    constexpr int kAlbedos = 100, kRadii = 64;
    std::vector<float> radius(kRadii);
    radius[0] = 0;
    radius[1] = 2.5e-3f;
    for (int i = 2; i < kRadii; ++i) radius[size_t(i)] = radius[size_t(i) - 1] * 1.2f;
    m_rho.resize(kAlbedos);
    m_rho_eff.resize(kAlbedos);
    std::vector<float> profile(kRadii);
    for (int i = 0; i < kAlbedos; ++i) {
        const float rho = (1 - std::exp(-8.f * float(i) / (kAlbedos - 1))) / (1 - std::exp(-8.f));
        m_rho[size_t(i)] = rho;
        for (int j = 0; j < kRadii; ++j) {
            const float r = radius[size_t(j)];
            profile[size_t(j)] = 2 * kPi * r * beam_diffusion_profile(rho, g, eta, r);
        }
        // The profile integrated over the radii by its spline.
        float sum = 0;
        for (size_t j = 0; j + 1 < radius.size(); ++j) {
            const Segment s = segment(radius, profile, j);
            sum += s.width * ((s.f0 + s.f1) / 2 + (s.d0 - s.d1) / 12);
        }
        m_rho_eff[size_t(i)] = sum;
    }
}

float BeamDiffusionTable::effective_albedo(float rho) const {
    if (!(rho > m_rho.front())) return m_rho_eff.front();
    if (!(rho < m_rho.back())) return m_rho_eff.back();
    const size_t i = interval(m_rho, rho);
    const Segment s = segment(m_rho, m_rho_eff, i);
    return spline_value(s, (rho - s.x0) / s.width);
}

float BeamDiffusionTable::albedo_for(float reflectance) const {
    if (!(reflectance > m_rho_eff.front())) return m_rho.front();
    if (!(reflectance < m_rho_eff.back())) return m_rho.back();
    const size_t i = interval(m_rho_eff, reflectance);
    const Segment s = segment(m_rho, m_rho_eff, i);
    // Newton's method on the segment's cubic, kept inside [lo, hi] by bisection.
    float lo = 0, hi = 1, t = 0.5f;
    for (int k = 0; k < 64; ++k) {
        const float f = spline_value(s, t) - reflectance;
        if (std::abs(f) < 1e-6f) break;
        if (f < 0)
            lo = t;
        else
            hi = t;
        const float slope = spline_slope(s, t);
        float next = slope != 0 ? t - f / slope : 0.5f * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5f * (lo + hi);
        if (std::abs(next - t) < 1e-6f) {
            t = next;
            break;
        }
        t = next;
    }
    return s.x0 + t * s.width;
}

void subsurface_from_diffuse(const BeamDiffusionTable& table, const RGB& reflectance,
                             const RGB& mfp, RGB* sigma_a, RGB* sigma_s) {
    for (int c = 0; c < 3; ++c) {
        const float rho = table.albedo_for(std::clamp(reflectance[c], 0.f, 1.f));
        (*sigma_s)[c] = rho / mfp[c];
        (*sigma_a)[c] = (1 - rho) / mfp[c];
    }
}

}  // namespace ml
