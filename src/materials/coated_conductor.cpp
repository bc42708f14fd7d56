// A dielectric coat over a conductor (pbrt-v4's "coatedconductor"), in closed form. pbrt-v4
// evaluates it with its stochastic LayeredBxDF random walk; this is the walk's expected value
// for a smooth coat, term by term:
//
//   f(wo, wi) = f_coat(wo, wi)
//             + T(cos_o) T(cos_i) tr(wo') tr(wi') / eta^2 * f_base(wo', wi') * sum_{k<n} q^k
//
// - f_coat: the coat's own reflection, a delta lobe when smooth, else GGX with dielectric
//   Fresnel (as a rough coateddiffuse's).
// - wo', wi': wo and wi refracted into the coat through its macro surface; T = 1 - F is the
//   transmittance in and out, 1 / eta^2 the radiance compression of the refracted cone, and
//   tr = exp(-thickness / cos') the layer's absorption along each pass (pbrt-v4 attenuates even
//   a clear coat so).
// - f_base: the conductor's GGX BRDF, its complex IOR relative to the coat's.
// - the series: light reflected by the conductor back into the coat's escape cone is mostly
//   transmitted, but a fraction F is reflected back down (internal reflection at the same angle
//   as outside) and the conductor returns it near the same lobe: one round trip keeps
//   q = F_base sqrt(F(cos_o) F(cos_i)) tr(wo') tr(wi'), and pbrt-v4's walk ("maxdepth" 10)
//   reaches the base at most n = 5 times. For a smooth coat over a mirror this is exact (all of
//   it is one delta lobe).
//
// What it leaves out, measured against pbrt-v4 in tests/scenes/mat_coatedconductor*.pbrt:
// - light the conductor scatters outside the coat's escape cone is totally internally
//   reflected and comes back out after more bounces, more diffusely; here it is lost;
// - a rough coat transmits through tilted microfacets: here through the macro surface, with the
//   conductor's roughness widened to stand for the spread (alpha^2 + ((eta - 1) alpha_c)^2 / (2
//   eta^2): the deviation of a ray refracted by a facet tilted by theta is about
//   (1 - 1 / eta) theta, twice, seen from inside);
// - a scattering coat ("albedo" > 0) is refused by the material factory; "g" has no effect.
// Deterministic: eval and pdf are exact functions, so MIS weights are exact. Two-sided like
// pbrt-v4's: seen from -z it is mirrored through the surface.
#include "materials/bxdfs.h"
#include "materials/fresnel.h"
#include "sampling/warps.h"

