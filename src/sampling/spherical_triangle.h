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

// Triangle (v0, v1, v2) as seen from p, set up once for sampling and its inverse.
class SphericalTriangle {
public:
    // None when the triangle is degenerate as seen from p.
    static std::optional<SphericalTriangle> make(const Vec3& v0, const Vec3& v1, const Vec3& v2,
                                                 const Vec3& p);
    float solid_angle() const { return float(m_area); }
    // A unit direction from p through the triangle, with density 1 / solid angle. The square
    // maps so that u.y = 0 is the direction to v1 and, at u.y = 1, u.x runs from v0 (0) to v2
    // (1).
    std::optional<Vec3> sample(Vec2 u) const;
    float pdf_solid_angle() const { return m_area > 0 ? float(1 / m_area) : 0.f; }
    // The u that sample() maps direction w (through the triangle) to.
    Vec2 invert(const Vec3& w) const;

private:
    double m_a[3], m_b[3], m_c[3];            // the corners, unit vectors from p
    double m_cos_alpha = 0, m_sin_alpha = 0;  // the angle at a
    double m_area = 0;
};

// Bilinear density on [0,1]^2 through the corner weights w[0] at (0,0), w[1] at (1,0), w[2] at
// (0,1) and w[3] at (1,1) (all >= 0, not all 0); its pdf is over the square's area.
Vec2 sample_bilinear(Vec2 u, const float w[4]);
float pdf_bilinear_area(Vec2 p, const float w[4]);

}  // namespace ml
