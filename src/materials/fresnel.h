// Fresnel reflectance of dielectric and conducting interfaces, refraction, and the small warps the
// BSDFs need. Kept local to materials so the BSDFs do not depend on the sampling folder.
#pragma once

#include <complex>

#include "core/color.h"
#include "core/math.h"

namespace ml {

// Unpolarised Fresnel reflectance of a dielectric interface. eta = n_inside / n_outside, where
// "inside" is the -z side; cos_i < 0 means the light arrives from inside.
inline float fr_dielectric(float cos_i, float eta) {
    cos_i = std::clamp(cos_i, -1.f, 1.f);
    if (cos_i < 0) {
        eta = 1 / eta;
        cos_i = -cos_i;
    }
    float sin2_t = (1 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1) return 1;  // total internal reflection
    float cos_t = safe_sqrt(1 - sin2_t);
    float r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_parl * r_parl + r_perp * r_perp);
}

// Fresnel reflectance of a conductor with complex IOR eta + i k (cos_i in [0, 1]).
inline float fr_complex(float cos_i_f, float eta_re, float k) {
    // The unpolarised reflectance (|r_parl|^2 + |r_perp|^2) / 2 for the complex IOR eta + i k,
    // in real arithmetic (equal to the complex formulas, whose std::complex division and sqrt
    // are slow library calls), in double: near R = 1 the differences below cancel.
    double cos_i = std::clamp(double(cos_i_f), 0.0, 1.0);
    double cos2 = cos_i * cos_i, sin2 = 1 - cos2;
    double eta2 = double(eta_re) * eta_re, k2 = double(k) * k;
    double t0 = eta2 - k2 - sin2;
    double a2b2 = std::sqrt(std::max(0.0, t0 * t0 + 4 * eta2 * k2));  // |eta^2 - sin^2|
    double t1 = a2b2 + cos2;
    double a = std::sqrt(std::max(0.0, 0.5 * (a2b2 + t0)));
    double t2 = 2 * cos_i * a;
    double rs = t1 + t2 > 0 ? (t1 - t2) / (t1 + t2) : 1.0;
    double t3 = cos2 * a2b2 + sin2 * sin2;
    double t4 = t2 * sin2;
    double rp = t3 + t4 > 0 ? rs * (t3 - t4) / (t3 + t4) : rs;
    return float(0.5 * (rs + rp));
}

inline RGB fr_complex(float cos_i, const RGB& eta, const RGB& k) {
    return {fr_complex(cos_i, eta.r, k.r), fr_complex(cos_i, eta.g, k.g),
            fr_complex(cos_i, eta.b, k.b)};
}

// Refracts wi about n (both pointing away from the surface on wi's side when dot(wi, n) > 0).
// eta = n_inside / n_outside as for fr_dielectric; *etap receives the relative IOR actually
// crossed. Returns false on total internal reflection.
inline bool refract(const Vec3& wi, Vec3 n, float eta, float* etap, Vec3* wt) {
    float cos_i = dot(n, wi);
    if (cos_i < 0) {
        eta = 1 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    float sin2_t = std::max(0.f, 1 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1) return false;
    float cos_t = safe_sqrt(1 - sin2_t);
    *wt = -wi / eta + (cos_i / eta - cos_t) * n;
    if (etap) *etap = eta;
    return true;
}

// Hemispherical (cosine-weighted) average of the Fresnel reflectance seen from inside a
// dielectric of relative IOR eta: 2 * integral of F(cos) cos dcos, total internal reflection
// included. Integrated over cos^2 uniformly, where the integrand is smooth except at the
// critical angle.
inline float fresnel_diffuse_internal(float eta) {
    constexpr int kSteps = 2048;
    double sum = 0;
    for (int i = 0; i < kSteps; ++i) {
        float cos2 = (i + 0.5f) / kSteps;
        sum += fr_dielectric(-std::sqrt(cos2), eta);
    }
    return float(sum / kSteps);
}

// One round trip of diffusely reflected light inside pbrt-v4's coat layer of optical depth
// `thickness` (its LayeredBxDF has sigma_t = 1): up through the layer, Fresnel-reflected at the
// top from inside, down again, each pass attenuated by exp(-thickness / cos), averaged over the
// cosine-weighted directions leaving the base:
//   A = integral 2 mu F_int(mu) exp(-2 thickness / mu) dmu.
// With thickness 0 this is fresnel_diffuse_internal(eta).
inline float coat_internal_round_trip(float eta, float thickness) {
    constexpr int kSteps = 2048;
    double sum = 0;
    for (int i = 0; i < kSteps; ++i) {
        float cos2 = (i + 0.5f) / kSteps;
        float mu = std::sqrt(cos2);
        sum += fr_dielectric(-mu, eta) * std::exp(-2 * thickness / mu);
    }
    return float(sum / kSteps);
}

}  // namespace ml
