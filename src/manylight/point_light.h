// Point lights: what every light becomes for the many-light integrators (DESIGN.md section 1).
// Area lights are sampled into oriented lights, environment maps and distant lights into
// directional lights, point lights stay omni, spot lights are omni lights with a cone, and
// virtual point lights (VPLs) deposited by light paths are oriented lights (diffuse surfaces) or
// re-emit through their surface's BSDF (glossy surfaces).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/color.h"
#include "core/math.h"
#include "core/scratch.h"
#include "materials/bsdf.h"

namespace ml {

enum class PointLightKind : uint8_t {
    Omni,         // intensity in every direction (spot lights: within their cone)
    Oriented,     // intensity * max(0, cos(n, w)): a cosine lobe about n
    Directional,  // parallel light travelling along n; intensity is the irradiance it gives
};

// What becomes of light paths at glossy surfaces (vpl.glossy): a VPL that re-emits through the
// whole BSDF, one that keeps only its diffuse part (Bxdf::eval_diffuse; none on a surface with
// no diffuse part), or no VPL. The path carries on through the BSDF in every case.
enum class GlossyVpls : uint8_t { Bsdf, Diffuse, Skip };

struct PointLight {
    Vec3 p;  // position (omni, oriented)
    Vec3 n;  // oriented: lobe axis; directional: unit direction the light travels; spot: axis
    // Omni: W/sr. Oriented: W/sr along n, an upper bound of the lobe everywhere (for a glossy
    // VPL: flux times the largest BSDF value). Directional: irradiance at normal incidence.
    RGB intensity;
    PointLightKind kind = PointLightKind::Omni;
    // Spot lights: smoothstep falloff from 1 inside cos_start to 0 outside cos_end (about n).
    // Plain omni lights have cos_end = -2 (no cone).
    float cos_start = 1, cos_end = -2;
    // Glossy VPLs: index into PointLightSet::surfaces, whose BSDF the light re-emits through;
    // -1: the cosine lobe (or omni/directional as above).
    int32_t surface = -1;
    bool is_vpl = false;
};

// The surface of a glossy VPL: its BSDF (with the Bxdf kept alive by the set's arenas), the
// direction the light arrived from, and the flux that arrived.
struct VplSurface {
    Bsdf bsdf;
    Vec3 wi;                    // unit, pointing back towards where the light came from
    RGB flux;                   // incident flux carried by the light path
    bool diffuse_only = false;  // re-emits through the BSDF's diffuse part alone
};

struct PointLightSet {
    std::vector<PointLight> lights;  // emitters' point lights first, then the VPLs
    std::vector<VplSurface> surfaces;
    std::vector<std::unique_ptr<ScratchBuffer>> arenas;  // the VPL surfaces' Bxdfs live here
    size_t omni = 0, oriented = 0, directional = 0;      // counts by kind
    size_t vpls = 0;                                     // how many of the lights are VPLs
    size_t light_paths = 0;                              // light paths traced for the VPLs
    double seconds = 0;                                  // time to build the set
};

// Intensity of `pl` leaving towards unit direction `w` (from the light; ignored for
// directional lights, which return their irradiance): what reaches a receiver at distance d is
// this / d^2 (directional: this, undivided).
RGB point_light_intensity(const PointLightSet& set, const PointLight& pl, const Vec3& w);

}  // namespace ml
