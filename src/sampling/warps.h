// Warps from the unit square to common domains. Each comes as a sample/pdf pair whose pdf names
// its measure (area of the target domain, or solid angle), with the inverse where it is cheap, so
// chi-square tests and MIS can check every pair.
#pragma once

#include <cmath>

#include "core/math.h"

namespace ml {

// Concentric (Shirley-Chiu) disk: preserves strata and adjacency better than the polar map.
inline Vec2 sample_uniform_disk_concentric(Vec2 u) {
    float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
    if (ox == 0 && oy == 0) return {0, 0};
    float r, theta;
    if (std::abs(ox) > std::abs(oy)) {
        r = ox;
        theta = (kPi / 4) * (oy / ox);
    } else {
        r = oy;
        theta = kPi / 2 - (kPi / 4) * (ox / oy);
    }
    return {r * std::cos(theta), r * std::sin(theta)};
}
inline float pdf_uniform_disk_area() { return kInvPi; }
inline Vec2 invert_uniform_disk_concentric(Vec2 p) {
    float r = std::sqrt(p.x * p.x + p.y * p.y);
    float phi = std::atan2(p.y, p.x);
    if (phi < -kPi / 4) phi += 2 * kPi;  // phi in [-pi/4, 7pi/4)
    float a, b;
    if (phi < kPi / 4) {  // right wedge: r = ox
        a = r;
        b = phi * a / (kPi / 4);
    } else if (phi < 3 * kPi / 4) {  // top wedge: r = oy
        b = r;
        a = -(phi - kPi / 2) * b / (kPi / 4);
    } else if (phi < 5 * kPi / 4) {  // left wedge: r = -ox
        a = -r;
        b = (phi - kPi) * a / (kPi / 4);
    } else {  // bottom wedge: r = -oy
        b = -r;
        a = -(phi - 3 * kPi / 2) * b / (kPi / 4);
    }
    return {std::clamp(0.5f * (a + 1), 0.f, kOneMinusEpsilon),
            std::clamp(0.5f * (b + 1), 0.f, kOneMinusEpsilon)};
}

// Cosine-weighted hemisphere about +z (Malley's method).
inline Vec3 sample_cosine_hemisphere(Vec2 u) {
    Vec2 d = sample_uniform_disk_concentric(u);
    float z = safe_sqrt(1 - d.x * d.x - d.y * d.y);
    return {d.x, d.y, z};
}
inline float pdf_cosine_hemisphere(float cos_theta) { return std::max(0.f, cos_theta) * kInvPi; }
inline Vec2 invert_cosine_hemisphere(const Vec3& w) {
    return invert_uniform_disk_concentric({w.x, w.y});
}

// Uniform hemisphere about +z, solid angle.
inline Vec3 sample_uniform_hemisphere(Vec2 u) {
    float z = u.x;
    float r = safe_sqrt(1 - z * z);
    float phi = 2 * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float pdf_uniform_hemisphere() { return kInv2Pi; }
inline Vec2 invert_uniform_hemisphere(const Vec3& w) {
    float phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += 2 * kPi;
    return {w.z, std::min(phi * kInv2Pi, kOneMinusEpsilon)};
}

// Uniform sphere, solid angle.
inline Vec3 sample_uniform_sphere(Vec2 u) {
    float z = 1 - 2 * u.x;
    float r = safe_sqrt(1 - z * z);
    float phi = 2 * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float pdf_uniform_sphere() { return kInv4Pi; }
inline Vec2 invert_uniform_sphere(const Vec3& w) {
    float phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += 2 * kPi;
    return {(1 - w.z) / 2, std::min(phi * kInv2Pi, kOneMinusEpsilon)};
}

// Uniform cone of directions about +z with cos(half angle) = cos_max, solid angle.
inline Vec3 sample_uniform_cone(Vec2 u, float cos_max) {
    float cos_theta = (1 - u.x) + u.x * cos_max;
    float sin_theta = safe_sqrt(1 - cos_theta * cos_theta);
    float phi = 2 * kPi * u.y;
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}
inline float pdf_uniform_cone(float cos_max) { return 1 / (2 * kPi * (1 - cos_max)); }
inline Vec2 invert_uniform_cone(const Vec3& w, float cos_max) {
    float phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += 2 * kPi;
    return {std::clamp((1 - w.z) / (1 - cos_max), 0.f, kOneMinusEpsilon),
            std::min(phi * kInv2Pi, kOneMinusEpsilon)};
}

// Uniform barycentrics (b0, b1, b2) over a triangle (Heitz 2019's low-distortion split), area
// density 1 / triangle area.
struct Barycentrics {
    float b0, b1, b2;
};
inline Barycentrics sample_uniform_triangle(Vec2 u) {
    float b0, b1;
    if (u.x < u.y) {
        b0 = u.x / 2;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2;
        b0 = u.x - b1;
    }
    return {b0, b1, 1 - b0 - b1};
}
inline Vec2 invert_uniform_triangle(const Barycentrics& b) {
    if (b.b0 > b.b1) {  // came from u.x >= u.y: b1 = uy / 2, b0 = ux - b1
        float uy = 2 * b.b1;
        return {b.b0 + b.b1, uy};
    }
    float ux = 2 * b.b0;
    return {ux, b.b1 + b.b0};
}

// Exponential density a exp(-a x) on [0, inf).
inline float sample_exponential(float u, float a) { return -std::log(1 - u) / a; }
inline float pdf_exponential(float x, float a) { return a * std::exp(-a * x); }
inline float invert_exponential(float x, float a) { return 1 - std::exp(-a * x); }

// Equal-area octahedral mapping between [0,1]^2 and the unit sphere (Clarberg 2008), the
// parameterisation pbrt-v4 reads square environment maps in. +z is the centre of the square and
// -z its corners; a unit area of the square covers 4 pi steradians uniformly.
Vec3 equal_area_square_to_sphere(Vec2 p);
Vec2 equal_area_sphere_to_square(const Vec3& d);

// Spherical coordinates with +z as the pole: theta from +z, phi from +x towards +y in [0, 2pi).
inline Vec3 spherical_direction(float sin_theta, float cos_theta, float phi) {
    sin_theta = std::clamp(sin_theta, -1.f, 1.f);
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), std::clamp(cos_theta, -1.f, 1.f)};
}
inline float spherical_theta(const Vec3& v) { return safe_acos(v.z); }
inline float spherical_phi(const Vec3& v) {
    float p = std::atan2(v.y, v.x);
    return p < 0 ? p + 2 * kPi : p;
}

// Point i of n of a Hammersley set, shifted (mod 1) by `shift`: n stratified points in the unit
// square, each one uniformly distributed when the shift is uniform (so estimates stay unbiased).
inline Vec2 shifted_hammersley(uint32_t i, uint32_t n, const Vec2& shift) {
    uint32_t r = i;
    r = (r << 16) | (r >> 16);
    r = ((r & 0x00ff00ffu) << 8) | ((r & 0xff00ff00u) >> 8);
    r = ((r & 0x0f0f0f0fu) << 4) | ((r & 0xf0f0f0f0u) >> 4);
    r = ((r & 0x33333333u) << 2) | ((r & 0xccccccccu) >> 2);
    r = ((r & 0x55555555u) << 1) | ((r & 0xaaaaaaaau) >> 1);
    float x = (float(i) + 0.5f) / float(n) + shift.x;
    float y = float(r) * 0x1p-32f + shift.y;
    x -= std::floor(x);
    y -= std::floor(y);
    return {std::min(x, kOneMinusEpsilon), std::min(y, kOneMinusEpsilon)};
}

}  // namespace ml
