// The equal-area octahedral sphere mapping (Clarberg, "Fast Equal-Area Mapping of the (Hemi)Sphere
// using SIMD", 2008).
#include "sampling/warps.h"

namespace ml {

Vec3 equal_area_square_to_sphere(Vec2 p) {
    // Steps: fold the square [-1,1]^2 into its first quadrant, measure the signed distance from
    // the diagonal |u| + |v| = 1 (inside: upper hemisphere, outside: lower), turn the distance
    // into a radius r on the octahedron and the position along the diamond edge into phi.
    float u = 2 * p.x - 1, v = 2 * p.y - 1;
    float au = std::abs(u), av = std::abs(v);
    float signed_dist = 1 - (au + av);
    float r = 1 - std::abs(signed_dist);
    float phi = (r == 0 ? 1 : (av - au) / r + 1) * (kPi / 4);
    float z = std::copysign(1 - r * r, signed_dist);
    float cos_phi = std::copysign(std::cos(phi), u);
    float sin_phi = std::copysign(std::sin(phi), v);
    float s = r * safe_sqrt(2 - r * r);
    return {cos_phi * s, sin_phi * s, z};
}

Vec2 equal_area_sphere_to_square(const Vec3& d) {
    float x = std::abs(d.x), y = std::abs(d.y), z = std::abs(d.z);
    // r from the area of the spherical cap above |z|; phi in the first quadrant in [0, 1].
    float r = safe_sqrt(1 - z);
    float a = std::max(x, y), b = std::min(x, y);
    float t = a == 0 ? 0 : b / a;
    float phi = std::atan(t) * (2 / kPi);
    if (x < y) phi = 1 - phi;
    float v = phi * r;
    float u = r - v;
    if (d.z < 0) {
        // Lower hemisphere: mirror across the diamond's edge.
        std::swap(u, v);
        u = 1 - u;
        v = 1 - v;
    }
    u = std::copysign(u, d.x);
    v = std::copysign(v, d.y);
    return {std::clamp(0.5f * (u + 1), 0.f, 1.f), std::clamp(0.5f * (v + 1), 0.f, 1.f)};
}

}  // namespace ml
