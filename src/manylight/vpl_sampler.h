// VPL samplers: where a render's virtual point lights come from (vpl.sampler). One entry point
// for every VPL consumer (vpl, lightcuts, mdlightcuts, and the interactive gatherer):
// sample_vpls(scene, camera, options, set) appends the VPLs, and `options` holds the count, the
// seed and the sampler's settings (vpl_generator.h: VplOptions, VplSamplerOptions).
//   - standard: instant radiosity (Keller 1997), a VPL at each bounce of light paths.
//   - power: Wald, Benthin and Slusallek 2003: a pilot pass of VPLs and camera points estimates
//     how much each light gives the image; light paths then start at the lights in proportion to
//     that (with a share by power, so that no light is left out).
//   - bidirectional: Segovia et al. 2006: VPL positions from camera sub-paths one bounce in,
//     connected back to the lights (a point on a light, or a vertex of a light path), then
//     resampled so that each kept VPL carries the same flux.
// Every sampler is deterministic for options.seed at any thread count.
#pragma once

#include <string>

#include "manylight/gather.h"
#include "manylight/vpl_generator.h"

namespace ml {

class PerspectiveCamera;

// "standard", "power", "bidirectional", "metropolis"; UsageError for other names.
VplSamplerKind parse_vpl_sampler(const std::string& name);
const char* vpl_sampler_name(VplSamplerKind kind);

// Appends the VPLs of options.sampler.kind to set (as generate_vpls does). The samplers other
// than standard need the camera (where it looks); without one (nullptr) they throw UsageError.
void sample_vpls(const Scene& scene, const PerspectiveCamera* camera, const VplOptions& options,
                 PointLightSet& set);

// The samplers behind sample_vpls.
void sample_power_vpls(const Scene& scene, const PerspectiveCamera& camera,
                       const VplOptions& options, PointLightSet& set);
// power: each light's probability of starting a light path (scene light order).
std::vector<float> power_light_pmf(const Scene& scene, const PerspectiveCamera& camera,
                                   const VplOptions& options);
void sample_bidirectional_vpls(const Scene& scene, const PerspectiveCamera& camera,
                               const VplOptions& options, PointLightSet& set);

// metropolis: the chains' record, for tests and measurements: per step, the current state's VPL
// position and f (chain after chain); P_c, the power the kept geometric VPLs were given (sum of
// P_i), their count; per mutation (large, camera, light) the steps that proposed it and those
// accepted; each geometric VPL's multiplicity (the run of steps that kept its light side); the
// bootstrap paths with f > 0 and the distinct ones the chains start from.
struct MirTrace {
    std::vector<Vec3> positions;
    std::vector<float> contributions;
    double Pc = 0, kept_power = 0;
    size_t geometric = 0, steps = 0;
    size_t proposed[3] = {}, accepted[3] = {};
    std::vector<double> runs;
    size_t bootstrap_nonzero = 0, distinct_starts = 0;
};
void sample_metropolis_vpls(const Scene& scene, const PerspectiveCamera& camera,
                            const VplOptions& options, PointLightSet& set,
                            MirTrace* trace = nullptr);

// Points the camera sees (the first non-delta hit of camera rays through film positions
// stratified over the image, along delta chains as the gatherers follow them), for the pilot
// passes. Their BSDFs live in `arena`.
struct PilotPoints {
    std::vector<GatherPoint> points;
    std::unique_ptr<ScratchBuffer> arena;
};
PilotPoints camera_pilot_points(const Scene& scene, const PerspectiveCamera& camera, int count,
                                int max_depth, uint64_t seed);

// The emission focus (VplOptions::focus_center, focus_radius): the bounding sphere of the middle
// 90% of the points the camera sees along each axis (`count` pilot points), its box grown by a
// tenth on every side; false where the camera sees too little (fewer than 16 points).
bool camera_focus_sphere(const Scene& scene, const PerspectiveCamera& camera, int count,
                         uint64_t seed, Vec3* center, float* radius);

}  // namespace ml
