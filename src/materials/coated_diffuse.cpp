// A dielectric coat (smooth or GGX-rough) over a Lambertian base, in closed form after
// Weidlich & Wilkie 2007 and Tungsten's "roughplastic":
//
//   f(wo, wi) = f_coat(wo, wi)
//             + (1 - F(cos_i)) (1 - F(cos_o)) R / (pi eta^2 (1 - R Fdr))
//
// f_coat is the coat's specular (delta) or microfacet reflection. Light refracted into the coat
// reaches the base with transmittance 1 - F(cos_i), is reflected diffusely, and leaves with
// 1 - F(cos_o); the 1/eta^2 is the radiance compression of the cone it leaves through, and
// 1 / (1 - R Fdr) sums the geometric series of bounces between the base and the inside of the
// coat, where Fdr is the cosine-averaged internal Fresnel reflectance (total internal reflection
// included).
//
// How this differs from pbrt-v4's CoatedDiffuseMaterial, which estimates the layered BSDF
// stochastically by random walks between the two interfaces:
// - deterministic and noise-free: eval and pdf are exact functions, so MIS weights are exact;
// - the coat scatters once: light reflected between coat microfacets (multiple scattering) is
//   lost, and the diffuse transmittances use the smooth-interface Fresnel of the macro normal,
//   not the rough coat's, so rough coats are a little darker at grazing angles than pbrt's;
// - the layer is thin and clear: "thickness", "g", "maxdepth" and "nsamples" have no effect,
//   and a medium "albedo" other than zero is rejected by the material factory;
// - the internal bounces are taken as perfectly diffuse, where pbrt follows each one.
// Like pbrt-v4's, the material is two-sided: seen from -z it is mirrored through the surface.
#include "materials/bxdfs.h"
#include "materials/fresnel.h"

namespace ml {

using bxdf_detail::cosine_hemisphere_pdf;
using bxdf_detail::sample_cosine_hemisphere;

CoatedDiffuseBxdf::CoatedDiffuseBxdf(const TrowbridgeReitz& distrib, float eta,
                                     const RGB& reflectance, float fdr)
    : m_distrib(distrib), m_eta(eta) {
    RGB r = reflectance;
    RGB denom(1 - r.r * fdr, 1 - r.g * fdr, 1 - r.b * fdr);
    m_base_scale = r / denom * (kInvPi / (eta * eta));
    // Fraction of the light that enters the coat and eventually leaves it again.
    m_base_weight = (r * (1 - fdr) / denom).average();
}

uint8_t CoatedDiffuseBxdf::flags() const {
    uint8_t f = kBxdfReflection | (m_distrib.effectively_smooth() ? kBxdfSpecular : kBxdfGlossy);
    if (!m_base_scale.is_black()) f |= kBxdfDiffuse;
    return f;
}

float CoatedDiffuseBxdf::coat_probability(float cos_o) const {
    float fo = fr_dielectric(cos_o, m_eta);
    float wd = (1 - fo) * m_base_weight;
    if (fo + wd <= 0) return 0.5f;
    return fo / (fo + wd);
}

RGB CoatedDiffuseBxdf::eval_base(float cos_o, float cos_i) const {
    return m_base_scale * ((1 - fr_dielectric(cos_i, m_eta)) * (1 - fr_dielectric(cos_o, m_eta)));
}

float CoatedDiffuseBxdf::eval_coat(const Vec3& wo, const Vec3& wi) const {
    if (m_distrib.effectively_smooth()) return 0;
    Vec3 wm = wo + wi;
    if (length_squared(wm) == 0) return 0;
    wm = normalize(wm);
    float f = fr_dielectric(dot(wo, wm), m_eta);
    return m_distrib.d(wm) * m_distrib.g(wo, wi) * f / (4 * wi.z * wo.z);
}

float CoatedDiffuseBxdf::pdf_coat(const Vec3& wo, const Vec3& wi) const {
    if (m_distrib.effectively_smooth()) return 0;
    Vec3 wm = wo + wi;
    if (length_squared(wm) == 0) return 0;
    wm = normalize(wm);
    return m_distrib.pdf(wo, wm) / (4 * abs_dot(wo, wm));
}

RGB CoatedDiffuseBxdf::eval(const Vec3& wo_in, const Vec3& wi_in, TransportMode) const {
    if (!same_hemisphere(wo_in, wi_in)) return RGB();
    // Two-sided: work on the +z side.
    float sign = wo_in.z < 0 ? -1.f : 1.f;
    Vec3 wo(wo_in.x, wo_in.y, wo_in.z * sign), wi(wi_in.x, wi_in.y, wi_in.z * sign);
    return eval_base(wo.z, wi.z) + RGB(eval_coat(wo, wi));
}

std::optional<BsdfSample> CoatedDiffuseBxdf::sample(const Vec3& wo_in, float uc, const Vec2& u,
                                                    TransportMode mode) const {
    if (wo_in.z == 0) return std::nullopt;
    float sign = wo_in.z < 0 ? -1.f : 1.f;
    Vec3 wo(wo_in.x, wo_in.y, wo_in.z * sign);
    float p_coat = coat_probability(wo.z);
    bool smooth = m_distrib.effectively_smooth();
    BsdfSample s;
    Vec3 wi;
    if (uc < p_coat) {
        if (smooth) {
            wi = Vec3(-wo.x, -wo.y, wo.z);
            s.f = RGB(fr_dielectric(wo.z, m_eta) / wi.z);
            s.pdf_solid_angle = p_coat;
            s.flags = kBxdfSpecularReflection;
            s.wi = Vec3(wi.x, wi.y, wi.z * sign);
            return s;
        }
        wi = reflect(wo, m_distrib.sample_wm(wo, u));
        if (wi.z <= 0) return std::nullopt;
        s.flags = kBxdfGlossyReflection;
    } else {
        wi = sample_cosine_hemisphere(u);
        if (wi.z <= 0) return std::nullopt;
        s.flags = kBxdfDiffuseReflection;
    }
    // Both lobes of the mixture can produce any non-delta direction: value and density are the
    // whole BSDF's.
    s.f = eval_base(wo.z, wi.z) + RGB(eval_coat(wo, wi));
    s.pdf_solid_angle = (1 - p_coat) * cosine_hemisphere_pdf(wi.z) + p_coat * pdf_coat(wo, wi);
    s.wi = Vec3(wi.x, wi.y, wi.z * sign);
    if (!(s.pdf_solid_angle > 0)) return std::nullopt;
    return s;
}

float CoatedDiffuseBxdf::pdf_solid_angle(const Vec3& wo_in, const Vec3& wi_in,
                                         TransportMode) const {
    if (!same_hemisphere(wo_in, wi_in)) return 0;
    float sign = wo_in.z < 0 ? -1.f : 1.f;
    Vec3 wo(wo_in.x, wo_in.y, wo_in.z * sign), wi(wi_in.x, wi_in.y, wi_in.z * sign);
    float p_coat = coat_probability(wo.z);
    return (1 - p_coat) * cosine_hemisphere_pdf(wi.z) + p_coat * pdf_coat(wo, wi);
}

}  // namespace ml
