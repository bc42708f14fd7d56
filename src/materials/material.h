// Materials turn a hit into a BSDF: they look up their textures, apply bump mapping to the
// shading frame, and build a Bxdf in the per-sample scratch buffer.
#pragma once

#include <memory>
#include <string>

#include "core/scratch.h"
#include "geometry/interaction.h"
#include "materials/bsdf.h"

namespace ml {

class Material {
public:
    virtual ~Material() = default;
    // The BSDF at a hit; its Bxdf lives in `scratch` until the next reset.
    virtual Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const = 0;
    virtual std::string type() const = 0;
};

}  // namespace ml
