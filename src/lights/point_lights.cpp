#include "lights/point_lights.h"

#include "lights/light.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ml {

const float kFalloffCos[kFalloffBins] = {
    1.f,
    0.99862953f,  // 3 degrees
    0.99452190f,  // 6
    0.97814760f,  // 12
    0.93969262f,  // 20
    0.81915204f,  // 35
    0.57357644f,  // 55
    0.17364818f,  // 80
};

float falloff_value(uint8_t q) {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t;
        for (int i = 0; i < 256; ++i) t[size_t(i)] = std::exp2(-float(i) / 16);
        return t;
    }();
    return table[q];
}

uint8_t quantize_falloff(float t) {
    if (!(t < 1)) return 0;  // also NaN: no falloff
    if (t <= falloff_value(255)) return 255;
    int q = std::clamp(int(std::floor(-16 * std::log2(t))), 0, 255);
    while (q > 0 && falloff_value(uint8_t(q)) < t) --q;  // never below t
    return uint8_t(q);
}

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
            if (pl.emitter) return pl.emitter->emitted_intensity(w);
            if (pl.cos_end <= -1.f) return pl.intensity;
            float c = dot(pl.n, w);
            if (c <= pl.cos_end) return RGB();
            if (c >= pl.cos_start) return pl.intensity;
            float t = (c - pl.cos_end) / (pl.cos_start - pl.cos_end);
            return pl.intensity * (t * t * (3 - 2 * t));
        }
        case PointLightKind::Glossy:
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
