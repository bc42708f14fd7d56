// Materials turn a hit into a BSDF: they look up their textures, apply bump mapping to the
// shading frame, and build a Bxdf in the per-sample scratch buffer.
#pragma once

#include <memory>
#include <string>

#include "core/color.h"
#include "core/scratch.h"
#include "geometry/interaction.h"
#include "materials/bsdf.h"

namespace ml {

// What fills a closed shape of a material that has an inside (pbrt-v4's "subsurface"): a
// homogeneous medium, per unit of world distance, that the scene gives the shape as its inside.
struct InteriorMedium {
    RGB sigma_a, sigma_s;
    float g = 0;
};

class Material {
public:
    virtual ~Material() = default;
    // The medium inside shapes of this material, if it brings one.
    virtual const InteriorMedium* interior_medium() const { return nullptr; }
    // The BSDF at a hit; its Bxdf lives in `scratch` until the next reset.
    virtual Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const = 0;
    virtual std::string type() const = 0;
};

// The BSDF at a hit (none when the surface has no material), with si.ns set to the BSDF's
// shading normal: bump mapping tilts it, and every cosine at the hit must use the tilted normal
// the BSDF was built around (pbrt-v4's SetShadingGeometry). Integrators call this, not
// Material::get_bsdf.
inline Bsdf hit_bsdf(SurfaceInteraction& si, ScratchBuffer& scratch) {
    if (!si.material) return Bsdf();
    Bsdf bsdf = si.material->get_bsdf(si, scratch);
    if (bsdf) si.ns = bsdf.frame().n;
    return bsdf;
}

}  // namespace ml
