// Every light of a scene as point lights, plus virtual point lights from light paths (instant
// radiosity): the light set the VPL and Lightcuts integrators shade with.
#pragma once

#include <cstdint>

#include "core/math.h"
#include "lights/point_lights.h"
#include "manylight/vpl_budget.h"
#include "manylight/vpl_generator.h"
#include "sampling/warps.h"  // shifted_hammersley, which lived here

namespace ml {

class Scene;
class PerspectiveCamera;

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
    VplSamplerOptions vpl_sampler;  // vpl.sampler and its settings (manylight/vpl_sampler.h)
    // vpl.focus: the share of the distant and infinite lights' paths started towards what the
    // camera sees (VplOptions::focus_share; standard and power samplers, with a camera).
    float vpl_focus = 0;
    // The render's camera, which every sampler but `standard` needs (set before building).
    const PerspectiveCamera* camera = nullptr;
    // Under a time limit, what the VPL build may take (manylight/vpl_budget.h); none by default.
    VplBudget vpl_budget;
    VplRegion vpl_region;  // VplOptions::region
};

// Whether a light of the scene starts its light paths on a disk over the whole scene (distant
// and infinite lights, Light::emission_sphere): the lights vpl.focus aims.
bool has_disk_light(const Scene& scene);

// Emitters' point lights first (in scene light order), then the VPLs (in light-path order).
// Deterministic for a seed, whatever the number of threads.
PointLightSet build_point_light_set(const Scene& scene, const PointLightOptions& options);

}  // namespace ml
