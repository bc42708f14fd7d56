#include "transport/guided_bsdf.h"

#include <algorithm>

namespace ml {

float GuidedBsdf::mixture(float bsdf_pdf, const Vec3& wi) const {
    if (!m_guide) return bsdf_pdf;
    return m_bsdf_share * bsdf_pdf + (1 - m_bsdf_share) * m_guide->pdf_solid_angle(wi);
}

float GuidedBsdf::pdf_solid_angle(const Vec3& wo, const Vec3& wi) const {
    return mixture(m_bsdf.pdf_solid_angle(wo, wi), wi);
}

std::optional<BsdfSample> GuidedBsdf::sample(const Vec3& wo, float uc, const Vec2& u) const {
    if (!m_guide) return m_bsdf.sample(wo, uc, u);
    if (uc < m_bsdf_share) {
        auto bs = m_bsdf.sample(wo, std::min(uc / m_bsdf_share, kOneMinusEpsilon), u);
        if (bs) bs->pdf_solid_angle = mixture(bs->pdf_solid_angle, bs->wi);
        return bs;
    }
    BsdfSample g;
    g.wi = m_guide->sample(u);
    g.f = m_bsdf.eval(wo, g.wi);
    g.pdf_solid_angle = pdf_solid_angle(wo, g.wi);
    const Vec3& ng = m_bsdf.ng();
    g.flags = dot(wo, ng) * dot(g.wi, ng) < 0 ? kBxdfTransmission : kBxdfReflection;
    if (g.f.is_black() || !(g.pdf_solid_angle > 0)) return std::nullopt;
    return g;
}

}  // namespace ml
