// Every light of a scene as point lights, plus virtual point lights from light paths (instant
// radiosity): the light set the VPL and Lightcuts integrators shade with.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/math.h"
#include "manylight/point_light.h"

namespace ml {

class Scene;

struct PointLightOptions {
    int area_count = 1024;  // oriented lights shared over the area lights in proportion to power
    int env_count = 1024;   // directional lights for each infinite light
    int vpl_count = 10000;  // target number of VPLs (at least this many are made)
    int vpl_max_depth = 5;  // most VPLs along one light path (vpl.max_depth: maxdepth - 1)
    GlossyVpls vpl_glossy = GlossyVpls::Bsdf;  // VPLs on glossy surfaces (point_light.h)
    bool emitters = true;                      // include the emitters' point lights
    // Leave out the area and infinite lights (lights.direct=sample: they are sampled instead).
    bool sampled_direct = false;
    bool vpls = true;  // include VPLs
    uint64_t seed = 0;
};

// Emitters' point lights first (in scene light order), then the VPLs (in light-path order).
// Deterministic for a seed, whatever the number of threads.
PointLightSet build_point_light_set(const Scene& scene, const PointLightOptions& options);

// Point i of n of a Hammersley set, shifted (mod 1) by `shift`: n stratified points in the unit
// square, each one uniformly distributed when the shift is uniform (so estimates stay unbiased).
inline Vec2 shifted_hammersley(uint32_t i, uint32_t n, const Vec2& shift) {
    uint32_t r = i;
    r = (r << 16) | (r >> 16);
    r = ((r & 0x00ff00ffu) << 8) | ((r & 0xff00ff00u) >> 8);
    r = ((r & 0x0f0f0f0fu) << 4) | ((r & 0xf0f0f0f0u) >> 4);
    r = ((r & 0x33333333u) << 2) | ((r & 0xccccccccu) >> 2);
    r = ((r & 0x55555555u) << 1) | ((r & 0xaaaaaaaau) >> 1);
    float x = (float(i) + 0.5f) / float(n) + shift.x;
    float y = float(r) * 0x1p-32f + shift.y;
    x -= std::floor(x);
    y -= std::floor(y);
    return {std::min(x, kOneMinusEpsilon), std::min(y, kOneMinusEpsilon)};
}

}  // namespace ml
