// Textures: float and RGB values over a surface, looked up by (u, v) (and p, for procedural ones).
#pragma once

#include <map>
#include <memory>
#include <string>

#include "core/color.h"
#include "core/math.h"

namespace ml {

struct TextureEvalContext {
    Vec3 p;
    Vec2 uv;
    Vec3 n = Vec3(0, 0, 0);  // the geometric normal (directionmix); zero where there is none
};

class FloatTexture {
public:
    virtual ~FloatTexture() = default;
    virtual float eval(const TextureEvalContext& ctx) const = 0;
};

class RGBTexture {
public:
    virtual ~RGBTexture() = default;
    virtual RGB eval(const TextureEvalContext& ctx) const = 0;
};

// Named textures as declared by the scene's `Texture` directives, for materials to look up.
struct NamedTextures {
    std::map<std::string, std::shared_ptr<FloatTexture>> floats;
    std::map<std::string, std::shared_ptr<RGBTexture>> rgbs;
};

}  // namespace ml
