#include "camera/aperture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "core/assert.h"

namespace ml {

namespace {

constexpr int kRes = ApertureImage::kResolution;

// The centre of pixel (x, y) in [-1, 1]^2.
Vec2 pixel_centre(int x, int y) {
    return Vec2(-1 + 2 * (float(x) + 0.5f) / kRes, -1 + 2 * (float(y) + 0.5f) / kRes);
}

// 1 inside the polygon (non-zero winding number), 0 outside.
std::vector<float> rasterize(std::span<const Vec2> v) {
    std::vector<float> out(size_t(kRes) * kRes, 0.f);
    for (int y = 0; y < kRes; ++y)
        for (int x = 0; x < kRes; ++x) {
            Vec2 p = pixel_centre(x, y);
            int winding = 0;
            for (size_t i = 0; i < v.size(); ++i) {
                const Vec2& a = v[i];
                const Vec2& b = v[(i + 1) % v.size()];
                float e = (p.x - a.x) * (b.y - a.y) - (p.y - a.y) * (b.x - a.x);
                if (a.y <= p.y) {
                    if (b.y > p.y && e > 0) ++winding;
                } else if (b.y <= p.y && e < 0) {
                    --winding;
                }
            }
            out[size_t(y) * kRes + x] = winding == 0 ? 0.f : 1.f;
        }
    return out;
}

}  // namespace

bool ApertureImage::is_builtin_name(const std::string& name) {
    return name == "gaussian" || name == "square" || name == "pentagon" || name == "star";
}

ApertureImage ApertureImage::builtin(const std::string& name) {
    ApertureImage im;
    im.m_width = im.m_height = kRes;
    std::vector<float>& v = im.m_values;
    if (name == "gaussian") {
        v.resize(size_t(kRes) * kRes);
        for (int y = 0; y < kRes; ++y)
            for (int x = 0; x < kRes; ++x) {
                Vec2 p = pixel_centre(x, y);
                float r2 = p.x * p.x + p.y * p.y;
                v[size_t(y) * kRes + x] = std::max(0.f, std::exp(-r2) - std::exp(-1.f));
            }
    } else if (name == "square") {
        // The middle half of each axis.
        v.assign(size_t(kRes) * kRes, 0.f);
        for (int y = kRes / 4; y < 3 * kRes / 4; ++y)
            for (int x = kRes / 4; x < 3 * kRes / 4; ++x) v[size_t(y) * kRes + x] = 4.f;
    } else if (name == "pentagon") {
        // A regular pentagon of circumradius 0.8, a vertex up, clockwise.
        const float c1 = (std::sqrt(5.f) - 1) / 4, c2 = (std::sqrt(5.f) + 1) / 4;
        const float s1 = std::sqrt(10.f + 2.f * std::sqrt(5.f)) / 4;
        const float s2 = std::sqrt(10.f - 2.f * std::sqrt(5.f)) / 4;
        std::array<Vec2, 5> p = {Vec2(0, 1), Vec2(s1, c1), Vec2(s2, -c2), Vec2(-s2, -c2),
                                 Vec2(-s1, c1)};
        for (Vec2& q : p) q = q * 0.8f;
        v = rasterize(p);
    } else if (name == "star") {
        // Five points: vertices alternate between the inner pentagon's radius and 1, clockwise.
        std::array<Vec2, 10> p;
        const float inner = std::cos(radians(72.f)) / std::cos(radians(36.f));
        for (int i = 0; i < 10; ++i) {
            float r = (i & 1) ? 1.f : inner;
            float a = kPi * float(i) / 5.f;
            p[size_t(9 - i)] = Vec2(r * std::cos(a), r * std::sin(a));
        }
        v = rasterize(p);
    } else {
        return ApertureImage();
    }
    im.normalize();
    return im;
}

ApertureImage ApertureImage::from_values(int width, int height, std::vector<float> values,
                                         bool at_most_one) {
    ML_ASSERT(width > 0 && height > 0 && values.size() == size_t(width) * height,
              "an aperture image of width x height values");
    ApertureImage im;
    im.m_width = width, im.m_height = height;
    im.m_values = std::move(values);
    im.normalize(at_most_one);
    return im;
}

void ApertureImage::normalize(bool at_most_one) {
    std::vector<float>& v = m_values;
    for (int y = 0; y < m_height / 2; ++y)
        for (int x = 0; x < m_width; ++x)
            std::swap(v[size_t(y) * m_width + x], v[size_t(m_height - 1 - y) * m_width + x]);
    double sum = 0;
    for (float f : v) sum += f;
    ML_ASSERT(sum > 0, "an aperture that passes light (the caller refuses a black image)");
    const float scale = float((kPi / 4) / (sum / double(v.size())));
    for (float& f : v) f = at_most_one ? std::min(1.f, f * scale) : f * scale;
}

float ApertureImage::at(int x, int y) const {
    if (x < 0 || y < 0 || x >= m_width || y >= m_height) return 0.f;
    return m_values[size_t(y) * m_width + x];
}

float ApertureImage::lookup(float u, float w) const {
    // (u, w) in [-1, 1]^2 to [0, 1]^2, then bilinear among pixel centres.
    float x = (u + 1) / 2 * float(m_width) - 0.5f, y = (w + 1) / 2 * float(m_height) - 0.5f;
    float xf = std::floor(x), yf = std::floor(y);
    int xi = int(xf), yi = int(yf);
    float dx = x - xf, dy = y - yf;
    return (1 - dx) * (1 - dy) * at(xi, yi) + dx * (1 - dy) * at(xi + 1, yi) +
           (1 - dx) * dy * at(xi, yi + 1) + dx * dy * at(xi + 1, yi + 1);
}

}  // namespace ml
