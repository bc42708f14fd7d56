#include "lights/light_bounds.h"

#include <algorithm>

namespace ml {
namespace {

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

}  // namespace

float LightBounds::importance(const Vec3& p, const Vec3& n) const {
    if (phi <= 0 || box.empty()) return 0;
    // The distance to the centre, but no less than the radius of the box's bounding sphere:
    // inside or near a big cluster the centre's distance means little (pbrt-v4 clamps d^2 by
    // half the diagonal's length, which mixes units; this is its square).
    Vec3 wi = p - box.center();
    float dc2 = length_squared(wi), r2 = length_squared(box.diagonal()) / 4;
    float d2 = std::max(dc2, r2);
    if (!(d2 > 0)) return 0;  // p on a point light: it cannot light p
    wi = dc2 > 0 ? wi / std::sqrt(dc2) : Vec3(0, 0, 1);

    // theta_w: from the cone's axis to p; two-sided emitters count either way.
    float cos_w = dot(w, wi);
    if (two_sided) cos_w = std::abs(cos_w);
    float sin_w = safe_sqrt(1 - sqr(cos_w));
    // theta_b: the half-angle the box's bounding sphere subtends at p (any angle when p is
    // inside it). Rounding is covered by kCosSlack below.
    float cos_b = -1, sin_b = 0;
    if (dc2 > r2) {
        float sin2_b = r2 / dc2;
        cos_b = safe_sqrt(1 - sin2_b);
        sin_b = std::sqrt(sin2_b);
    }
    // theta' = max(0, theta_w - theta_o - theta_b): the smallest angle from any emitter normal
    // to the direction towards p. Beyond theta_e nothing reaches p.
    float sin_o = safe_sqrt(1 - sqr(cos_theta_o));
    float cos_x = cos_sub_clamped(sin_w, cos_w, sin_o, cos_theta_o);
    float sin_x = sin_sub_clamped(sin_w, cos_w, sin_o, cos_theta_o);
    float cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
    if (cos_p <= cos_theta_e - kCosSlack) return 0;
    float imp = phi * std::max(cos_p, kCosSlack) / d2;
    // The receiver's cosine, at its largest over the box (either side: transmission).
    if (n.x != 0 || n.y != 0 || n.z != 0) {
        float cos_i = std::abs(dot(wi, n));
        float sin_i = safe_sqrt(1 - sqr(cos_i));
        imp *= std::max(cos_sub_clamped(sin_i, cos_i, sin_b, cos_b), kCosSlack);
    }
    // Overflow (p all but on a light) stays a finite, dominant weight.
    return std::isfinite(imp) ? imp : 1e37f;
}

LightBounds union_bounds(const LightBounds& a, const LightBounds& b) {
    if (a.phi <= 0) return b;
    if (b.phi <= 0) return a;
    DirectionCone cone =
        union_cones(DirectionCone(a.w, a.cos_theta_o), DirectionCone(b.w, b.cos_theta_o));
    LightBounds r;
    r.box = a.box;
    r.box.expand(b.box);
    r.w = cone.axis;
    r.phi = a.phi + b.phi;
    r.cos_theta_o = std::max(-1.f, cone.cos_theta);
    r.cos_theta_e = std::min(a.cos_theta_e, b.cos_theta_e);
    r.two_sided = a.two_sided || b.two_sided;
    return r;
}

}  // namespace ml
