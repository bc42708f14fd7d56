// Directions towards a triangle with uniform density over the solid angle it subtends (Arvo,
// "Stratified Sampling of Spherical Triangles", 1995), the inverse map, and a bilinear warp of
// the unit square that the caller can put in front to follow the receiver's cosine
// (pbrt-v4's Triangle::Sample does both). Sample/pdf/invert triples, as in warps.h.
#pragma once

#include <optional>

#include "core/math.h"

namespace ml {

// The solid angle of triangle (v0, v1, v2) seen from p (Van Oosterom and Strackee's formula).
float spherical_triangle_solid_angle(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Vec3& p);

// A unit direction from p towards the triangle, with density 1 / solid angle; none when the
// triangle is degenerate as seen from p. The square maps so that u.y = 0 is the direction to v1
// and, at u.y = 1, u.x runs from v0 (0) to v2 (1).
std::optional<Vec3> sample_spherical_triangle(const Vec3& v0, const Vec3& v1, const Vec3& v2,
                                              const Vec3& p, Vec2 u);
inline float pdf_spherical_triangle_solid_angle(float solid_angle) {
    return solid_angle > 0 ? 1 / solid_angle : 0.f;
}
// The u that sample_spherical_triangle maps to direction w (a direction through the triangle).
Vec2 invert_spherical_triangle(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Vec3& p,
                               const Vec3& w);

// Bilinear density on [0,1]^2 through the corner weights w[0] at (0,0), w[1] at (1,0), w[2] at
// (0,1) and w[3] at (1,1) (all >= 0, not all 0); its pdf is over the square's area.
Vec2 sample_bilinear(Vec2 u, const float w[4]);
float pdf_bilinear_area(Vec2 p, const float w[4]);

}  // namespace ml
