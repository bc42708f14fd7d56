// The unidirectional path tracer's vertex loop: at each vertex, next-event estimation with one
// light chosen by a LightSampler (or every light, PathTraceOptions::all_lights), then a BSDF sample
// whose ray finds emission weighted by MIS against those light samples (power heuristic), and
// Russian roulette. `path` traces whole paths with it; an estimator that covers the short paths
// itself continues its own eye path with it (bdlightcuts' remainder), the one copy of next-event
// estimation and MIS along a path.
#pragma once

#include "core/scratch.h"
#include "lights/light_sampler.h"
#include "materials/bsdf.h"
#include "sampling/sampler.h"
#include "scene/scene.h"
#include "transport/sd_tree.h"

namespace ml {

struct PathTraceOptions {
    int max_depth = 5;  // scattering vertices of the longest path counted
    int rr_depth = 1;   // Russian roulette after the BSDF samples of vertices from this depth on
    // Next-event estimation samples every light of the scene once at each vertex (pmf 1 each,
    // pbrt-v3's "all" strategy) instead of one light chosen by the LightSampler: no variance of
    // the light choice, at one shadow ray per light (`path.lightsampler=all`).
    bool all_lights = false;
    // Path guiding: at a vertex without delta or near-specular lobes whose region of `guide` has
    // learned a distribution, the next direction comes from the BSDF with probability
    // guide_bsdf_share,
    // else from the guide (one-sample MIS: the mixture's density is the direction's pdf, for the
    // throughput and for MIS with light samples). With guide_record, every vertex without delta
    // lobes records the radiance its path brought back along its direction into the guide.
    const SDTree* guide = nullptr;
    bool guide_record = false;
    float guide_bsdf_share = 0.5f;
    // In participating media (transport/volume_path.h): single scattering towards point lights
    // also sampled by distance equiangularly, weighed by MIS against delta tracking.
    bool equiangular = true;
};

// A weight of the continued paths that depends on the direction in which they leave their first
// vertex: it multiplies that vertex's light samples and, through its BSDF sample, the rest of
// the path. bdlightcuts' remainder is one (it needs the lobe there towards the next vertex).
class FirstBounceWeight {
public:
    virtual ~FirstBounceWeight() = default;
    // The weight of the paths leaving the first vertex, with BSDF `bsdf`, along wi (towards
    // the light sample or the BSDF sample; `specular`: a delta lobe's sample), wo the way back.
    // `f`: bsdf.eval(wo, wi) where the caller has it, else null.
    virtual float weight(const Bsdf& bsdf, const Vec3& wo, const Vec3& wi, bool specular,
                         const RGB* f) const = 0;
    // True where the weight is 0 for every wi: the path is not continued at all.
    virtual bool vanishes(const Bsdf& bsdf, const Vec3& wo) const = 0;
    // False where the light that participating media emit past the first vertex counts whole,
    // unweighted (no other estimator of the caller's finds it): the path then goes on for that
    // light alone where the weight is 0.
    virtual bool weighs_media_emission() const { return true; }
    // False where the paths leave the first vertex by its non-delta lobes only (the caller
    // follows its delta lobes itself): a delta sample there ends the path.
    virtual bool takes_delta_lobes() const { return true; }
};

// The radiance that paths continued past `si` bring back along si.wo, times the throughput
// `beta` with which the caller reached si after `depth` scattering vertices: si's own emission
// is the caller's (counted or not), and every longer path up to max_depth scattering vertices
// counts, light samples and BSDF samples weighted by MIS. `first`, if given, weighs the paths
// by the direction they leave si in.
RGB continue_path(const Scene& scene, SurfaceInteraction si, int depth, RGB beta, Sampler& sampler,
                  ScratchBuffer& scratch, const LightSampler& light_sampler,
                  const PathTraceOptions& options, const FirstBounceWeight* first = nullptr);

}  // namespace ml
