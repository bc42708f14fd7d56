// Arvo's spherical triangle sampling. The triangle's corners, seen from p, are the unit vectors
// a, b, c; alpha, beta, gamma are its angles (between the great circles through its edges), and
// its area on the unit sphere is alpha + beta + gamma - pi. u.x picks the sub-triangle (a, b,
// c') whose area is the fraction u.x of the whole, with c' on the arc from a to c; u.y then
// picks a point on the arc from b to c' so that the density over the sphere is uniform.
// The formula for c' divides by sin(alpha), which is small when p is close to a large triangle,
// so the computation runs in double (float lost 7% of u.x there).
#include "sampling/spherical_triangle.h"

#include <algorithm>
#include <cmath>

namespace ml {
namespace {

struct D3 {
    double x = 0, y = 0, z = 0;
};
D3 operator+(const D3& a, const D3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator-(const D3& a) { return {-a.x, -a.y, -a.z}; }
D3 operator*(const D3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(const D3& a, const D3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double length(const D3& a) { return std::sqrt(dot(a, a)); }
D3 to_d3(const Vec3& v) { return {v.x, v.y, v.z}; }
// a / |a|, or zero for the zero vector.
D3 normalized(const D3& a) {
    double l = length(a);
    return l > 0 ? a * (1 / l) : D3{};
}

// Angle between unit vectors, accurate near 0 and pi.
double angle_between(const D3& v1, const D3& v2) {
    if (dot(v1, v2) < 0) return M_PI - 2 * std::asin(std::min(1.0, length(v1 + v2) / 2));
    return 2 * std::asin(std::min(1.0, length(v2 - v1) / 2));
}

// The solid angle of the spherical triangle with unit corners a, b, c (Van Oosterom and
// Strackee).
double unit_solid_angle(const D3& a, const D3& b, const D3& c) {
    return std::abs(2 * std::atan2(dot(a, cross(b, c)), 1 + dot(a, b) + dot(a, c) + dot(b, c)));
}

struct SphericalTriangle {
    D3 a, b, c;
    double alpha = 0, area = 0;
};

// The corners as unit vectors, the angle at a and the area; none if degenerate from p.
std::optional<SphericalTriangle> spherical_triangle(const Vec3& v0, const Vec3& v1, const Vec3& v2,
                                                    const Vec3& p) {
    SphericalTriangle t;
    D3 o = to_d3(p);
    t.a = normalized(to_d3(v0) - o);
    t.b = normalized(to_d3(v1) - o);
    t.c = normalized(to_d3(v2) - o);
    D3 n_ab = normalized(cross(t.a, t.b)), n_ca = normalized(cross(t.c, t.a));
    if (length(n_ab) == 0 || length(n_ca) == 0 || length(cross(t.b, t.c)) == 0) return std::nullopt;
    t.alpha = angle_between(n_ab, -n_ca);
    t.area = unit_solid_angle(t.a, t.b, t.c);
    if (!(t.area > 0) || !std::isfinite(t.area)) return std::nullopt;
    return t;
}

// v minus its component along unit w, normalised; zero when v is along w.
D3 orthogonal_part(const D3& v, const D3& w) { return normalized(v - w * dot(v, w)); }

float sample_linear(float u, float a, float b) {
    if (u == 0 && a == 0) return 0;
    float x = u * (a + b) / (a + std::sqrt(lerp(u, a * a, b * b)));
    return std::min(x, kOneMinusEpsilon);
}

}  // namespace

float spherical_triangle_solid_angle(const Vec3& v0, const Vec3& v1, const Vec3& v2,
                                     const Vec3& p) {
    D3 o = to_d3(p);
    D3 a = to_d3(v0) - o, b = to_d3(v1) - o, c = to_d3(v2) - o;
    if (!(length(a) > 0 && length(b) > 0 && length(c) > 0)) return 0;
    double omega = unit_solid_angle(normalized(a), normalized(b), normalized(c));
    return std::isfinite(omega) ? float(omega) : 0.f;
}

std::optional<Vec3> sample_spherical_triangle(const Vec3& v0, const Vec3& v1, const Vec3& v2,
                                              const Vec3& p, Vec2 u) {
    auto t = spherical_triangle(v0, v1, v2, p);
    if (!t) return std::nullopt;
    // The sub-triangle's area A' = u.x A, through its angle sum A' + pi (Arvo's phi).
    double ap_pi = M_PI + double(u.x) * t->area;
    double cos_alpha = std::cos(t->alpha), sin_alpha = std::sin(t->alpha);
    double sin_phi = std::sin(ap_pi) * cos_alpha - std::cos(ap_pi) * sin_alpha;
    double cos_phi = std::cos(ap_pi) * cos_alpha + std::sin(ap_pi) * sin_alpha;
    double k1 = cos_phi + cos_alpha;
    double k2 = sin_phi - sin_alpha * dot(t->a, t->b);
    double denom = (k2 * sin_phi + k1 * cos_phi) * sin_alpha;
    double cos_bp = denom != 0 ? (k2 + (k2 * cos_phi - k1 * sin_phi) * cos_alpha) / denom : 1.0;
    cos_bp = std::clamp(cos_bp, -1.0, 1.0);
    double sin_bp = std::sqrt(std::max(0.0, 1 - cos_bp * cos_bp));
    D3 cp = t->a * cos_bp + orthogonal_part(t->c, t->a) * sin_bp;
    // Along the arc from b to c', uniform in the sub-triangle's area.
    double cos_theta = 1 - double(u.y) * (1 - dot(cp, t->b));
    double sin_theta = std::sqrt(std::max(0.0, 1 - cos_theta * cos_theta));
    D3 w = normalized(t->b * cos_theta + orthogonal_part(cp, t->b) * sin_theta);
    if (length(w) == 0) return std::nullopt;
    Vec3 wf(float(w.x), float(w.y), float(w.z));
    return wf / ml::length(wf);
}

Vec2 invert_spherical_triangle(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Vec3& p,
                               const Vec3& w_in) {
    auto t = spherical_triangle(v0, v1, v2, p);
    if (!t) return {0.5f, 0.5f};
    D3 w = normalized(to_d3(w_in));
    // c' is where the great circle through b and w meets the arc from a to c.
    D3 cp = normalized(cross(cross(t->b, w), cross(t->c, t->a)));
    if (length(cp) == 0) return {0.5f, 0.5f};
    if (dot(cp, t->a + t->c) < 0) cp = -cp;
    // u.x: the sub-triangle (a, b, c')'s share of the area, by the robust formula.
    double u0 = unit_solid_angle(t->a, t->b, cp) / t->area;
    // u.y = (1 - cos theta) / (1 - cos theta'), with 1 - cos x = |chord|^2 / 2 (no cancellation).
    D3 bw = w - t->b, bc = cp - t->b;
    double d = dot(bc, bc);
    double u1 = d > 0 ? dot(bw, bw) / d : 0.0;
    return {std::clamp(float(u0), 0.f, 1.f), std::clamp(float(u1), 0.f, 1.f)};
}

Vec2 sample_bilinear(Vec2 u, const float w[4]) {
    float y = sample_linear(u.y, w[0] + w[1], w[2] + w[3]);
    float x = sample_linear(u.x, lerp(y, w[0], w[2]), lerp(y, w[1], w[3]));
    return {x, y};
}

float pdf_bilinear_area(Vec2 p, const float w[4]) {
    float sum = w[0] + w[1] + w[2] + w[3];
    if (!(sum > 0)) return 1;
    return 4 *
           ((1 - p.x) * (1 - p.y) * w[0] + p.x * (1 - p.y) * w[1] + (1 - p.x) * p.y * w[2] +
            p.x * p.y * w[3]) /
           sum;
}

}  // namespace ml
