// The VPL build under a time limit. A sampler's cost grows with its VPL count (light paths,
// candidates, chain steps); bidirectional builds the kitchen's 100k VPLs in about 13 s, which
// a 10 s --time-limit cannot take. Under a limit the build times small builds of the same
// sampler (probes, then dropped), fits their cost, and builds as many VPLs as fit its share of
// the time. Every sampler is unbiased (metropolis: consistent) at any count, so the smaller set
// estimates the same image with more noise. Without a limit nothing changes: sample_vpls with
// the requested count, deterministic for a seed at any thread count.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <string>

#include "manylight/vpl_generator.h"

namespace ml {

class PerspectiveCamera;
class World;
struct RenderContext;

// Under a time limit, the VPL build (its probes included) takes at most this share of it: the
// render needs the rest for the light tree, the cut-cap probe and at least one whole pass over
// the film (the Metropolis integrators give their bootstraps the same share).
inline constexpr double kVplBuildTimeShare = 0.25;
// The first probe's count; each further probe doubles it, up to a quarter of the count asked.
inline constexpr int kVplFirstProbe = 1024;
// Probing stops once a probe took this share of the build's time: enough to time it, and the
// probes (each twice the last) then take at most about twice that.
inline constexpr double kVplProbeShare = 0.08;

struct VplBudget {
    double seconds = 0;      // > 0: wall seconds the build may take; 0: no limit
    World* world = nullptr;  // the ranks that build the same set (null: this process alone)
    // Set: what the caller builds over the set next and that grows with it (the light tree),
    // run on each probe's set and timed with it, so that the count fits with it.
    std::function<void(const PointLightSet&)> also_timed;
};

// kVplBuildTimeShare of ctx's time limit, less what the render has spent (no limit without one;
// also_timed unset).
VplBudget vpl_build_budget(const RenderContext& ctx);

// One timed build: `count` VPLs asked for, `seconds` of wall time.
struct VplProbe {
    int count = 0;
    double seconds = 0;
};

// The VPL count that a build is predicted to make in `seconds`, at most `requested`: the cost
// taken as fixed + per_vpl * count, fitted through the two probes (smaller.count 0: through
// `larger` alone, no fixed part; where the fit has no positive slope, larger's mean cost). At
// least min(requested, kVplFirstProbe): a set that small still lights the image.
int fit_vpl_count(int requested, const VplProbe& smaller, const VplProbe& larger, double seconds);

// sample_vpls within `budget` (VplOptions::count reduced where it does not fit, agreed across
// budget.world's ranks, who must all call this); returns the count the sampler was given.
int sample_vpls_within(const Scene& scene, const PerspectiveCamera* camera,
                       const VplOptions& options, const VplBudget& budget, PointLightSet& set);

// For the render result: that the time limit reduced the VPL count, from what to what (empty
// when it did not), naming the integrator's count setting; and the --stats figures
// (vpl_count_requested, vpl_count_used).
std::string vpl_budget_warning(const PointLightSet& set, const char* setting = "vpl.count");
nlohmann::json vpl_budget_json(const PointLightSet& set);

}  // namespace ml
