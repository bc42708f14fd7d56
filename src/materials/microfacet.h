// The anisotropic Trowbridge-Reitz (GGX) microfacet distribution with visible-normal sampling
// (Heitz 2018), in the local shading frame. Conventions follow pbrt-v4 so that its scenes'
// roughness values mean the same here.
#pragma once

#include "core/math.h"

namespace ml {

// pbrt-v4's "remaproughness": a user roughness in [0, 1] becomes alpha = sqrt(roughness).
inline float roughness_to_alpha(float roughness) { return std::sqrt(std::max(0.f, roughness)); }

class TrowbridgeReitz {
public:
    TrowbridgeReitz() = default;
    TrowbridgeReitz(float alpha_x, float alpha_y)
        : m_alpha_x(std::max(alpha_x, 0.f)), m_alpha_y(std::max(alpha_y, 0.f)) {
        // A nearly smooth but not delta distribution is numerically fragile; pbrt-v4 treats
        // alpha < 1e-3 as a mirror and clamps just above it otherwise.
        if (!effectively_smooth()) {
            m_alpha_x = std::max(m_alpha_x, kMinAlpha);
            m_alpha_y = std::max(m_alpha_y, kMinAlpha);
        }
    }
    // The least roughness of a distribution that is not effectively smooth.
    static constexpr float kMinAlpha = 1e-4f;
    bool effectively_smooth() const { return std::max(m_alpha_x, m_alpha_y) < 1e-3f; }
    float alpha_x() const { return m_alpha_x; }
    float alpha_y() const { return m_alpha_y; }

    // Density of microfacet normals (projected-area normalised: integral of D cos = 1).
    float d(const Vec3& wm) const {
        float cos2 = wm.z * wm.z;
        if (!(cos2 > 1e-8f)) return 0;
        float sin2 = std::max(0.f, 1 - cos2);
        float tan2 = sin2 / cos2;
        float e = 0;
        if (sin2 > 0) {
            float cos2_phi = wm.x * wm.x / sin2, sin2_phi = wm.y * wm.y / sin2;
            e = tan2 * (cos2_phi / (m_alpha_x * m_alpha_x) + sin2_phi / (m_alpha_y * m_alpha_y));
        }
        float cos4 = cos2 * cos2;
        return 1 / (kPi * m_alpha_x * m_alpha_y * cos4 * sqr(1 + e));
    }
    // Smith's auxiliary function for the height-uncorrelated masking term.
    float lambda(const Vec3& w) const {
        float cos2 = w.z * w.z;
        float sin2 = std::max(0.f, 1 - cos2);
        if (sin2 == 0) return 0;
        if (cos2 == 0) return kInfinity;
        float tan2 = sin2 / cos2;
        float alpha2 =
            (w.x * w.x * m_alpha_x * m_alpha_x + w.y * w.y * m_alpha_y * m_alpha_y) / sin2;
        return (std::sqrt(1 + alpha2 * tan2) - 1) / 2;
    }
    float g1(const Vec3& w) const { return 1 / (1 + lambda(w)); }
    // Height-correlated masking-shadowing.
    float g(const Vec3& wo, const Vec3& wi) const { return 1 / (1 + lambda(wo) + lambda(wi)); }
    // Density of normals visible from w: G1(w) max(0, w.wm) D(wm) / |cos w|.
    float d_visible(const Vec3& w, const Vec3& wm) const {
        float c = std::abs(w.z);
        if (c == 0) return 0;
        return g1(w) / c * d(wm) * std::abs(dot(w, wm));
    }
    float pdf(const Vec3& w, const Vec3& wm) const { return d_visible(w, wm); }

    // A visible normal from w (either hemisphere), in the +z hemisphere.
    Vec3 sample_wm(Vec3 w, const Vec2& u) const {
        // Stretch the view direction to the configuration of a hemisphere of unit roughness.
        Vec3 wh = normalize(Vec3(m_alpha_x * w.x, m_alpha_y * w.y, w.z));
        if (wh.z < 0) wh = -wh;
        // Orthonormal basis around wh; the projected-area disk is sampled uniformly, its far
        // half squeezed by the visible fraction.
        Vec3 t1 = wh.z < 0.99999f ? normalize(cross(Vec3(0, 0, 1), wh)) : Vec3(1, 0, 0);
        Vec3 t2 = cross(wh, t1);
        float r = std::sqrt(u.x), phi = 2 * kPi * u.y;
        float px = r * std::cos(phi), py = r * std::sin(phi);
        float h = std::sqrt(std::max(0.f, 1 - px * px));
        py = lerp((1 + wh.z) / 2, h, py);
        float pz = safe_sqrt(1 - px * px - py * py);
        Vec3 nh = t1 * px + t2 * py + wh * pz;
        // Unstretch.
        return normalize(Vec3(m_alpha_x * nh.x, m_alpha_y * nh.y, std::max(1e-6f, nh.z)));
    }

private:
    float m_alpha_x = 0, m_alpha_y = 0;
};

}  // namespace ml
