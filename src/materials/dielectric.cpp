// Dielectrics: Fresnel-weighted specular reflection and refraction, or their GGX-rough versions
// with the generalised half vector (Walter et al. 2007). In Radiance mode, refracted radiance is
// scaled by 1 / eta^2 (the solid-angle compression), as in pbrt-v4.
#include "materials/bxdfs.h"
#include "materials/fresnel.h"

namespace ml {

uint8_t DielectricBxdf::flags() const {
    uint8_t f = m_eta == 1 ? kBxdfTransmission : (kBxdfReflection | kBxdfTransmission);
    return f | (smooth() ? kBxdfSpecular : kBxdfGlossy);
}

namespace {

// The generalised half vector of a reflection or refraction pair, in the +z hemisphere, and the
// relative IOR crossed; false for a degenerate pair.
bool half_vector(const Vec3& wo, const Vec3& wi, float eta, Vec3* wm, float* etap) {
    float cos_o = wo.z, cos_i = wi.z;
    bool reflect = cos_i * cos_o > 0;
    *etap = 1;
    if (!reflect) *etap = cos_o > 0 ? eta : 1 / eta;
    Vec3 m = wi * *etap + wo;
    if (cos_i == 0 || cos_o == 0 || length_squared(m) == 0) return false;
    m = face_forward(normalize(m), Vec3(0, 0, 1));
    // Microfacets seen from their back do not contribute.
    if (dot(m, wi) * cos_i < 0 || dot(m, wo) * cos_o < 0) return false;
    *wm = m;
    return true;
}

}  // namespace

RGB DielectricBxdf::eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    if (smooth()) return RGB();
    Vec3 wm;
    float etap;
    if (!half_vector(wo, wi, m_eta, &wm, &etap)) return RGB();
    float cos_o = wo.z, cos_i = wi.z;
    float fr = fr_dielectric(dot(wo, wm), m_eta);
    if (etap == 1) {
        return RGB(m_distrib.d(wm) * m_distrib.g(wo, wi) * fr / std::abs(4 * cos_i * cos_o));
    }
    float denom = sqr(dot(wi, wm) + dot(wo, wm) / etap) * cos_i * cos_o;
    float ft = m_distrib.d(wm) * (1 - fr) * m_distrib.g(wo, wi) *
               std::abs(dot(wi, wm) * dot(wo, wm) / denom);
    if (mode == TransportMode::Radiance) ft /= sqr(etap);
    return RGB(ft);
}

std::optional<BsdfSample> DielectricBxdf::sample(const Vec3& wo, float uc, const Vec2& u,
                                                 TransportMode mode) const {
    if (wo.z == 0) return std::nullopt;
    BsdfSample s;
    if (smooth()) {
        // Choose reflection or refraction by the Fresnel reflectance itself, so each sample has
        // weight one.
        float r = fr_dielectric(wo.z, m_eta), t = 1 - r;
        if (uc < r) {
            s.wi = Vec3(-wo.x, -wo.y, wo.z);
            s.f = RGB(r / std::abs(s.wi.z));
            s.pdf_solid_angle = r;
            s.flags = kBxdfSpecularReflection;
            return s;
        }
        float etap;
        Vec3 wi;
        if (!refract(wo, Vec3(0, 0, 1), m_eta, &etap, &wi) || wi.z == 0) return std::nullopt;
        float ft = t / std::abs(wi.z);
        if (mode == TransportMode::Radiance) ft /= sqr(etap);
        s.wi = wi;
        s.f = RGB(ft);
        s.pdf_solid_angle = t;
        s.flags = kBxdfSpecularTransmission;
        s.eta = etap;
        return s;
    }
    // Rough: a visible normal, then reflection or refraction about it by its Fresnel term.
    Vec3 wm = m_distrib.sample_wm(wo, u);
    float r = fr_dielectric(dot(wo, wm), m_eta), t = 1 - r;
    if (uc < r) {
        Vec3 wi = reflect(wo, wm);
        if (!same_hemisphere(wo, wi)) return std::nullopt;
        s.wi = wi;
        s.pdf_solid_angle = m_distrib.pdf(wo, wm) / (4 * abs_dot(wo, wm)) * r;
        s.f = RGB(m_distrib.d(wm) * m_distrib.g(wo, wi) * r / std::abs(4 * wi.z * wo.z));
        s.flags = kBxdfGlossyReflection;
        if (!(s.pdf_solid_angle > 0)) return std::nullopt;  // a grazing microfacet
        return s;
    }
    float etap;
    Vec3 wi;
    if (!refract(wo, wm, m_eta, &etap, &wi)) return std::nullopt;
    if (same_hemisphere(wo, wi) || wi.z == 0) return std::nullopt;
    float denom = sqr(dot(wi, wm) + dot(wo, wm) / etap);
    float dwm_dwi = abs_dot(wi, wm) / denom;
    s.wi = wi;
    s.pdf_solid_angle = m_distrib.pdf(wo, wm) * dwm_dwi * t;
    float ft = t * m_distrib.d(wm) * m_distrib.g(wo, wi) *
               std::abs(dot(wi, wm) * dot(wo, wm) / (wi.z * wo.z * denom));
    if (mode == TransportMode::Radiance) ft /= sqr(etap);
    s.f = RGB(ft);
    s.flags = kBxdfGlossyTransmission;
    s.eta = etap;
    if (!(s.pdf_solid_angle > 0)) return std::nullopt;
    return s;
}

float DielectricBxdf::pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode) const {
    if (smooth()) return 0;
    Vec3 wm;
    float etap;
    if (!half_vector(wo, wi, m_eta, &wm, &etap)) return 0;
    float r = fr_dielectric(dot(wo, wm), m_eta), t = 1 - r;
    if (etap == 1) return m_distrib.pdf(wo, wm) / (4 * abs_dot(wo, wm)) * r;
    float dwm_dwi = abs_dot(wi, wm) / sqr(dot(wi, wm) + dot(wo, wm) / etap);
    return m_distrib.pdf(wo, wm) * dwm_dwi * t;
}

}  // namespace ml
