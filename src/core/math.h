// Small-vector math: points, vectors and normals share Vec3 (the measure lives in names, not
// types), 4x4 transforms, orthonormal frames, rays and boxes. Single precision throughout.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace ml {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 0.31830988618379067154f;
constexpr float kInv2Pi = 0.15915494309189533577f;
constexpr float kInv4Pi = 0.07957747154594766788f;
constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

inline float radians(float deg) { return deg * (kPi / 180.f); }
inline float degrees(float rad) { return rad * (180.f / kPi); }
inline float sqr(float x) { return x * x; }
inline float safe_sqrt(float x) { return std::sqrt(std::max(0.f, x)); }
inline float safe_acos(float x) { return std::acos(std::clamp(x, -1.f, 1.f)); }
inline float safe_asin(float x) { return std::asin(std::clamp(x, -1.f, 1.f)); }
inline float lerp(float t, float a, float b) { return (1 - t) * a + t * b; }

// Floating-point error analysis (Higham; pbrt-v4 section 6.8): the unit roundoff, the bound
// gamma(n) = n u / (1 - n u) on the relative error of n successive roundings, and the
// neighbouring floats: std::nextafter towards +-infinity, by stepping the bits inline (pbrt-v4's
// NextFloatUp), not through libm's call (2% of an igi frame: every shadow ray takes six).
constexpr float kMachineEpsilon = std::numeric_limits<float>::epsilon() * 0.5f;
constexpr float gamma_bound(int n) { return (n * kMachineEpsilon) / (1 - n * kMachineEpsilon); }
inline float next_float_up(float v) {
    if (!(v < kInfinity)) return v;  // +infinity and NaN stay
    if (v == 0.f) v = 0.f;           // -0 steps up to the least positive float, as +0 does
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v >= 0 ? bits + 1 : bits - 1;
    return std::bit_cast<float>(bits);
}
inline float next_float_down(float v) {
    if (!(v > -kInfinity)) return v;
    if (v == 0.f) v = -0.f;
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v > 0 ? bits - 1 : bits + 1;
    return std::bit_cast<float>(bits);
}

struct Vec2 {
    float x = 0, y = 0;
    constexpr Vec2() = default;
    constexpr Vec2(float x_, float y_) : x(x_), y(y_) {}
    float operator[](int i) const { return i == 0 ? x : y; }
    float& operator[](int i) { return i == 0 ? x : y; }
    Vec2 operator+(Vec2 b) const { return {x + b.x, y + b.y}; }
    Vec2 operator-(Vec2 b) const { return {x - b.x, y - b.y}; }
    Vec2 operator*(float s) const { return {x * s, y * s}; }
};
inline Vec2 operator*(float s, Vec2 v) { return v * s; }

