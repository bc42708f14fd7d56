// Cones of directions: what the light tree and the Lightcuts error bounds reason with.
//
// A cone is a unit axis and the cosine of its half-angle; cos_theta = -1 is the whole sphere.
// Every helper here is conservative: a cone it builds contains the directions it is meant to
// hold even after float rounding, and an angle it reports is never larger than the true one.
// Small half-angles are poorly represented by their cosine (near 1 a float cosine has about
// 3.5e-4 rad of resolution), so cones are widened by one ulp of their cosine when built, and the
// angle of a cone is read back with a small pad (kConeAnglePad).
#pragma once

#include <cmath>

#include "core/math.h"

namespace ml {

// Covers acos's own rounding and the rounding of the unit vectors the angles come from.
constexpr float kConeAnglePad = 2e-6f;

struct DirectionCone {
    Vec3 axis{0, 0, 1};
    float cos_theta = -1;  // -1: every direction; 2: the empty cone (holds nothing)

    DirectionCone() = default;
    DirectionCone(const Vec3& a, float c) : axis(a), cos_theta(c) {}
    // The cone holding the single unit direction w.
    explicit DirectionCone(const Vec3& w) : axis(w), cos_theta(1) {}
    static DirectionCone entire_sphere() { return {Vec3(0, 0, 1), -1}; }
    static DirectionCone empty_cone() { return {Vec3(0, 0, 1), 2}; }
    bool is_empty() const { return cos_theta > 1; }
    bool is_entire_sphere() const { return cos_theta <= -1; }
};

// Angle between two unit vectors, accurate for small and large angles (unlike acos of the dot).
inline float angle_between(const Vec3& a, const Vec3& b) {
    if (dot(a, b) < 0) return kPi - 2 * safe_asin(length(a + b) / 2);
    return 2 * safe_asin(length(b - a) / 2);
}

// Half-angle of a cone, padded so that it is never below the true one; pi for the sphere.
inline float cone_angle(const DirectionCone& c) {
    if (c.is_entire_sphere()) return kPi;
    if (c.is_empty()) return 0;
    return std::min(kPi, safe_acos(c.cos_theta) + kConeAnglePad);
}

// The cosine of a half-angle, rounded one ulp wider, so a stored cone holds what it should.
inline float cone_cos_widened(float theta) {
    if (theta >= kPi) return -1;
    float c = std::cos(theta);
    return c >= 1.f ? std::nextafter(1.f, 0.f) : std::nextafter(c, -2.f);
}

// Whether unit direction w lies inside the cone (with the cone's padding).
inline bool cone_contains(const DirectionCone& c, const Vec3& w) {
    if (c.is_empty()) return false;
    if (c.is_entire_sphere()) return true;
    return angle_between(c.axis, w) <= cone_angle(c);
}

// The cone of directions from point x towards every point of box b (through the box's bounding
// sphere); the whole sphere when x is inside that sphere.
inline DirectionCone bound_subtended_directions(const Bounds3& b, const Vec3& x) {
    if (b.empty()) return DirectionCone::empty_cone();
    Vec3 c;
    float r;
    b.bounding_sphere(&c, &r);
    // The sphere's radius is rounded; grow it a little so that it holds the box's corners.
    r = r * (1 + 1e-6f) + 1e-30f;
    float d2 = distance_squared(x, c);
    if (d2 <= r * r * (1 + 1e-5f)) return DirectionCone::entire_sphere();
    float d = std::sqrt(d2);
    float theta = safe_asin(r / d) * (1 + 1e-6f) + kConeAnglePad;
    return {(c - x) / d, cone_cos_widened(theta)};
}

// The smallest cone containing both cones (pbrt-v4's DirectionCone Union, made conservative).
inline DirectionCone union_cones(const DirectionCone& a, const DirectionCone& b) {
    if (a.is_empty()) return b;
    if (b.is_empty()) return a;
    if (a.is_entire_sphere() || b.is_entire_sphere()) return DirectionCone::entire_sphere();
    float theta_a = cone_angle(a), theta_b = cone_angle(b);
    float theta_d = angle_between(a.axis, b.axis);
    // One cone inside the other.
    if (std::min(theta_d + theta_b, kPi) <= theta_a) return a;
    if (std::min(theta_d + theta_a, kPi) <= theta_b) return b;
    // Otherwise the new cone spans from a's far edge to b's far edge through both axes.
    float theta_o = (theta_a + theta_d + theta_b) / 2;
    if (theta_o >= kPi) return DirectionCone::entire_sphere();
    Vec3 w = cross(a.axis, b.axis);
    float wl = length(w);
    if (!(wl > 1e-12f)) return DirectionCone::entire_sphere();  // opposite axes
    // Rotate a's axis towards b's by theta_o - theta_a about w.
    float theta_r = theta_o - theta_a;
    Vec3 k = w / wl;
    Vec3 axis = normalize(a.axis * std::cos(theta_r) + cross(k, a.axis) * std::sin(theta_r));
    // The rotated axis is off by rounding: widen by a few ulps of angle.
    return {axis, cone_cos_widened(theta_o + 4 * kConeAnglePad)};
}

// The smallest angle between unit direction w and any direction of the cone (0 inside it).
inline float min_angle(const DirectionCone& c, const Vec3& w) {
    if (c.is_empty()) return kPi;
    if (c.is_entire_sphere()) return 0;
    return std::max(0.f, angle_between(c.axis, w) - cone_angle(c));
}

// max over w in the cone of cos(angle(w, n)), for unit n.
inline float max_cos(const DirectionCone& c, const Vec3& n) {
    if (c.is_empty()) return -1;
    return std::cos(min_angle(c, n));
}

// max over w in the cone of |cos(angle(w, n))|, for unit n.
inline float max_abs_cos(const DirectionCone& c, const Vec3& n) {
    if (c.is_empty()) return 0;
    return std::cos(std::min(min_angle(c, n), min_angle(c, -n)));
}

// The cone reflected through the origin: the directions -w for w in c.
inline DirectionCone reverse(const DirectionCone& c) { return {-c.axis, c.cos_theta}; }

}  // namespace ml
