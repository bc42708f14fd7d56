// What a light-tree node knows of the lights below it (Conty Estevez & Kulla 2018; pbrt-v4's
// LightBounds): where they are (a box), which way they emit (a cone of normals of half-angle
// theta_o, each normal emitting up to theta_e away from it), and how strongly (phi). importance()
// turns that into an estimate of the irradiance the lights could deliver to a shading point, which
// the tree light sampler (light_sampler.h) chooses children by.
//
// phi is in units that make importance() an irradiance: a point or spot light's luminous
// intensity I (irradiance I cos / d^2), an area light's radiance times its area, L A (irradiance
// about L A cos cos / d^2). pbrt-v4 uses 4 pi I for points and L A for areas, which favours point
// lights 4 pi times over area lights of equal effect; and it cannot compare the tree with
// infinite lights, which it samples with a fixed probability. Ours can (light_sampler.cpp).
#pragma once

#include <algorithm>
#include <cmath>

#include "core/cone.h"
#include "core/math.h"

namespace ml {

struct LightBounds {
    Bounds3 box;
    Vec3 w{0, 0, 1};         // axis of the cone of emitter normals
    float phi = 0;           // see above; 0: emits nothing
    float cos_theta_o = 1;   // half-angle of the cone of normals
    float cos_theta_e = 0;   // how far from its normal a point emits (pi / 2: a diffuse face)
    bool two_sided = false;  // emits on both sides of each normal

    // Estimated irradiance at p (surface normal n; zero: none, as in a medium). Zero only where
    // no light of the bounds can reach p: every cone test is conservative.
    float importance(const Vec3& p, const Vec3& n) const;
};

// The bounds of both (phi adds up); an operand with phi = 0 leaves the other unchanged.
LightBounds union_bounds(const LightBounds& a, const LightBounds& b);

// What importance() reads of LightBounds, precomputed (centre, squared radius of the bounding
// sphere, sine of theta_o): the light BVH's nodes hold these, and a descent evaluates two per
// level.
struct ImportanceBounds {
    Vec3 center;
    float r2 = 0;  // squared radius of the box's bounding sphere
    Vec3 w{0, 0, 1};
    float phi = 0;
    float cos_theta_o = 1, sin_theta_o = 0, cos_theta_e = 0;
    bool two_sided = false;

    ImportanceBounds() = default;
    explicit ImportanceBounds(const LightBounds& b)
        : center(b.box.center()),
          r2(length_squared(b.box.diagonal()) / 4),
          w(b.w),
          phi(b.box.empty() ? 0.f : b.phi),
          cos_theta_o(b.cos_theta_o),
          sin_theta_o(safe_sqrt(1 - sqr(b.cos_theta_o))),
          cos_theta_e(b.cos_theta_e),
          two_sided(b.two_sided) {}

    inline float importance(const Vec3& p, const Vec3& n) const;
};

namespace detail {
// cos(max(0, a - b)) and sin(max(0, a - b)) for angles a, b in [0, pi] given by their cosines
// and sines.
inline float cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    return cos_a > cos_b ? 1.f : cos_a * cos_b + sin_a * sin_b;
}
inline float sin_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    return cos_a > cos_b ? 0.f : sin_a * cos_b - cos_a * sin_b;
}
// Rounding in the cone arithmetic must not turn a light that reaches p into one that cannot:
// cosines within this of a limit count as inside it.
constexpr float kCosSlack = 1e-4f;
}  // namespace detail

inline float ImportanceBounds::importance(const Vec3& p, const Vec3& n) const {
    using namespace detail;
    if (phi <= 0) return 0;
    // The distance to the centre, but no less than the radius of the box's bounding sphere:
    // inside or near a big cluster the centre's distance means little (pbrt-v4 clamps d^2 by
    // half the diagonal's length, which mixes units; this is its square).
    Vec3 wi = p - center;
    float dc2 = length_squared(wi);
    float d2 = std::max(dc2, r2);
    if (!(d2 > 0)) return 0;  // p on a point light: it cannot light p
    wi = dc2 > 0 ? wi / std::sqrt(dc2) : Vec3(0, 0, 1);

    // theta_w: from the cone's axis to p; two-sided emitters count either way.
    float cos_w = dot(w, wi);
    if (two_sided) cos_w = std::abs(cos_w);
    float sin_w = safe_sqrt(1 - sqr(cos_w));
    // theta_b: the half-angle the bounding sphere subtends at p (any angle when p is inside
    // it). Rounding is covered by kCosSlack below.
    float cos_b = -1, sin_b = 0;
    if (dc2 > r2) {
        float sin2_b = r2 / dc2;
        cos_b = safe_sqrt(1 - sin2_b);
        sin_b = std::sqrt(sin2_b);
    }
    // theta' = max(0, theta_w - theta_o - theta_b): the smallest angle from any emitter normal
    // to the direction towards p. Beyond theta_e nothing reaches p.
    float cos_x = cos_sub_clamped(sin_w, cos_w, sin_theta_o, cos_theta_o);
    float sin_x = sin_sub_clamped(sin_w, cos_w, sin_theta_o, cos_theta_o);
    float cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
    if (cos_p <= cos_theta_e - kCosSlack) return 0;
    float imp = phi * std::max(cos_p, kCosSlack) / d2;
    // The receiver's cosine, at its largest over the sphere (either side: transmission).
    if (n.x != 0 || n.y != 0 || n.z != 0) {
        float cos_i = std::abs(dot(wi, n));
        float sin_i = safe_sqrt(1 - sqr(cos_i));
        imp *= std::max(cos_sub_clamped(sin_i, cos_i, sin_b, cos_b), kCosSlack);
    }
    // Overflow (p all but on a light) stays a finite, dominant weight.
    return std::isfinite(imp) ? imp : 1e37f;
}

}  // namespace ml
