// Linear RGB radiometric quantities (radiance, power, reflectance). manylight renders in RGB.
#pragma once

#include <algorithm>
#include <cmath>

namespace ml {

struct RGB {
    float r = 0, g = 0, b = 0;
    constexpr RGB() = default;
    constexpr explicit RGB(float v) : r(v), g(v), b(v) {}
    constexpr RGB(float r_, float g_, float b_) : r(r_), g(g_), b(b_) {}
    float operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
    float& operator[](int i) { return i == 0 ? r : (i == 1 ? g : b); }
    RGB operator+(const RGB& o) const { return {r + o.r, g + o.g, b + o.b}; }
    RGB operator-(const RGB& o) const { return {r - o.r, g - o.g, b - o.b}; }
    RGB operator*(const RGB& o) const { return {r * o.r, g * o.g, b * o.b}; }
    RGB operator/(const RGB& o) const {
        return {o.r != 0 ? r / o.r : 0.f, o.g != 0 ? g / o.g : 0.f, o.b != 0 ? b / o.b : 0.f};
    }
    RGB operator*(float s) const { return {r * s, g * s, b * s}; }
    RGB operator/(float s) const {
        float inv = 1.f / s;
        return {r * inv, g * inv, b * inv};
    }
    RGB& operator+=(const RGB& o) {
        r += o.r, g += o.g, b += o.b;
        return *this;
    }
    RGB& operator*=(const RGB& o) {
        r *= o.r, g *= o.g, b *= o.b;
        return *this;
    }
    RGB& operator*=(float s) {
        r *= s, g *= s, b *= s;
        return *this;
    }
    bool operator==(const RGB& o) const { return r == o.r && g == o.g && b == o.b; }
    bool is_black() const { return r == 0 && g == 0 && b == 0; }
    float max_component() const { return std::max({r, g, b}); }
    float average() const { return (r + g + b) * (1.f / 3.f); }
    // Rec. 709 luminance.
    float luminance() const { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }
    bool is_finite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
};
inline RGB operator*(float s, const RGB& c) { return c * s; }
inline RGB sqrt(const RGB& c) { return {std::sqrt(c.r), std::sqrt(c.g), std::sqrt(c.b)}; }
inline RGB exp(const RGB& c) { return {std::exp(c.r), std::exp(c.g), std::exp(c.b)}; }
inline RGB clamp_zero(const RGB& c) {
    return {std::max(0.f, c.r), std::max(0.f, c.g), std::max(0.f, c.b)};
}

inline float srgb_to_linear(float v) {
    if (v <= 0.04045f) return v * (1.f / 12.92f);
    return std::pow((v + 0.055f) * (1.f / 1.055f), 2.4f);
}
inline float linear_to_srgb(float v) {
    if (v <= 0.0031308f) return 12.92f * v;
    return 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
}

}  // namespace ml
