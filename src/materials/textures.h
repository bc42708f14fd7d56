// The texture classes behind create_texture: constants, scaled textures and image maps with
// pbrt-v4's (u, v) mapping, wrap modes and filters. Exposed for tests and for materials that
// want to recognise constants.
#pragma once

#include <memory>
#include <vector>

#include "film/image.h"
#include "materials/texture.h"

namespace ml {

class ConstantFloatTexture final : public FloatTexture {
public:
    explicit ConstantFloatTexture(float v) : m_value(v) {}
    float eval(const TextureEvalContext&) const override { return m_value; }
    float value() const { return m_value; }

private:
    float m_value;
};

class ConstantRGBTexture final : public RGBTexture {
public:
    explicit ConstantRGBTexture(const RGB& v) : m_value(v) {}
    RGB eval(const TextureEvalContext&) const override { return m_value; }
    const RGB& value() const { return m_value; }

private:
    RGB m_value;
};

// A float texture read as grey RGB, for float textures named where colours are expected.
class FloatAsRGBTexture final : public RGBTexture {
public:
    explicit FloatAsRGBTexture(std::shared_ptr<FloatTexture> t) : m_tex(std::move(t)) {}
    RGB eval(const TextureEvalContext& ctx) const override { return RGB(m_tex->eval(ctx)); }

private:
    std::shared_ptr<FloatTexture> m_tex;
};

class ScaleFloatTexture final : public FloatTexture {
public:
    ScaleFloatTexture(std::shared_ptr<FloatTexture> tex, std::shared_ptr<FloatTexture> scale)
        : m_tex(std::move(tex)), m_scale(std::move(scale)) {}
    float eval(const TextureEvalContext& ctx) const override {
        float s = m_scale->eval(ctx);
        return s == 0 ? 0.f : s * m_tex->eval(ctx);
    }

private:
    std::shared_ptr<FloatTexture> m_tex, m_scale;
};

class ScaleRGBTexture final : public RGBTexture {
public:
    ScaleRGBTexture(std::shared_ptr<RGBTexture> tex, std::shared_ptr<FloatTexture> scale)
        : m_tex(std::move(tex)), m_scale(std::move(scale)) {}
    RGB eval(const TextureEvalContext& ctx) const override {
        float s = m_scale->eval(ctx);
        return s == 0 ? RGB() : m_tex->eval(ctx) * s;
    }

private:
    std::shared_ptr<RGBTexture> m_tex;
    std::shared_ptr<FloatTexture> m_scale;
};

// pbrt-v4's "uv" mapping: st = (su u + du, sv v + dv).
struct UVMapping {
    float su = 1, sv = 1, du = 0, dv = 0;
    Vec2 map(const Vec2& uv) const { return {su * uv.x + du, sv * uv.y + dv}; }
};

enum class WrapMode { Repeat, Black, Clamp };

// Image lookups shared by the float and RGB image textures. The image holds linear values
// (any sRGB or gamma decode was done once, at load).
class ImageLookup {
public:
    ImageLookup(std::shared_ptr<const Image> image, UVMapping mapping, WrapMode wrap, bool point)
        : m_image(std::move(image)), m_mapping(mapping), m_wrap(wrap), m_point(point) {}
    // The filtered texel value at texture coordinates uv (v flipped, as pbrt-v4 does: v = 0 is
    // the bottom row of the image).
    RGB lookup(const Vec2& uv) const;

private:
    RGB texel(int x, int y) const;
    std::shared_ptr<const Image> m_image;
    UVMapping m_mapping;
    WrapMode m_wrap;
    bool m_point;
};

class ImageRGBTexture final : public RGBTexture {
public:
    ImageRGBTexture(ImageLookup lookup, float scale, bool invert)
        : m_lookup(std::move(lookup)), m_scale(scale), m_invert(invert) {}
    RGB eval(const TextureEvalContext& ctx) const override;

private:
    ImageLookup m_lookup;
    float m_scale;
    bool m_invert;
};

// A float image texture reads the first channel, as pbrt-v4 does.
class ImageFloatTexture final : public FloatTexture {
public:
    ImageFloatTexture(ImageLookup lookup, float scale, bool invert)
        : m_lookup(std::move(lookup)), m_scale(scale), m_invert(invert) {}
    float eval(const TextureEvalContext& ctx) const override;

private:
    ImageLookup m_lookup;
    float m_scale;
    bool m_invert;
};

}  // namespace ml
