#include "manylight/point_light.h"

namespace ml {

namespace {

// f(w, wi) |cos(n, w)| at a VPL's surface (its diffuse part only, if so kept).
RGB vpl_surface_value(const VplSurface& s, const Vec3& w) {
    RGB f = s.diffuse_only ? s.bsdf.eval_diffuse(w, s.wi, TransportMode::Radiance)
                           : s.bsdf.eval(w, s.wi, TransportMode::Radiance);
    return f * abs_dot(w, s.bsdf.frame().n);
}

}  // namespace

RGB point_light_intensity(const PointLightSet& set, const PointLight& pl, const Vec3& w) {
    switch (pl.kind) {
        case PointLightKind::Directional:
            return pl.intensity;
        case PointLightKind::Omni: {
            // VPLs on surfaces that transmit: the BSDF on both sides, as for glossy VPLs.
            if (pl.surface >= 0) {
                const VplSurface& s = set.surfaces[size_t(pl.surface)];
                return s.flux * vpl_surface_value(s, w);
            }
            if (pl.cos_end <= -1.f) return pl.intensity;
            float c = dot(pl.n, w);
            if (c <= pl.cos_end) return RGB();
            if (c >= pl.cos_start) return pl.intensity;
            float t = (c - pl.cos_end) / (pl.cos_start - pl.cos_end);
            return pl.intensity * (t * t * (3 - 2 * t));
        }
        case PointLightKind::Oriented: {
            if (pl.surface >= 0) {
                const VplSurface& s = set.surfaces[size_t(pl.surface)];
                // Light arrived from s.wi and leaves towards w: radiance transport at the VPL,
                // I(w) = flux * f(w, wi) * |cos| (a diffuse VPL: flux * albedo / pi * cos).
                return s.flux * vpl_surface_value(s, w);
            }
            float c = dot(pl.n, w);
            return c > 0 ? pl.intensity * c : RGB();
        }
    }
    return RGB();
}

}  // namespace ml
