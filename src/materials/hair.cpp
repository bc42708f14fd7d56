#include "materials/hair.h"

#include <algorithm>
#include <cmath>

#include "materials/fresnel.h"

namespace ml {

namespace {

// The modified Bessel function of the first kind, order 0, by its series summed to convergence
// (in double: its terms reach e^x). pbrt-v4 stops at ten terms, which loses up to 2% near the
// longitudinal lobe's peak for beta_m about 0.3 and leaves its pdf short of its sampling.
double bessel_i0(double x) {
    double sum = 1, term = 1, x2_4 = x * x / 4;
    for (int i = 1; i < 200; ++i) {
        term *= x2_4 / (double(i) * double(i));
        sum += term;
        if (term < sum * 1e-12) break;
    }
    return sum;
}

// log I0(x); beyond x = 20 by its asymptotic expansion (error below 1e-7 there).
float log_bessel_i0(float x) {
    if (x > 20) {
        double ix = 1.0 / x;
        return float(x - 0.5 * std::log(2 * 3.14159265358979323846 * x) +
                     std::log1p(ix / 8 + 9 * ix * ix / 128 + 225 * ix * ix * ix / 3072));
    }
    return float(std::log(bessel_i0(x)));
}

// The longitudinal lobe of variance v (d'Eon et al. 2011): e^(-b) I0(a) / (2 v sinh(1 / v)),
// in the log domain for small v.
float longitudinal(float cos_i, float cos_o, float sin_i, float sin_o, float v) {
    float a = cos_i * cos_o / v, b = sin_i * sin_o / v;
    if (v <= 0.1f)
        return std::exp(log_bessel_i0(a) - b - 1 / v - std::log(v) - std::log1p(-std::exp(-2 / v)));
    return float(std::exp(-b) * bessel_i0(a) / (std::sinh(1 / v) * 2 * v));
}

float logistic(float x, float s) {
    x = std::abs(x);
    float e = std::exp(-x / s);
    return e / (s * sqr(1 + e));
}
float logistic_cdf(float x, float s) { return 1 / (1 + std::exp(-x / s)); }

// The logistic of scale s restricted to [-pi, pi] and renormalised.
float trimmed_logistic(float x, float s) {
    return logistic(x, s) / (logistic_cdf(kPi, s) - logistic_cdf(-kPi, s));
}

float sample_trimmed_logistic(float u, float s) {
    float lo = logistic_cdf(-kPi, s), k = logistic_cdf(kPi, s) - lo;
    float x = -s * std::log(1 / (u * k + lo) - 1);
    return std::clamp(x, -kPi, kPi);
}

// The azimuth the lobe p leaves at (Chiang et al.'s Phi).
float lobe_azimuth(int p, float gamma_o, float gamma_t) {
    return 2 * float(p) * gamma_t - 2 * gamma_o + float(p) * kPi;
}

float azimuthal(float phi, int p, float s, float gamma_o, float gamma_t) {
    float d = phi - lobe_azimuth(p, gamma_o, gamma_t);
    d = std::remainder(d, 2 * kPi);  // into [-pi, pi]
    return trimmed_logistic(d, s);
}

}  // namespace

HairBxdf::HairBxdf(float h, float eta, const RGB& sigma_a, float beta_m, float beta_n, float alpha)
    : m_h(std::clamp(h, -1.f, 1.f)), m_eta(eta), m_sigma_a(sigma_a) {
    m_gamma_o = safe_asin(m_h);
    // Longitudinal variances from the roughness beta_m (the fit of Chiang et al.): TT half as
    // wide as R, TRT and beyond twice as wide.
    m_v[0] = sqr(0.726f * beta_m + 0.812f * sqr(beta_m) + 3.7f * std::pow(beta_m, 20.f));
    m_v[1] = 0.25f * m_v[0];
    m_v[2] = 4 * m_v[0];
    for (int p = 3; p <= kPMax; ++p) m_v[p] = m_v[2];
    // The azimuthal logistic's scale from beta_n.
    m_s = 0.626657069f * (0.265f * beta_n + 1.194f * sqr(beta_n) + 5.372f * std::pow(beta_n, 22.f));
    // sin and cos of 2^k alpha: the scales tilt R by 2 alpha, TT by -alpha, TRT by -4 alpha.
    m_sin2k_alpha[0] = std::sin(radians(alpha));
    m_cos2k_alpha[0] = safe_sqrt(1 - sqr(m_sin2k_alpha[0]));
    for (int i = 1; i < kPMax; ++i) {
        m_sin2k_alpha[i] = 2 * m_cos2k_alpha[i - 1] * m_sin2k_alpha[i - 1];
        m_cos2k_alpha[i] = sqr(m_cos2k_alpha[i - 1]) - sqr(m_sin2k_alpha[i - 1]);
    }
}

void HairBxdf::tilted(int p, float sin_o, float cos_o, float* sin_p, float* cos_p) const {
    if (p == 0) {
        *sin_p = sin_o * m_cos2k_alpha[1] - cos_o * m_sin2k_alpha[1];
        *cos_p = cos_o * m_cos2k_alpha[1] + sin_o * m_sin2k_alpha[1];
    } else if (p == 1) {
        *sin_p = sin_o * m_cos2k_alpha[0] + cos_o * m_sin2k_alpha[0];
        *cos_p = cos_o * m_cos2k_alpha[0] - sin_o * m_sin2k_alpha[0];
    } else if (p == 2) {
        *sin_p = sin_o * m_cos2k_alpha[2] + cos_o * m_sin2k_alpha[2];
        *cos_p = cos_o * m_cos2k_alpha[2] - sin_o * m_sin2k_alpha[2];
    } else {
        *sin_p = sin_o;
        *cos_p = cos_o;
    }
    *cos_p = std::abs(*cos_p);
}

void HairBxdf::refraction(float sin_o, RGB* t, float* gamma_t) const {
    float cos_o = safe_sqrt(1 - sqr(sin_o));
    float sin_t = sin_o / m_eta, cos_t = safe_sqrt(1 - sqr(sin_t));
    // The modified index of refraction in the plane across the fibre (Bravais).
    float etap = safe_sqrt(sqr(m_eta) - sqr(sin_o)) / cos_o;
    float sin_gt = m_h / etap, cos_gt = safe_sqrt(1 - sqr(sin_gt));
    *gamma_t = safe_asin(sin_gt);
    float len = 2 * cos_gt / cos_t;
    *t = RGB(std::exp(-m_sigma_a.r * len), std::exp(-m_sigma_a.g * len),
             std::exp(-m_sigma_a.b * len));
}

std::array<RGB, HairBxdf::kPMax + 1> HairBxdf::attenuation(float cos_o, const RGB& t) const {
    std::array<RGB, kPMax + 1> ap;
    float f = fr_dielectric(cos_o * safe_sqrt(1 - sqr(m_h)), m_eta);
    ap[0] = RGB(f);
    ap[1] = t * sqr(1 - f);
    for (int p = 2; p < kPMax; ++p) ap[p] = ap[p - 1] * t * f;
    // The rest of the orders, summed as a geometric series.
    for (int c = 0; c < 3; ++c) {
        float tf = t[c] * f;
        ap[kPMax][c] = tf < 1 ? ap[kPMax - 1][c] * tf / (1 - tf) : 0.f;
    }
    return ap;
}

std::array<float, HairBxdf::kPMax + 1> HairBxdf::lobe_pdf(float cos_o) const {
    RGB t;
    float gamma_t;
    refraction(safe_sqrt(1 - sqr(cos_o)), &t, &gamma_t);
    std::array<RGB, kPMax + 1> ap = attenuation(cos_o, t);
    std::array<float, kPMax + 1> pdf;
    float sum = 0;
    for (int p = 0; p <= kPMax; ++p) sum += (pdf[size_t(p)] = ap[size_t(p)].average());
    for (float& w : pdf) w = sum > 0 ? w / sum : 0.f;
    return pdf;
}

RGB HairBxdf::eval(const Vec3& wo, const Vec3& wi, TransportMode) const {
    const float sin_o = wo.x, cos_o = safe_sqrt(1 - sqr(sin_o));
    const float sin_i = wi.x, cos_i = safe_sqrt(1 - sqr(sin_i));
    const float phi = std::atan2(wi.z, wi.y) - std::atan2(wo.z, wo.y);
    RGB t;
    float gamma_t;
    refraction(sin_o, &t, &gamma_t);
    std::array<RGB, kPMax + 1> ap = attenuation(cos_o, t);
    RGB sum;
    for (int p = 0; p < kPMax; ++p) {
        float sin_p, cos_p;
        tilted(p, sin_o, cos_o, &sin_p, &cos_p);
        sum += ap[size_t(p)] * (longitudinal(cos_i, cos_p, sin_i, sin_p, m_v[p]) *
                                azimuthal(phi, p, m_s, m_gamma_o, gamma_t));
    }
    sum += ap[kPMax] * (longitudinal(cos_i, cos_o, sin_i, sin_o, m_v[kPMax]) * kInv2Pi);
    // The model gives f |cos theta_i|; the cosine is the shading normal's (pbrt-v4's choice).
    if (wi.z != 0) sum = sum / std::abs(wi.z);
    return sum;
}

float HairBxdf::pdf_sum(const Vec3& wo, const Vec3& wi,
                        const std::array<float, kPMax + 1>& w) const {
    const float sin_o = wo.x, cos_o = safe_sqrt(1 - sqr(sin_o));
    const float sin_i = wi.x, cos_i = safe_sqrt(1 - sqr(sin_i));
    const float phi = std::atan2(wi.z, wi.y) - std::atan2(wo.z, wo.y);
    RGB t;
    float gamma_t;
    refraction(sin_o, &t, &gamma_t);
    float sum = 0;
    for (int p = 0; p < kPMax; ++p) {
        float sin_p, cos_p;
        tilted(p, sin_o, cos_o, &sin_p, &cos_p);
        sum += w[size_t(p)] * longitudinal(cos_i, cos_p, sin_i, sin_p, m_v[p]) *
               azimuthal(phi, p, m_s, m_gamma_o, gamma_t);
    }
    sum += w[kPMax] * longitudinal(cos_i, cos_o, sin_i, sin_o, m_v[kPMax]) * kInv2Pi;
    return sum;
}

float HairBxdf::pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode) const {
    return pdf_sum(wo, wi, lobe_pdf(safe_sqrt(1 - sqr(wo.x))));
}

