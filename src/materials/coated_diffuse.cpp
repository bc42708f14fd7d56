// A dielectric coat (smooth or GGX-rough) over a Lambertian base, in closed form. The diffuse
// part is the expected value of pbrt-v4's LayeredBxDF random walk (CoatedDiffuseBxDF, clear
// medium: albedo 0) for a smooth coat:
//
//   f(wo, wi) = f_coat(wo, wi)
//             + T(cos_o) T(cos_i) tr(wo) tr(wi) R / (pi eta^2) sum_{k<n} (R A)^k
//
// f_coat is the coat's specular (delta) or microfacet reflection. Light refracted into the coat
// reaches the base with transmittance T = 1 - F(cos_i), is reflected diffusely, and leaves with
// 1 - F(cos_o); the 1/eta^2 is the radiance compression of the cone it leaves through. pbrt-v4
// attenuates every pass through the layer by tr = exp(-thickness / |cos|) of the refracted
// direction, even with a clear medium (LayeredBxDF::Tr, thickness 0.01 by default), so a round
// trip base -> top -> base keeps A = integral 2 mu F_int(mu) exp(-2 thickness / mu) dmu of the
// light (F_int: internal Fresnel reflectance, total internal reflection included), and its walk
// stops after "maxdepth" (10) interface events: the base is reached at most n = 5 times, so the
// geometric series of internal bounces is cut after n terms. For a white base under a smooth
// coat that is 14% below the energy-conserving 1 / (1 - A) (Weidlich & Wilkie 2007, Tungsten's
// "roughplastic"), and about 2% darker for a black one.
//
// How this still differs from pbrt-v4's CoatedDiffuseMaterial:
// - deterministic and noise-free: eval and pdf are exact functions, so MIS weights are exact;
// - for a rough coat the transmittances and tr use the macro normal's smooth Fresnel and
//   refraction, where pbrt transmits through the rough interface (and its coat scatters once:
//   light reflected between coat microfacets is lost in both);
// - "g" has no effect and a medium "albedo" other than zero is rejected by the material factory;
// - the internal bounces are taken as perfectly diffuse, where pbrt follows each one.
// Like pbrt-v4's, the material is two-sided: seen from -z it is mirrored through the surface.
#include "materials/bxdfs.h"
#include "materials/fresnel.h"
#include "sampling/warps.h"

namespace ml {

CoatedDiffuseBxdf::CoatedDiffuseBxdf(const TrowbridgeReitz& distrib, float eta,
                                     const RGB& reflectance, const CoatLayer& layer)
    : m_distrib(distrib), m_eta(eta), m_thickness(layer.thickness) {
    RGB r = reflectance;
    // sum_{k<n} (r A)^k per channel, in closed form.
    auto series = [&](float ra) {
        int n = layer.base_visits;
        if (n <= 0) return 0.f;
        if (std::abs(1 - ra) < 1e-6f) return float(n);
        return (1 - std::pow(ra, float(n))) / (1 - ra);
    };
    float a = layer.round_trip;
    RGB sum(series(r.r * a), series(r.g * a), series(r.b * a));
    m_base_scale = r * sum * (kInvPi / (eta * eta));
    // Fraction of the light that enters the coat and eventually leaves it again (roughly: the
    // walk's own absorption on the way in and out is left out), for lobe selection only.
    m_base_weight = (r * sum * (1 - a)).average();
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
    // Transmittance into (or out of) the coat along cos, times the layer's attenuation along the
    // refracted direction.
    auto through = [&](float cos) {
        float t = 1 - fr_dielectric(cos, m_eta);
        if (t <= 0 || m_thickness <= 0) return t;
        float cos_t = safe_sqrt(1 - (1 - cos * cos) / (m_eta * m_eta));
        return cos_t > 0 ? t * std::exp(-m_thickness / cos_t) : 0.f;
    };
    return m_base_scale * (through(cos_i) * through(cos_o));
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

RGB CoatedDiffuseBxdf::eval_diffuse(const Vec3& wo, const Vec3& wi, TransportMode) const {
    if (!same_hemisphere(wo, wi)) return RGB();
    return eval_base(std::abs(wo.z), std::abs(wi.z));
}

std::optional<RGB> CoatedDiffuseBxdf::max_diffuse_value(const Vec3& wi) const {
    // The way out, 1 - F(cos) times exp(-thickness / cos_t), grows with cos: largest along the
    // normal.
    return eval_base(1.f, std::abs(wi.z));
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
    s.pdf_solid_angle = (1 - p_coat) * pdf_cosine_hemisphere(wi.z) + p_coat * pdf_coat(wo, wi);
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
    return (1 - p_coat) * pdf_cosine_hemisphere(wi.z) + p_coat * pdf_coat(wo, wi);
}

}  // namespace ml
