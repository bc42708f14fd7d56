// Lambertian reflection and Lambertian transmission.
#include "materials/bxdfs.h"
#include "materials/fresnel.h"
#include "sampling/warps.h"

namespace ml {

RGB DiffuseBxdf::eval(const Vec3& wo, const Vec3& wi, TransportMode) const {
    if (!same_hemisphere(wo, wi)) return RGB();
    return m_r * kInvPi;
}

std::optional<BsdfSample> DiffuseBxdf::sample(const Vec3& wo, float, const Vec2& u,
                                              TransportMode) const {
    if (m_r.is_black()) return std::nullopt;
    Vec3 wi = sample_cosine_hemisphere(u);
    if (wo.z < 0) wi.z = -wi.z;
    BsdfSample s;
    s.f = m_r * kInvPi;
    s.wi = wi;
    s.pdf_solid_angle = pdf_cosine_hemisphere(std::abs(wi.z));
    s.flags = kBxdfDiffuseReflection;
    return s;
}

float DiffuseBxdf::pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode) const {
    if (!same_hemisphere(wo, wi) || m_r.is_black()) return 0;
    return pdf_cosine_hemisphere(std::abs(wi.z));
}

uint8_t DiffuseTransmissionBxdf::flags() const {
    uint8_t f = kBxdfNone;
    if (!m_r.is_black()) f |= kBxdfDiffuseReflection;
    if (!m_t.is_black()) f |= kBxdfDiffuseTransmission;
    return f;
}

RGB DiffuseTransmissionBxdf::eval(const Vec3& wo, const Vec3& wi, TransportMode) const {
    return (same_hemisphere(wo, wi) ? m_r : m_t) * kInvPi;
}

std::optional<BsdfSample> DiffuseTransmissionBxdf::sample(const Vec3& wo, float uc, const Vec2& u,
                                                          TransportMode) const {
    // Lobe choice by the larger channel of each, as pbrt-v4 does.
    float pr = m_r.max_component(), pt = m_t.max_component();
    if (pr + pt <= 0) return std::nullopt;
    Vec3 wi = sample_cosine_hemisphere(u);
    BsdfSample s;
    if (uc < pr / (pr + pt)) {
        if (wo.z < 0) wi.z = -wi.z;
        s.f = m_r * kInvPi;
        s.pdf_solid_angle = pdf_cosine_hemisphere(std::abs(wi.z)) * pr / (pr + pt);
        s.flags = kBxdfDiffuseReflection;
    } else {
        if (wo.z > 0) wi.z = -wi.z;
        s.f = m_t * kInvPi;
        s.pdf_solid_angle = pdf_cosine_hemisphere(std::abs(wi.z)) * pt / (pr + pt);
        s.flags = kBxdfDiffuseTransmission;
    }
    s.wi = wi;
    return s;
}

float DiffuseTransmissionBxdf::pdf_solid_angle(const Vec3& wo, const Vec3& wi,
                                               TransportMode) const {
    float pr = m_r.max_component(), pt = m_t.max_component();
    if (pr + pt <= 0) return 0;
    float lobe = same_hemisphere(wo, wi) ? pr : pt;
    return pdf_cosine_hemisphere(std::abs(wi.z)) * lobe / (pr + pt);
}

}  // namespace ml