struct Vec3 {
    float x = 0, y = 0, z = 0;
    constexpr Vec3() = default;
    constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3 operator+(const Vec3& b) const { return {x + b.x, y + b.y, z + b.z}; }
    Vec3 operator-(const Vec3& b) const { return {x - b.x, y - b.y, z - b.z}; }
    Vec3 operator-() const { return {-x, -y, -z}; }
    Vec3 operator*(float s) const { return {x * s, y * s, z * s}; }
    Vec3 operator/(float s) const {
        float inv = 1.f / s;
        return {x * inv, y * inv, z * inv};
    }
    Vec3& operator+=(const Vec3& b) {
        x += b.x, y += b.y, z += b.z;
        return *this;
    }
    Vec3& operator-=(const Vec3& b) {
        x -= b.x, y -= b.y, z -= b.z;
        return *this;
    }
    Vec3& operator*=(float s) {
        x *= s, y *= s, z *= s;
        return *this;
    }
    bool operator==(const Vec3& b) const { return x == b.x && y == b.y && z == b.z; }
};
inline Vec3 operator*(float s, const Vec3& v) { return v * s; }
inline Vec3 mul(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float abs_dot(const Vec3& a, const Vec3& b) { return std::abs(dot(a, b)); }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length_squared(const Vec3& v) { return dot(v, v); }
inline float length(const Vec3& v) { return std::sqrt(dot(v, v)); }
inline Vec3 normalize(const Vec3& v) { return v / length(v); }
inline float distance(const Vec3& a, const Vec3& b) { return length(a - b); }
inline float distance_squared(const Vec3& a, const Vec3& b) { return length_squared(a - b); }
inline Vec3 vmin(const Vec3& a, const Vec3& b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline Vec3 vmax(const Vec3& a, const Vec3& b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
inline Vec3 vabs(const Vec3& a) { return {std::abs(a.x), std::abs(a.y), std::abs(a.z)}; }
inline float max_component(const Vec3& v) { return std::max({v.x, v.y, v.z}); }
inline bool is_finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
// The normal n turned to the hemisphere of v.
inline Vec3 face_forward(const Vec3& n, const Vec3& v) { return dot(n, v) < 0.f ? -n : n; }
inline Vec3 reflect(const Vec3& wo, const Vec3& n) { return -wo + 2 * dot(wo, n) * n; }

// Two unit vectors completing n (unit) to a right-handed orthonormal basis (Duff et al. 2017).
inline void coordinate_system(const Vec3& n, Vec3* s, Vec3* t) {
    float sign = std::copysign(1.f, n.z);
    float a = -1.f / (sign + n.z);
    float b = n.x * n.y * a;
    *s = Vec3(1 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    *t = Vec3(b, sign + n.y * n.y * a, -n.y);
}

// An orthonormal frame; local coordinates have the normal along +z.
struct Frame {
    Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};
    Frame() = default;
    Frame(const Vec3& s_, const Vec3& t_, const Vec3& n_) : s(s_), t(t_), n(n_) {}
    static Frame from_z(const Vec3& n) {
        Frame f;
        f.n = n;
        coordinate_system(n, &f.s, &f.t);
        return f;
    }
    // A frame with normal n whose s axis follows the tangent dpdu as closely as possible.
    static Frame from_normal_tangent(const Vec3& n, const Vec3& dpdu) {
        Vec3 s = dpdu - n * dot(n, dpdu);
        float l2 = length_squared(s);
        if (!(l2 > 1e-12f)) return from_z(n);
        s = s / std::sqrt(l2);
        return Frame(s, cross(n, s), n);
    }
    Vec3 to_local(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

struct Ray {
    Vec3 o, d;
    float tmax = kInfinity;
    float time = 0;
    Vec3 at(float t) const { return o + d * t; }
};

struct Bounds3 {
    Vec3 lo{kInfinity, kInfinity, kInfinity};
    Vec3 hi{-kInfinity, -kInfinity, -kInfinity};
    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    void expand(const Vec3& p) {
        lo = vmin(lo, p);
        hi = vmax(hi, p);
    }
    void expand(const Bounds3& b) {
        lo = vmin(lo, b.lo);
        hi = vmax(hi, b.hi);
    }
    Vec3 center() const { return (lo + hi) * 0.5f; }
    Vec3 diagonal() const { return hi - lo; }
    void bounding_sphere(Vec3* c, float* r) const {
        *c = center();
        *r = empty() ? 0.f : distance(*c, hi);
    }
};

// A 4x4 affine or projective transform with its inverse kept alongside.
class Transform {
public:
    Transform() {
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) m_m[i][j] = m_inv[i][j] = (i == j) ? 1.f : 0.f;
    }
    // Row-major m[row][col]; returns false in `ok` if m is singular.
    static Transform from_matrix(const float m[4][4], bool* ok = nullptr);
    static Transform translate(const Vec3& d);
    static Transform scale(const Vec3& s);
    static Transform rotate(float degrees, const Vec3& axis);
    static Transform look_at(const Vec3& eye, const Vec3& look, const Vec3& up, bool* ok);
    static Transform perspective(float fov_degrees, float n, float f);

    Transform operator*(const Transform& b) const;
    Transform inverse() const {
        Transform t;
        std::copy(&m_inv[0][0], &m_inv[0][0] + 16, &t.m_m[0][0]);
        std::copy(&m_m[0][0], &m_m[0][0] + 16, &t.m_inv[0][0]);
        return t;
    }
    Vec3 point(const Vec3& p) const {
        float x = m_m[0][0] * p.x + m_m[0][1] * p.y + m_m[0][2] * p.z + m_m[0][3];
        float y = m_m[1][0] * p.x + m_m[1][1] * p.y + m_m[1][2] * p.z + m_m[1][3];
        float z = m_m[2][0] * p.x + m_m[2][1] * p.y + m_m[2][2] * p.z + m_m[2][3];
        float w = m_m[3][0] * p.x + m_m[3][1] * p.y + m_m[3][2] * p.z + m_m[3][3];
        return w == 1.f ? Vec3(x, y, z) : Vec3(x, y, z) / w;
    }
    Vec3 vector(const Vec3& v) const {
        return {m_m[0][0] * v.x + m_m[0][1] * v.y + m_m[0][2] * v.z,
                m_m[1][0] * v.x + m_m[1][1] * v.y + m_m[1][2] * v.z,
                m_m[2][0] * v.x + m_m[2][1] * v.y + m_m[2][2] * v.z};
    }
    // Normals transform by the inverse transpose.
    Vec3 normal(const Vec3& n) const {
        return {m_inv[0][0] * n.x + m_inv[1][0] * n.y + m_inv[2][0] * n.z,
                m_inv[0][1] * n.x + m_inv[1][1] * n.y + m_inv[2][1] * n.z,
                m_inv[0][2] * n.x + m_inv[1][2] * n.y + m_inv[2][2] * n.z};
    }
    // True if the transform flips handedness (negative determinant of the upper 3x3).
    bool swaps_handedness() const;
    float m(int r, int c) const { return m_m[r][c]; }

private:
    float m_m[4][4];
    float m_inv[4][4];
};

}  // namespace ml