std::optional<BsdfSample> HairBxdf::sample(const Vec3& wo, float uc, const Vec2& u,
                                           TransportMode mode) const {
    const float sin_o = wo.x, cos_o = safe_sqrt(1 - sqr(sin_o));
    const float phi_o = std::atan2(wo.z, wo.y);
    // The lobe p by its share of the attenuation; uc is then reused for the azimuth.
    std::array<float, kPMax + 1> w = lobe_pdf(cos_o);
    int p = 0;
    for (; p < kPMax; ++p) {
        if (uc < w[size_t(p)]) break;
        uc -= w[size_t(p)];
    }
    uc = w[size_t(p)] > 0 ? std::min(uc / w[size_t(p)], 0x1.fffffep-1f) : 0.f;
    float sin_p, cos_p;
    tilted(p, sin_o, cos_o, &sin_p, &cos_p);
    // theta_i from Mp (d'Eon et al. 2013's sampling of the longitudinal lobe).
    const float v = m_v[p];
    float cos_t = 1 + v * std::log(std::max(u.x, 1e-5f) + (1 - u.x) * std::exp(-2 / v));
    float sin_t = safe_sqrt(1 - sqr(cos_t));
    float sin_i = -cos_t * sin_p + sin_t * std::cos(2 * kPi * u.y) * cos_p;
    float cos_i = safe_sqrt(1 - sqr(sin_i));
    // The azimuth from Np about the lobe's exit azimuth.
    RGB t;
    float gamma_t;
    refraction(sin_o, &t, &gamma_t);
    float dphi = p < kPMax ? lobe_azimuth(p, m_gamma_o, gamma_t) + sample_trimmed_logistic(uc, m_s)
                           : 2 * kPi * uc;
    float phi_i = phi_o + dphi;
    BsdfSample s;
    s.wi = Vec3(sin_i, cos_i * std::cos(phi_i), cos_i * std::sin(phi_i));
    s.pdf_solid_angle = pdf_sum(wo, s.wi, w);
    s.f = eval(wo, s.wi, mode);
    s.flags = kBxdfGlossyReflection;
    if (!(s.pdf_solid_angle > 0)) return std::nullopt;
    return s;
}

