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

// pbrt-v4's 2D texture mappings ("mapping" with its parameters): where a point of a surface
// lands in the texture's (s, t) plane.
//   uv:          (uscale u + udelta, vscale v + vdelta)
//   spherical:   (theta / pi, phi / 2 pi) of the point's direction from the texture-space
//                origin (theta from +z, phi from +x towards +y in [0, 2 pi))
//   cylindrical: ((pi + atan2(y, x)) / 2 pi, z) of the texture-space point
//   planar:      (udelta + p . v1, vdelta + p . v2) of the texture-space point
// Texture space is the CTM at the Texture directive.
struct TextureMapping2D {
    enum class Kind { UV, Spherical, Cylindrical, Planar };
    Kind kind = Kind::UV;
    float su = 1, sv = 1, du = 0, dv = 0;
    Vec3 v1{1, 0, 0}, v2{0, 1, 0};
    Transform world_to_texture;
    Vec2 map(const TextureEvalContext& ctx) const;
};

enum class WrapMode { Repeat, Black, Clamp };

// Image lookups shared by the float and RGB image textures. The image holds linear values
// (any sRGB or gamma decode was done once, at load).
class ImageLookup {
public:
    ImageLookup(std::shared_ptr<const Image> image, TextureMapping2D mapping, WrapMode wrap,
                bool point)
        : m_image(std::move(image)), m_mapping(mapping), m_wrap(wrap), m_point(point) {}
    // The filtered texel value where the mapping takes the context (t flipped, as pbrt-v4 does:
    // t = 0 is the bottom row of the image).
    RGB lookup(const TextureEvalContext& ctx) const;

private:
    RGB texel(int x, int y) const;
    std::shared_ptr<const Image> m_image;
    TextureMapping2D m_mapping;
    WrapMode m_wrap;
    bool m_point;
};

// A file name of the scene, relative to the scene file's folder unless absolute.
std::string resolve_path(const std::string& name, const std::string& base_dir);

struct ImageCache;
// pbrt-v4's "normalmap": the image of `filename` (relative to `base_dir`) read as linear values
// (no sRGB decode, whatever the format), looked up at (u, v) bilinearly, repeating.
ImageLookup normal_map_lookup(ImageCache& images, const std::string& base_dir,
                              const std::string& filename, const FileLoc& loc);

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

// pbrt-v4's "checkerboard": tex1 on the squares whose integer corners (floor s, floor t), or
// (floor x, floor y, floor z) of the texture-space point for dimension 3, sum to an even number,
// tex2 on the others. Point-sampled: pbrt-v4 box-filters the edges over the pixel's footprint,
// which changes nothing in expectation once a pixel's samples cover it.
struct Checkerboard {
    int dimension = 2;
    TextureMapping2D map2d;      // dimension 2
    Transform world_to_texture;  // dimension 3
    // True where tex2 shows.
    bool second(const TextureEvalContext& ctx) const;
};

// tex1 and tex2 (float or RGB textures) on the squares of a Checkerboard.
template <typename Base, typename Value>
class CheckerboardTexture final : public Base {
public:
    CheckerboardTexture(Checkerboard board, std::shared_ptr<Base> tex1, std::shared_ptr<Base> tex2)
        : m_board(std::move(board)), m_tex1(std::move(tex1)), m_tex2(std::move(tex2)) {}
    Value eval(const TextureEvalContext& ctx) const override {
        return m_board.second(ctx) ? m_tex2->eval(ctx) : m_tex1->eval(ctx);
    }

private:
    Checkerboard m_board;
    std::shared_ptr<Base> m_tex1, m_tex2;
};
using CheckerboardFloatTexture = CheckerboardTexture<FloatTexture, float>;
using CheckerboardRGBTexture = CheckerboardTexture<RGBTexture, RGB>;

}  // namespace ml
