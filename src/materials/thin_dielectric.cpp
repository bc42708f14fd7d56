// pbrt-v4's thin dielectric: specular reflection and straight-through transmission of a sheet
// whose two interfaces reflect light back and forth.
#include "materials/bxdfs.h"
#include "materials/fresnel.h"

namespace ml {

float ThinDielectricBxdf::reflectance(float cos_o) const {
    // One interface reflects r; the light that enters bounces between the faces, leaving
    // through the front a geometric series of T^2 R^(2k+1): in total R + T^2 R / (1 - R^2).
    float r = fr_dielectric(cos_o, m_eta), t = 1 - r;
    return r < 1 ? r + t * t * r / (1 - r * r) : r;
}

std::optional<BsdfSample> ThinDielectricBxdf::sample(const Vec3& wo, float uc, const Vec2&,
                                                     TransportMode) const {
    if (wo.z == 0) return std::nullopt;
    const float r = reflectance(std::abs(wo.z)), t = 1 - r;
    BsdfSample s;
    // Reflection or transmission in proportion to its weight: each sample has weight one.
    if (uc < r) {
        s.wi = Vec3(-wo.x, -wo.y, wo.z);
        s.f = RGB(r / std::abs(wo.z));
        s.pdf_solid_angle = r;
        s.flags = kBxdfSpecularReflection;
        return s;
    }
    // Straight through: the solid angle is not compressed, so no 1 / eta^2 in either mode.
    s.wi = -wo;
    s.f = RGB(t / std::abs(wo.z));
    s.pdf_solid_angle = t;
    s.flags = kBxdfSpecularTransmission;
    return s;
}

}  // namespace ml
