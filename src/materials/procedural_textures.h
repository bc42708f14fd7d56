// pbrt-v4's procedural textures but checkerboard (textures.h): bilerp, dots, fbm, wrinkled,
// windy, marble, mix and directionmix, each as pbrt-v4 evaluates it. The noise textures read the
// texture-space point (the CTM at the Texture directive); bilerp and dots a 2D mapping.
#pragma once

#include <memory>
#include <utility>

#include "materials/textures.h"

namespace ml {

// (1-s)(1-t) v00 + s(1-t) v10 + (1-s)t v01 + st v11 at the mapping's (s, t).
template <typename Base, typename Value>
class BilerpTexture final : public Base {
public:
    BilerpTexture(TextureMapping2D mapping, Value v00, Value v01, Value v10, Value v11)
        : m_mapping(std::move(mapping)), m_v00(v00), m_v01(v01), m_v10(v10), m_v11(v11) {}
    Value eval(const TextureEvalContext& ctx) const override {
        Vec2 st = m_mapping.map(ctx);
        return m_v00 * ((1 - st.x) * (1 - st.y)) + m_v10 * (st.x * (1 - st.y)) +
               m_v01 * ((1 - st.x) * st.y) + m_v11 * (st.x * st.y);
    }

private:
    TextureMapping2D m_mapping;
    Value m_v00, m_v01, m_v10, m_v11;
};
using BilerpFloatTexture = BilerpTexture<FloatTexture, float>;
using BilerpRGBTexture = BilerpTexture<RGBTexture, RGB>;

// pbrt-v4's polka dots: in each unit cell around an integer (s, t) whose noise is positive, a dot
// of radius 0.35 placed by two more noise lookups.
bool inside_polka_dot(const Vec2& st);

// pbrt-v4's "dots". pbrt-v4 passes its "inside" texture where its constructor expects the
// outside one and the reverse, so the "outside" texture shows inside the dots: kept, so that a
// pbrt-v4 scene looks the same here.
template <typename Base, typename Value>
class DotsTexture final : public Base {
public:
    DotsTexture(TextureMapping2D mapping, std::shared_ptr<Base> in_dots,
                std::shared_ptr<Base> between_dots)
        : m_mapping(std::move(mapping)),
          m_in(std::move(in_dots)),
          m_between(std::move(between_dots)) {}
    Value eval(const TextureEvalContext& ctx) const override {
        return inside_polka_dot(m_mapping.map(ctx)) ? m_in->eval(ctx) : m_between->eval(ctx);
    }

private:
    TextureMapping2D m_mapping;
    std::shared_ptr<Base> m_in, m_between;
};
using DotsFloatTexture = DotsTexture<FloatTexture, float>;
using DotsRGBTexture = DotsTexture<RGBTexture, RGB>;

// "fbm", "wrinkled" (turbulence) and "windy" (|fbm(p/10), 3 octaves| x fbm(p, 6 octaves)).
class NoiseTexture final : public FloatTexture {
public:
    enum class Kind { Fbm, Wrinkled, Windy };
    NoiseTexture(Kind kind, Transform world_to_texture, int octaves, float omega)
        : m_kind(kind), m_world_to_texture(world_to_texture), m_octaves(octaves), m_omega(omega) {}
    float eval(const TextureEvalContext& ctx) const override;

private:
    Kind m_kind;
    Transform m_world_to_texture;
    int m_octaves;
    float m_omega;
};

// "marble": sin of the texture-space y perturbed by fbm, through pbrt-v4's cubic Bezier of
// marble colours, times 1.5.
class MarbleTexture final : public RGBTexture {
public:
    MarbleTexture(Transform world_to_texture, int octaves, float omega, float scale,
                  float variation)
        : m_world_to_texture(world_to_texture),
          m_octaves(octaves),
          m_omega(omega),
          m_scale(scale),
          m_variation(variation) {}
    RGB eval(const TextureEvalContext& ctx) const override;

private:
    Transform m_world_to_texture;
    int m_octaves;
    float m_omega, m_scale, m_variation;
};

// "mix": (1 - amount) tex1 + amount tex2; "directionmix": amount = |n . dir| (n the geometric
// normal), amount tex1 + (1 - amount) tex2. A texture whose weight is 0 is not evaluated.
template <typename Base, typename Value>
class MixTexture final : public Base {
public:
    MixTexture(std::shared_ptr<Base> tex1, std::shared_ptr<Base> tex2,
               std::shared_ptr<FloatTexture> amount)
        : m_tex1(std::move(tex1)), m_tex2(std::move(tex2)), m_amount(std::move(amount)) {}
    MixTexture(std::shared_ptr<Base> tex1, std::shared_ptr<Base> tex2, const Vec3& dir)
        : m_tex1(std::move(tex1)), m_tex2(std::move(tex2)), m_dir(dir) {}
    Value eval(const TextureEvalContext& ctx) const override {
        // Weight of tex2.
        float w = m_amount ? m_amount->eval(ctx) : 1 - abs_dot(ctx.n, m_dir);
        Value v = Value();
        if (w != 1) v = v + m_tex1->eval(ctx) * (1 - w);
        if (w != 0) v = v + m_tex2->eval(ctx) * w;
        return v;
    }

private:
    std::shared_ptr<Base> m_tex1, m_tex2;
    std::shared_ptr<FloatTexture> m_amount;  // null: directionmix
    Vec3 m_dir;
};
using MixFloatTexture = MixTexture<FloatTexture, float>;
using MixRGBTexture = MixTexture<RGBTexture, RGB>;

}  // namespace ml
