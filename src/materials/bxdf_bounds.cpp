// Lightcuts' material bounds: for each Bxdf, an upper bound of f(wo, wi) |cos wi| over a cone of
// incident directions, in the local shading frame. The lightcuts integrator multiplies it with
// the geometric bound and a node's intensity to bound the node's error (manylight/bounds.h), so
// a bound must never be below the true maximum; how loose it is only costs refinement work.
//
// Every Bxdf here is symmetric under mirroring through the surface (z -> -z on both
// directions), so the bounds first turn wo to +z and mirror the cone with it.
#include "materials/bxdfs.h"
#include "materials/fresnel.h"

namespace ml {

RGB Bxdf::max_value_bound(const Vec3&, const DirectionCone&) const { return RGB(kInfinity); }

namespace {

// wo and the cone mirrored so that wo.z >= 0.
struct UpperSide {
    Vec3 wo;
    DirectionCone cone;
};
UpperSide to_upper_side(const Vec3& wo, const DirectionCone& cone) {
    if (wo.z >= 0) return {wo, cone};
    return {Vec3(wo.x, wo.y, -wo.z),
            {Vec3(cone.axis.x, cone.axis.y, -cone.axis.z), cone.cos_theta}};
}

// max(0, largest cos theta) over the cone's directions on the +z side, and on the -z side.
float max_cos_up(const DirectionCone& c) { return std::max(0.f, max_cos(c, Vec3(0, 0, 1))); }
float max_cos_down(const DirectionCone& c) { return std::max(0.f, max_cos(c, Vec3(0, 0, -1))); }

// What a microfacet reflection lobe's bound needs, for wo on the +z side:
// - the largest value of D(wm) G(wo, wi) / (4 cos_o) over the cone, so that
//   f cos_i = F D G / (4 cos_o) <= F_max * dg;
// - the range of cos(wo, wm) = cos(angle(wo, wi) / 2) over the cone, for the Fresnel term.
struct MicrofacetReflectionBound {
    float dg = 0;
    float cos_h_lo = 1, cos_h_hi = 1;
};

MicrofacetReflectionBound microfacet_reflection_bound(const TrowbridgeReitz& distrib,
                                                      const Vec3& wo, const DirectionCone& cone) {
    MicrofacetReflectionBound out;
    float cos_o = wo.z;
    if (!(cos_o > 0) || max_cos_up(cone) <= 0) return out;
    // D: reflecting wo about wm instead of the normal turns the mirror direction wr by at most
    // twice the angle between wm and the normal (two half-turns about axes an angle phi apart
    // compose to a rotation by 2 phi), so theta_m >= angle(wi, wr) / 2 >= min_angle(cone, wr) / 2.
    // With e >= tan^2 theta_m / alpha_max^2 in D's denominator,
    //   D <= alpha_max^4 / (pi alpha_x alpha_y (alpha_max^2 cos^2 theta_m + sin^2 theta_m)^2),
    // decreasing in theta_m when alpha_max < 1, and at most alpha_max^4 / (pi alpha_x alpha_y)
    // otherwise.
    Vec3 wr(-wo.x, -wo.y, wo.z);
    float theta_m = min_angle(cone, wr) / 2;
    float ax = distrib.alpha_x(), ay = distrib.alpha_y(), amax = std::max(ax, ay);
    float a2 = amax * amax;
    float s2 = sqr(std::sin(theta_m));
    float denom = amax >= 1 ? 1.f : a2 * (1 - s2) + s2;
    float d_max = a2 * a2 / (kPi * ax * ay * denom * denom);
    // G: the height-correlated 1 / (1 + L(wo) + L(wi)) is at most G1(wo) = 1 / (1 + L(wo)).
    out.dg = d_max * distrib.g1(wo) / (4 * cos_o);
    // Half the angle between wo and wi, over the cone.
    float a = angle_between(cone.axis, wo), t = cone_angle(cone);
    float ang_lo = std::max(0.f, a - t), ang_hi = std::min(kPi, a + t);
    out.cos_h_lo = std::cos(ang_hi / 2);
    out.cos_h_hi = std::cos(ang_lo / 2);
    return out;
}

}  // namespace

RGB DiffuseBxdf::max_value_bound(const Vec3& wo, const DirectionCone& cone) const {
    if (wo.z == 0) return RGB();
    UpperSide u = to_upper_side(wo, cone);
    return m_r * (kInvPi * max_cos_up(u.cone));
}

RGB DiffuseTransmissionBxdf::max_value_bound(const Vec3& wo, const DirectionCone& cone) const {
    if (wo.z == 0) return RGB();
    UpperSide u = to_upper_side(wo, cone);
    // Each wi lies on one side: the larger of the two lobes' bounds, per channel.
    RGB r = m_r * (kInvPi * max_cos_up(u.cone)), t = m_t * (kInvPi * max_cos_down(u.cone));
    return {std::max(r.r, t.r), std::max(r.g, t.g), std::max(r.b, t.b)};
}

RGB ConductorBxdf::max_value_bound(const Vec3& wo, const DirectionCone& cone) const {
    if (m_distrib.effectively_smooth() || wo.z == 0) return RGB();  // a mirror: a delta lobe
    UpperSide u = to_upper_side(wo, cone);
    MicrofacetReflectionBound mb = microfacet_reflection_bound(m_distrib, u.wo, u.cone);
    if (mb.dg == 0) return RGB();
    // A conductor's unpolarised reflectance falls from normal incidence to at most one minimum
    // (near the principal angle) and then rises to 1 at grazing, so over an interval of angles
    // it is largest at an end (checked over many eta, k by BoundBxdf.ConductorFresnelEnds).
    RGB f_lo = fr_complex(mb.cos_h_lo, m_eta, m_k), f_hi = fr_complex(mb.cos_h_hi, m_eta, m_k);
    RGB f(std::max(f_lo.r, f_hi.r), std::max(f_lo.g, f_hi.g), std::max(f_lo.b, f_hi.b));
    return f * mb.dg;
}

RGB DielectricBxdf::max_value_bound(const Vec3& wo, const DirectionCone& cone) const {
    if (smooth() || wo.z == 0) return RGB();  // delta lobes only
    float side = wo.z > 0 ? 1.f : -1.f;
    UpperSide u = to_upper_side(wo, cone);
    // Transmission: no sound bound of the rough BTDF over a cone is implemented (its generalised
    // half vector does not follow the mirror argument used for reflection). When any direction
    // of the cone lies across the surface, the bound is +infinity and the cut refines there.
    if (max_cos_down(u.cone) > 0) return RGB(kInfinity);
    MicrofacetReflectionBound mb = microfacet_reflection_bound(m_distrib, u.wo, u.cone);
    if (mb.dg == 0) return RGB();
    // Dielectric reflectance grows monotonically with the angle of incidence (from outside and,
    // up to total internal reflection, from inside): largest at the smallest cos(wo, wm). eval
    // takes the cosine signed by wo's side.
    return RGB(fr_dielectric(side * mb.cos_h_lo, m_eta) * mb.dg);
}

RGB CoatedDiffuseBxdf::max_value_bound(const Vec3& wo, const DirectionCone& cone) const {
    if (wo.z == 0) return RGB();
    UpperSide u = to_upper_side(wo, cone);
    float c_max = max_cos_up(u.cone);
    if (c_max <= 0) return RGB();
    // Base: eval_base(cos_o, cos_i) cos_i grows with cos_i (so do the transmittance into the
    // coat, 1 - F(cos_i), and the layer's attenuation along the refracted direction): largest at
    // the cone's highest direction.
    RGB bound = eval_base(u.wo.z, c_max) * c_max;
    // Coat: a microfacet reflection with dielectric Fresnel, as for rough glass.
    if (!m_distrib.effectively_smooth()) {
        MicrofacetReflectionBound mb = microfacet_reflection_bound(m_distrib, u.wo, u.cone);
        bound += RGB(fr_dielectric(mb.cos_h_lo, m_eta) * mb.dg);
    }
    return bound;
}

RGB CoatedConductorBxdf::max_value_bound(const Vec3& wo, const DirectionCone& cone) const {
    if (wo.z == 0 || mirror_only()) return RGB();  // a delta lobe only
    UpperSide u = to_upper_side(wo, cone);
    float c_max = max_cos_up(u.cone);
    if (c_max <= 0) return RGB();
    RGB bound;
    if (!m_base.effectively_smooth()) {
        // Refraction into a denser coat (eta >= 1) brings directions closer together: theta
        // shrinks with d theta' / d theta = cos / (eta cos') <= 1 and the azimuthal arc by
        // sin' / sin = 1 / eta. So the cone's part above the surface refracts into the cone of
        // the same angle about the refracted axis, and every refracted direction lies in the
        // escape cone, within the critical angle of the normal. A rarer coat gets no bound.
        if (m_eta < 1) return RGB(kInfinity);
        Vec3 to = coat_inside(u.wo);
        float crit_cos = safe_sqrt(1 - 1 / (m_eta * m_eta));
        DirectionCone inner(Vec3(0, 0, 1), crit_cos);
        float t = cone_angle(u.cone);
        if (u.cone.axis.z > 0 && std::cos(t) > crit_cos)
            inner = DirectionCone(coat_inside(u.cone.axis), cone_cos_widened(t));
        MicrofacetReflectionBound mb = microfacet_reflection_bound(m_base, to, inner);
        if (mb.dg > 0) {
            // f cos_i = fb series lobe cos_i (1 - F_o) (1 - F_i) tr_o tr_i / eta^2, with
            // cos_i <= cos_ti (refraction into a denser coat turns towards the normal), the
            // Fresnel transmittance 1 - F_i and tr_i largest at the cone's highest direction,
            // F_i <= 1 in the series' ratio, and the conductor's reflectance largest at an end
            // of its interval (ConductorBxdf's bound).
            float fo = fr_dielectric(u.wo.z, m_eta);
            float tr_o = m_thickness > 0 ? std::exp(-m_thickness / to.z) : 1.f;
            float ti_max = coat_inside(Vec3(safe_sqrt(1 - c_max * c_max), 0, c_max)).z;
            float tr_i = m_thickness > 0 ? std::exp(-m_thickness / ti_max) : 1.f;
            float t_i = 1 - fr_dielectric(c_max, m_eta);
            RGB f_lo = fr_complex(mb.cos_h_lo, m_base_eta, m_base_k);
            RGB f_hi = fr_complex(mb.cos_h_hi, m_base_eta, m_base_k);
            RGB fb(std::max(f_lo.r, f_hi.r), std::max(f_lo.g, f_hi.g), std::max(f_lo.b, f_hi.b));
            RGB series = coat_series(fb * (std::sqrt(fo) * tr_o));
            bound += fb * series * (mb.dg * (1 - fo) * t_i * tr_o * tr_i / (m_eta * m_eta));
        }
    }
    if (!m_trap.scale.is_black()) {
        // eval_trapped cos_i: its wo factors exactly, its wi factors each at their largest over
        // the cone (the trapped fraction at its largest node: it is interpolated linearly).
        Vec3 to = coat_inside(u.wo),
             ti_max = coat_inside(Vec3(safe_sqrt(1 - c_max * c_max), 0, c_max));
        RGB t_max;
        for (const RGB& t : m_trap.fraction)
            t_max = RGB(std::max(t_max.r, t.r), std::max(t_max.g, t.g), std::max(t_max.b, t.b));
        float fo = fr_dielectric(u.wo.z, m_eta);
        float tr = m_thickness > 0 ? std::exp(-m_thickness / to.z - m_thickness / ti_max.z) : 1.f;
        bound += trapped(to.z) * t_max * m_trap.scale *
                 ((1 - fo) * (1 - fr_dielectric(c_max, m_eta)) * tr * c_max / (m_eta * m_eta));
    }
    if (!m_coat.effectively_smooth()) {
        MicrofacetReflectionBound mb = microfacet_reflection_bound(m_coat, u.wo, u.cone);
        bound += RGB(fr_dielectric(mb.cos_h_lo, m_eta) * mb.dg);
    }
    return bound;
}

}  // namespace ml
