// Shading with point lights: where a camera path gathers (its first non-delta hit), and what one
// point light gives there. Shared by the brute-force `vpl` integrator and `lightcuts`, so both
// shade with exactly the same arithmetic.
#pragma once

#include <optional>

#include "core/scratch.h"
#include "manylight/point_light.h"
#include "sampling/sampler.h"
#include "scene/scene.h"

namespace ml {

struct GatherPoint {
    SurfaceInteraction si;
    Bsdf bsdf;
    RGB beta;  // throughput of the delta chain that led here (1 for a direct hit)
};

// Follows `ray` through delta surfaces (mirrors, glass) for at most `max_depth` bounces, adding
// the emission it sees to *L (times throughput), and returns the first non-delta hit.
std::optional<GatherPoint> trace_to_gather_point(const Scene& scene, Ray ray, Sampler& sampler,
                                                 ScratchBuffer& scratch, int max_depth, RGB* L);

// What `pl` gives at the gather point without visibility: f(wo, wi) |cos| I / d^2 (directional:
// f |cos| E), and the shadow ray that decides visibility. False when it gives nothing.
bool point_light_contribution(const PointLightSet& set, const PointLight& pl, const GatherPoint& g,
                              RGB* value, Ray* shadow);

}  // namespace ml
