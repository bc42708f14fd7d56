// Conductors: a mirror when smooth, else a GGX microfacet BRDF with per-channel complex Fresnel.
#include "materials/bxdfs.h"
#include "materials/fresnel.h"

namespace ml {

RGB ConductorBxdf::eval(const Vec3& wo, const Vec3& wi, TransportMode) const {
    if (!same_hemisphere(wo, wi) || m_distrib.effectively_smooth()) return RGB();
    float cos_o = std::abs(wo.z), cos_i = std::abs(wi.z);
    if (cos_i == 0 || cos_o == 0) return RGB();
    Vec3 wm = wi + wo;
    if (length_squared(wm) == 0) return RGB();
    wm = normalize(wm);
    RGB f = fr_complex(abs_dot(wo, wm), m_eta, m_k);
    return f * (m_distrib.d(wm) * m_distrib.g(wo, wi) / (4 * cos_i * cos_o));
}

std::optional<BsdfSample> ConductorBxdf::sample(const Vec3& wo, float, const Vec2& u,
                                                TransportMode) const {
    if (wo.z == 0) return std::nullopt;
    BsdfSample s;
    s.flags = flags();
    if (m_distrib.effectively_smooth()) {
        s.wi = Vec3(-wo.x, -wo.y, wo.z);
        float cos_i = std::abs(s.wi.z);
        s.f = fr_complex(cos_i, m_eta, m_k) / cos_i;
        s.pdf_solid_angle = 1;
        return s;
    }
    Vec3 wm = m_distrib.sample_wm(wo, u);
    Vec3 wi = reflect(wo, wm);
    if (!same_hemisphere(wo, wi)) return std::nullopt;
    float cos_o = std::abs(wo.z), cos_i = std::abs(wi.z);
    if (cos_i == 0) return std::nullopt;
    s.wi = wi;
    s.pdf_solid_angle = m_distrib.pdf(wo, wm) / (4 * abs_dot(wo, wm));
    RGB f = fr_complex(abs_dot(wo, wm), m_eta, m_k);
    s.f = f * (m_distrib.d(wm) * m_distrib.g(wo, wi) / (4 * cos_i * cos_o));
    if (!(s.pdf_solid_angle > 0)) return std::nullopt;  // a grazing microfacet
    return s;
}

float ConductorBxdf::pdf_solid_angle(const Vec3& wo, const Vec3& wi, TransportMode) const {
    if (!same_hemisphere(wo, wi) || m_distrib.effectively_smooth()) return 0;
    Vec3 wm = wo + wi;
    if (length_squared(wm) == 0) return 0;
    wm = face_forward(normalize(wm), Vec3(0, 0, 1));
    return m_distrib.pdf(wo, wm) / (4 * abs_dot(wo, wm));
}

}  // namespace ml