RGB HairBxdf::max_value_bound(const Vec3& wo, const DirectionCone& cone) const {
    // f |cos theta_i| = sum_p Mp Ap Np. Ap does not depend on wi; Np is at most its peak; and
    // with I0(a) <= e^a, Mp <= exp((cos(theta_i + theta_p) - 1) / v) / (v (1 - e^(-2/v))), where
    // theta_p is theta_o tilted for lobe p: largest where theta_i comes nearest -theta_p over the
    // cone's directions (theta_i = pi/2 - angle(wi, x)).
    if (cone.is_empty()) return RGB();
    const float sin_o = wo.x, cos_o = safe_sqrt(1 - sqr(sin_o));
    float ax = angle_between(normalize(cone.axis), Vec3(1, 0, 0)), ca = cone_angle(cone);
    const float theta_hi = 0.5f * kPi - std::max(0.f, ax - ca);
    const float theta_lo = 0.5f * kPi - std::min(kPi, ax + ca);
    auto mp_bound = [&](float sin_p, float cos_p, float v) {
        float theta_p = std::atan2(sin_p, cos_p);
        float target = std::clamp(-theta_p, theta_lo, theta_hi);
        float c = std::cos(target + theta_p);
        return std::exp((c - 1) / v) / (v * -std::expm1(-2 / v));
    };
    RGB t;
    float gamma_t;
    refraction(sin_o, &t, &gamma_t);
    std::array<RGB, kPMax + 1> ap = attenuation(cos_o, t);
    const float np_max = trimmed_logistic(0, m_s);
    RGB bound;
    for (int p = 0; p < kPMax; ++p) {
        float sin_p, cos_p;
        tilted(p, sin_o, cos_o, &sin_p, &cos_p);
        bound += ap[size_t(p)] * (mp_bound(sin_p, cos_p, m_v[p]) * np_max);
    }
    bound += ap[kPMax] * (mp_bound(sin_o, cos_o, m_v[kPMax]) * kInv2Pi);
    // Rounding in the lobes' evaluation (a few ulps): a margin keeps the bound above it.
    return bound * 1.001f;
}

