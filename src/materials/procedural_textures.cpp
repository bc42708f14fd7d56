#include "materials/procedural_textures.h"

#include <algorithm>
#include <cmath>

#include "core/noise.h"

namespace ml {

bool inside_polka_dot(const Vec2& st) {
    // The cell around the nearest integer point; a dot only where the noise there is positive.
    const float s_cell = std::floor(st.x + .5f), t_cell = std::floor(st.y + .5f);
    if (!(perlin_noise(s_cell + .5f, t_cell + .5f, .5f) > 0)) return false;
    constexpr float kRadius = .35f, kMaxShift = 0.5f - kRadius;
    const float s_centre = s_cell + kMaxShift * perlin_noise(s_cell + 1.5f, t_cell + 2.8f, .5f);
    const float t_centre = t_cell + kMaxShift * perlin_noise(s_cell + 4.5f, t_cell + 9.8f, .5f);
    return sqr(st.x - s_centre) + sqr(st.y - t_centre) < sqr(kRadius);
}

float NoiseTexture::eval(const TextureEvalContext& ctx) const {
    const Vec3 p = m_world_to_texture.point(ctx.p);
    switch (m_kind) {
        case Kind::Fbm:
            return fbm(p, 0, m_omega, m_octaves);
        case Kind::Wrinkled:
            return turbulence(p, 0, m_omega, m_octaves);
        case Kind::Windy:
            return std::abs(fbm(p * .1f, 0, .5f, 3)) * fbm(p, 0, .5f, 6);
    }
    return 0;
}

RGB MarbleTexture::eval(const TextureEvalContext& ctx) const {
    const Vec3 p = m_world_to_texture.point(ctx.p) * m_scale;
    const float marble = p.y + m_variation * fbm(p, 0, m_omega, m_octaves);
    float t = .5f + .5f * std::sin(marble);
    // pbrt-v4's colours, as control points of consecutive cubic Bezier segments.
    static const RGB kColors[] = {
        {.58f, .58f, .6f}, {.58f, .58f, .6f}, {.58f, .58f, .6f},
        {.5f, .5f, .5f},   {.6f, .59f, .58f}, {.58f, .58f, .6f},
        {.58f, .58f, .6f}, {.2f, .2f, .33f},  {.58f, .58f, .6f},
    };
    constexpr int kSegments = int(std::size(kColors)) - 3;
    const int first = std::min(int(std::floor(t * kSegments)), kSegments - 1);
    t = t * kSegments - float(first);
    const RGB* c = kColors + first;
    const float s = 1 - t;
    RGB bezier =
        c[0] * (s * s * s) + c[1] * (3 * s * s * t) + c[2] * (3 * s * t * t) + c[3] * (t * t * t);
    return bezier * 1.5f;
}

}  // namespace ml
