// Point lights: what every light becomes for the many-light integrators (DESIGN.md section 1).
// Area lights are sampled into oriented lights, environment maps and distant lights into
// directional lights, point lights stay omni, spot lights are omni lights with a cone, and
// virtual point lights (VPLs) deposited by light paths are oriented lights (diffuse surfaces),
// glossy lights (reflecting glossy surfaces: a lobe about the mirror direction, bounded by how it
// falls off away from it) or omni lights (surfaces that transmit), the last two re-emitting
// through their surface's BSDF.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/color.h"
#include "core/math.h"
#include "core/scratch.h"
#include "materials/bsdf.h"

namespace ml {

class Light;

enum class PointLightKind : uint8_t {
    Omni,         // intensity in every direction (spot lights: within their cone)
    Oriented,     // intensity * max(0, cos(n, w)): a cosine lobe about n
    Directional,  // parallel light travelling along n; intensity is the irradiance it gives
    // A glossy VPL: intensity * falloff(angle between n and w) bounds what it sends towards w,
    // n being the mirror direction of the light's arrival, where a reflection lobe peaks.
    Glossy,
};
constexpr int kPointLightKinds = 4;
constexpr PointLightKind kAllPointLightKinds[kPointLightKinds] = {
    PointLightKind::Omni, PointLightKind::Oriented, PointLightKind::Directional,
    PointLightKind::Glossy};

// A glossy light's falloff: bin k bounds, relative to the intensity (channel by channel), what
// the light sends in the directions at least bin k's angle (kFalloffCos) from its axis. Stored as
// q, for the value 2^(-q / 16) (q = 0: 1), rounded so that the stored value is never below the
// bound. A cluster keeps, bin by bin, the largest value (smallest q) of its lights.
constexpr int kFalloffBins = 8;
// cos of the bins' angles: 0, 3, 6, 12, 20, 35, 55 and 80 degrees.
extern const float kFalloffCos[kFalloffBins];
float falloff_value(uint8_t q);
uint8_t quantize_falloff(float t);
// The falloff towards directions at least acos(cos_angle) from the axis: the value of the last
// bin whose angle does not exceed that.
inline float falloff_bound(const uint8_t* q, float cos_angle) {
    int k = 0;
    while (k + 1 < kFalloffBins && kFalloffCos[k + 1] >= cos_angle) ++k;
    return falloff_value(q[k]);
}

// What becomes of light paths at glossy surfaces (vpl.glossy): a VPL that re-emits through the
// whole BSDF, one that keeps only its diffuse part (Bxdf::eval_diffuse; none on a surface with
// no diffuse part), or no VPL. The path carries on through the BSDF in every case.
enum class GlossyVpls : uint8_t { Bsdf, Diffuse, Skip };

struct PointLight {
    Vec3 p;  // position (omni, oriented)
    // Oriented: lobe axis; glossy: mirror direction; directional: unit direction the light
    // travels; spot: axis.
    Vec3 n;
    // On a surface (VPLs, area-light samples): what shadow rays move p by (segment_ray); zero
    // for points on no surface.
    Vec3 offset;
    // Omni: W/sr. Oriented: W/sr along n, an upper bound of the lobe everywhere (for a VPL kept
    // with its BSDF: flux times the largest BSDF value). Glossy: flux times a bound of f |cos|
    // over every direction. Directional: irradiance at normal incidence.
    RGB intensity;
    PointLightKind kind = PointLightKind::Omni;
    // Spot lights: smoothstep falloff from 1 inside cos_start to 0 outside cos_end (about n).
    // Plain omni lights have cos_end = -2 (no cone).
    float cos_start = 1, cos_end = -2;
    // Glossy VPLs: index into PointLightSet::surfaces, whose BSDF the light re-emits through;
    // -1: the cosine lobe (or omni/directional as above).
    int32_t surface = -1;
    bool is_vpl = false;
    // VPLs of the plain light tracer (vpl.sampler=power/uniform): the light path's surface
    // vertices up to this one (1: the first surface hit); 0 for emitters' lights and unknown.
    uint8_t depth = 0;
    // Lambertian VPLs (oriented, no surface): the largest channel of their constant BSDF value
    // f, so that f |cos| towards w is known without the flux (bdlightcuts' weights).
    float diffuse_f = 0;
    uint8_t falloff[kFalloffBins] = {};  // glossy lights (see kFalloffBins); 0: no falloff
    // Omni lights of goniometric and projection lights: the light whose emitted_intensity gives
    // the intensity towards each direction (`intensity` then bounds it over all directions, and
    // the cone, if any, bounds where it is not zero). Null for every other light.
    const Light* emitter = nullptr;
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
    size_t omni = 0, oriented = 0, directional = 0, glossy = 0;  // counts by kind
    size_t vpls = 0;                                             // how many of the lights are VPLs
    size_t light_paths = 0;                                      // light paths traced for the VPLs
    float focus_share = 0, focus_radius = 0;  // the VPLs' emission focus (VplOptions), if any
    double seconds = 0;                       // time to build the set
    // The VPL count asked for (vpl.count) and the one the sampler was given: fewer where a
    // time limit allowed no more (manylight/vpl_budget.h).
    int vpl_count_requested = 0, vpl_count_used = 0;
};

// Intensity of `pl` leaving towards unit direction `w` (from the light; ignored for
// directional lights, which return their irradiance): what reaches a receiver at distance d is
// this / d^2 (directional: this, undivided).
RGB point_light_intensity(const PointLightSet& set, const PointLight& pl, const Vec3& w);

}  // namespace ml