RGB HairBxdf::sigma_a_from_concentration(float eumelanin, float pheomelanin) {
    return RGB(0.419f, 0.697f, 1.37f) * eumelanin + RGB(0.187f, 0.4f, 1.05f) * pheomelanin;
}

RGB HairBxdf::sigma_a_from_reflectance(const RGB& c, float beta_n) {
    float bn = beta_n;
    float d = 5.969f - 0.215f * bn + 2.532f * sqr(bn) - 10.73f * bn * bn * bn +
              5.574f * sqr(sqr(bn)) + 0.245f * std::pow(bn, 5.f);
    RGB out;
    for (int i = 0; i < 3; ++i) out[i] = sqr(std::log(c[i]) / d);
    return out;
}

Bsdf HairMaterial::get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const {
    TextureEvalContext ctx{si.p, si.uv, si.ng};
    float bm = std::clamp(m_beta_m.eval(ctx), 0.01f, 1.f);
    float bn = std::clamp(m_beta_n.eval(ctx), 0.01f, 1.f);
    float alpha = m_alpha.eval(ctx), eta = m_eta.eval(ctx);
    RGB sigma_a;
    if (m_source == Source::sigma_a) {
        RGB s = m_colour.eval(ctx);
        sigma_a = RGB(std::max(0.f, s.r), std::max(0.f, s.g), std::max(0.f, s.b));
    } else if (m_source == Source::reflectance) {
        RGB c = m_colour.eval(ctx);
        c = RGB(std::clamp(c.r, 0.f, 1.f), std::clamp(c.g, 0.f, 1.f), std::clamp(c.b, 0.f, 1.f));
        sigma_a = HairBxdf::sigma_a_from_reflectance(c, bn);
    } else {
        sigma_a = HairBxdf::sigma_a_from_concentration(std::max(0.f, m_eumelanin.eval(ctx)),
                                                       std::max(0.f, m_pheomelanin.eval(ctx)));
    }
    float h = -1 + 2 * std::clamp(si.uv.y, 0.f, 1.f);
    return Bsdf(Frame::from_normal_tangent(si.ns, si.dpdu), si.ng,
                scratch_new<HairBxdf>(scratch, h, eta, sigma_a, bm, bn, alpha));
}

}  // namespace ml