namespace ml {

namespace {

// w (+z side) refracted into a coat of IOR eta, pointing away from the base; z = 0 when it
// cannot enter (eta < 1 beyond the critical angle).
Vec3 into_coat(const Vec3& w, float eta) {
    float sin2 = (1 - w.z * w.z) / (eta * eta);
    if (sin2 >= 1) return Vec3(0, 0, 0);
    return Vec3(w.x / eta, w.y / eta, std::sqrt(1 - sin2));
}

// The inverse: a direction inside the coat, refracted out; z = 0 when it is totally internally
// reflected.
Vec3 out_of_coat(const Vec3& w, float eta) {
    float sin2 = (1 - w.z * w.z) * eta * eta;
    if (sin2 >= 1) return Vec3(0, 0, 0);
    return Vec3(w.x * eta, w.y * eta, std::sqrt(1 - sin2));
}

TrowbridgeReitz widened_base(const CoatedConductorLayers& l) {
    if (l.coat.effectively_smooth()) return l.base;
    float s = (l.eta - 1) * (l.eta - 1) / (2 * l.eta * l.eta);
    return TrowbridgeReitz(std::sqrt(sqr(l.base.alpha_x()) + s * sqr(l.coat.alpha_x())),
                           std::sqrt(sqr(l.base.alpha_y()) + s * sqr(l.coat.alpha_y())));
}

// sum_{k<n} q^k, per channel.
RGB truncated_series(const RGB& q, int n) {
    RGB out;
    for (int c = 0; c < 3; ++c) {
        float x = q[c];
        if (n <= 0) {
            out[c] = 0;
        } else if (std::abs(1 - x) < 1e-6f) {
            out[c] = float(n);
        } else {
            out[c] = (1 - std::pow(x, float(n))) / (1 - x);
        }
    }
    return out;
}

Vec3 upper(const Vec3& w, float sign) { return Vec3(w.x, w.y, w.z * sign); }

}  // namespace

CoatedConductorBxdf::CoatedConductorBxdf(const CoatedConductorLayers& l)
    : m_coat(l.coat),
      m_base(widened_base(l)),
      m_eta(l.eta),
      m_thickness(std::max(0.f, l.thickness)),
      m_base_eta(l.base_eta),
      m_base_k(l.base_k),
      m_base_visits(l.base_visits) {
    m_base_weight = fr_complex(1.f, m_base_eta, m_base_k).average();
    m_trap = l.trap ? *l.trap : compute_trap(l);
}

// The conductor's single-scattering lobe lit from inside direction (sin, 0, cos), integrated
// by its visible normals over a fixed 4x4 stratification (deterministic): the fraction sent
// beyond the critical angle, the fraction escaping the coat (times 1 - F), and the fraction
// Fresnel-reflected back from within the escape cone.
struct LobeSplit {
    RGB trapped, escaping, returned;
};
static LobeSplit split_lobe(const TrowbridgeReitz& d, const RGB& eta, const RGB& k, float coat_eta,
                            float crit_cos, float cos_t) {
    LobeSplit out;
    Vec3 wi(safe_sqrt(1 - cos_t * cos_t), 0, cos_t);
    constexpr int kR = 16, kPhi = 6;
    for (int a = 0; a < kR; ++a)
        for (int b = 0; b < kPhi; ++b) {
            Vec3 wm = d.sample_wm(wi, Vec2((a + 0.5f) / kR, (b + 0.5f) / kPhi));
            Vec3 w = reflect(wi, wm);
            if (w.z <= 0) continue;
            RGB v = fr_complex(abs_dot(wi, wm), eta, k) * (d.g(wi, w) / d.g1(wi));
            if (w.z < crit_cos) {
                out.trapped += v;
            } else {
                float f = fr_dielectric(-w.z, coat_eta);
                out.escaping += v * (1 - f);
                out.returned += v * f;
            }
        }
    float n = 1.f / (kR * kPhi);
    out.trapped = out.trapped * n;
    out.escaping = out.escaping * n;
    out.returned = out.returned * n;
    return out;
}

CoatedConductorTrap CoatedConductorBxdf::compute_trap(const CoatedConductorLayers& l) {
    CoatedConductorTrap out;
    TrowbridgeReitz base = widened_base(l);
    if (base.effectively_smooth() || l.eta <= 1) return out;
    constexpr int kNodes = CoatedConductorTrap::kNodes;
    const float eta = l.eta, crit = safe_sqrt(1 - 1 / (eta * eta));
    out.crit_cos = crit;
    auto tr = [&](float cos) { return l.thickness > 0 ? std::exp(-l.thickness / cos) : 1.f; };
    // The trapped fraction where light enters (inside the escape cone), and the integral of the
    // way out, X = 2 integral over the cone of (1 - F) tr trapped cos dcos.
    RGB x;
    for (int i = 0; i < kNodes; ++i) {
        float c = crit + (1 - crit) * i / (kNodes - 1);
        out.fraction[i] = split_lobe(base, l.base_eta, l.base_k, eta, crit, c).trapped;
        float w = (i == 0 || i == kNodes - 1 ? 0.5f : 1.f) * (1 - crit) / (kNodes - 1);
        x += out.fraction[i] * (2 * w * c * (1 - fr_dielectric(-c, eta)) * tr(c));
    }
    // Trapped light goes up, is totally reflected, and meets the conductor again at a grazing
    // angle (averaged over three, uniform in cos^2 below the critical angle): from there a
    // fraction escapes, and a fraction is trapped again, for the walk's remaining visits.
    LobeSplit g;
    float tg = 0;
    constexpr int kG = 3;
    for (int j = 0; j < kG; ++j) {
        float cg = crit * std::sqrt((j + 0.5f) / kG);
        LobeSplit gj = split_lobe(base, l.base_eta, l.base_k, eta, crit, cg);
        g.trapped += gj.trapped / kG;
        g.escaping += gj.escaping / kG;
        g.returned += gj.returned / kG;
        tg += tr(cg) * tr(cg) / kG;
    }
    RGB series = truncated_series((g.trapped + g.returned) * tg, l.base_visits - 1);
    for (int c = 0; c < 3; ++c)
        out.scale[c] = x[c] > 0 ? tg * g.escaping[c] * series[c] / (kPi * x[c]) : 0.f;
    out.weight = (out.fraction[kNodes - 1] * g.escaping * series * tg).average();
    return out;
}

RGB CoatedConductorBxdf::trapped(float cos_t) const {
    constexpr int kNodes = CoatedConductorTrap::kNodes;
    float c0 = m_trap.crit_cos;
    float x = std::clamp((cos_t - c0) / (1 - c0), 0.f, 1.f) * (kNodes - 1);
    int i = std::min(int(x), kNodes - 2);
    float t = x - i;
    return m_trap.fraction[i] * (1 - t) + m_trap.fraction[i + 1] * t;
}

// Reciprocal by construction: light entering along wi is trapped in proportion to
// trapped(cos_ti), and leaves, after its further bounces, spread like the reverse.
RGB CoatedConductorBxdf::eval_trapped(const Vec3& wo, const Vec3& wi) const {
    if (m_trap.scale.is_black()) return RGB();
    Vec3 to = into_coat(wo, m_eta), ti = into_coat(wi, m_eta);
    if (to.z <= 0 || ti.z <= 0) return RGB();
    float fo = fr_dielectric(wo.z, m_eta), fi = fr_dielectric(wi.z, m_eta);
    float tr = m_thickness > 0 ? std::exp(-m_thickness / to.z - m_thickness / ti.z) : 1.f;
    return trapped(to.z) * trapped(ti.z) * m_trap.scale *
           ((1 - fo) * (1 - fi) * tr / (m_eta * m_eta));
}

Vec3 CoatedConductorBxdf::coat_inside(const Vec3& w) const { return into_coat(w, m_eta); }

RGB CoatedConductorBxdf::coat_series(const RGB& q) const {
    return truncated_series(q, m_base_visits);
}

uint8_t CoatedConductorBxdf::flags() const {
    if (mirror_only()) return kBxdfSpecularReflection;
    uint8_t f = kBxdfGlossyReflection;
    if (m_coat.effectively_smooth()) f |= kBxdfSpecular;
    return f;
}

RGB CoatedConductorBxdf::mirror_weight(float cos_o) const {
    float f = fr_dielectric(cos_o, m_eta);
    Vec3 w = into_coat(Vec3(safe_sqrt(1 - cos_o * cos_o), 0, cos_o), m_eta);
    if (w.z <= 0) return RGB(f);
    float tr2 = m_thickness > 0 ? std::exp(-2 * m_thickness / w.z) : 1.f;
    RGB fb = fr_complex(w.z, m_base_eta, m_base_k);
    RGB series = truncated_series(fb * (f * tr2), m_base_visits);
    return RGB(f) + fb * series * ((1 - f) * (1 - f) * tr2);
}

void CoatedConductorBxdf::lobe_probabilities(float cos_o, float* p_coat, float* p_base,
                                             float* p_trap) const {
    float f = fr_dielectric(cos_o, m_eta);
    float wc = f, wb = (1 - f) * m_base_weight, wt = (1 - f) * m_trap.weight;
    if (m_base.effectively_smooth()) wb = 0;
    float sum = wc + wb + wt;
    if (!(sum > 0)) {
        wc = 1, wb = wt = 0, sum = 1;
    }
    *p_coat = wc / sum;
    *p_base = wb / sum;
    *p_trap = wt / sum;
}

float CoatedConductorBxdf::eval_coat(const Vec3& wo, const Vec3& wi) const {
    if (m_coat.effectively_smooth()) return 0;
    Vec3 wm = wo + wi;
    if (length_squared(wm) == 0) return 0;
    wm = normalize(wm);
    float f = fr_dielectric(dot(wo, wm), m_eta);
    return m_coat.d(wm) * m_coat.g(wo, wi) * f / (4 * wi.z * wo.z);
}

float CoatedConductorBxdf::pdf_coat(const Vec3& wo, const Vec3& wi) const {
    if (m_coat.effectively_smooth()) return 0;
    Vec3 wm = wo + wi;
    if (length_squared(wm) == 0) return 0;
    wm = normalize(wm);
    return m_coat.pdf(wo, wm) / (4 * abs_dot(wo, wm));
}

RGB CoatedConductorBxdf::eval_base(const Vec3& wo, const Vec3& wi) const {
    if (m_base.effectively_smooth()) return RGB();
    Vec3 to = into_coat(wo, m_eta), ti = into_coat(wi, m_eta);
    if (to.z <= 0 || ti.z <= 0) return RGB();
    Vec3 wm = to + ti;
    if (length_squared(wm) == 0) return RGB();
    wm = normalize(wm);
    float fo = fr_dielectric(wo.z, m_eta), fi = fr_dielectric(wi.z, m_eta);
    float tr = m_thickness > 0 ? std::exp(-m_thickness / to.z - m_thickness / ti.z) : 1.f;
    RGB fb = fr_complex(dot(to, wm), m_base_eta, m_base_k);
    float lobe = m_base.d(wm) * m_base.g(to, ti) / (4 * to.z * ti.z);
    RGB series = truncated_series(fb * (std::sqrt(fo * fi) * tr), m_base_visits);
    return fb * series * (lobe * (1 - fo) * (1 - fi) * tr / (m_eta * m_eta));
}

float CoatedConductorBxdf::pdf_base(const Vec3& wo, const Vec3& wi) const {
    if (m_base.effectively_smooth()) return 0;
    Vec3 to = into_coat(wo, m_eta), ti = into_coat(wi, m_eta);
    if (to.z <= 0 || ti.z <= 0) return 0;
    Vec3 wm = to + ti;
    if (length_squared(wm) == 0) return 0;
    wm = normalize(wm);
    // The density of ti, times the solid angle ratio of refraction, d(ti) / d(wi) =
    // cos_i / (eta^2 cos_ti).
    float p = m_base.pdf(to, wm) / (4 * abs_dot(to, wm));
    return p * wi.z / (m_eta * m_eta * ti.z);
}

RGB CoatedConductorBxdf::eval(const Vec3& wo_in, const Vec3& wi_in, TransportMode) const {
    if (!same_hemisphere(wo_in, wi_in) || mirror_only()) return RGB();
    float sign = wo_in.z < 0 ? -1.f : 1.f;
    Vec3 wo = upper(wo_in, sign), wi = upper(wi_in, sign);
    return eval_base(wo, wi) + eval_trapped(wo, wi) + RGB(eval_coat(wo, wi));
}

float CoatedConductorBxdf::pdf_solid_angle(const Vec3& wo_in, const Vec3& wi_in,
                                           TransportMode) const {
    if (!same_hemisphere(wo_in, wi_in) || mirror_only()) return 0;
    float sign = wo_in.z < 0 ? -1.f : 1.f;
    Vec3 wo = upper(wo_in, sign), wi = upper(wi_in, sign);
    float p_coat, p_base, p_trap;
    lobe_probabilities(wo.z, &p_coat, &p_base, &p_trap);
    return p_coat * pdf_coat(wo, wi) + p_base * pdf_base(wo, wi) + p_trap * wi.z * kInvPi;
}

std::optional<BsdfSample> CoatedConductorBxdf::sample(const Vec3& wo_in, float uc, const Vec2& u,
                                                      TransportMode mode) const {
    if (wo_in.z == 0) return std::nullopt;
    float sign = wo_in.z < 0 ? -1.f : 1.f;
    Vec3 wo = upper(wo_in, sign);
    BsdfSample s;
    if (mirror_only()) {
        s.wi = Vec3(-wo_in.x, -wo_in.y, wo_in.z);
        s.f = mirror_weight(wo.z) / wo.z;
        s.pdf_solid_angle = 1;
        s.flags = kBxdfSpecularReflection;
        return s;
    }
    float p_coat, p_base, p_trap;
    lobe_probabilities(wo.z, &p_coat, &p_base, &p_trap);
    Vec3 wi;
    if (uc < p_coat) {
        if (m_coat.effectively_smooth()) {
            s.wi = Vec3(-wo_in.x, -wo_in.y, wo_in.z);
            s.f = RGB(fr_dielectric(wo.z, m_eta) / wo.z);
            s.pdf_solid_angle = p_coat;
            s.flags = kBxdfSpecularReflection;
            return s;
        }
        wi = reflect(wo, m_coat.sample_wm(wo, u));
    } else if (uc < p_coat + p_base) {
        // The conductor's visible normals, seen from inside the coat, and out again.
        Vec3 to = into_coat(wo, m_eta);
        if (to.z <= 0) return std::nullopt;
        Vec3 ti = reflect(to, m_base.sample_wm(to, u));
        if (ti.z <= 0) return std::nullopt;
        wi = out_of_coat(ti, m_eta);
    } else {
        wi = sample_cosine_hemisphere(u);
    }
    if (wi.z <= 0) return std::nullopt;
    s.flags = kBxdfGlossyReflection;
    s.f = eval(wo, wi, mode);
    s.pdf_solid_angle = pdf_solid_angle(wo, wi, mode);
    s.wi = upper(wi, sign);
    if (!(s.pdf_solid_angle > 0)) return std::nullopt;
    return s;
}

}  // namespace ml
