// What a primary-sample-space Markov chain explores: a function from the sampler's numbers to a
// path contribution and the film position it lands on, split into depth strata (a chain stays
// in one stratum, as in pbrt-v4's MLT, so the number of dimensions a path uses is stable).
#pragma once

#include <memory>
#include <string>

#include "camera/camera.h"
#include "core/color.h"
#include "core/scratch.h"
#include "sampling/mlt_sampler.h"
#include "scene/scene.h"

namespace ml {

struct PrimaryPathSample {
    RGB L;          // contribution (the pixel estimate's numerator); black: no path
    Vec2 p_raster;  // pixels, (0, 0) the top-left corner
};

class PrimaryEstimator {
public:
    virtual ~PrimaryEstimator() = default;
    // Strata 0 .. depth_count() - 1; their contributions sum to the pixel's value.
    virtual int depth_count() const = 0;
    // Streams the estimator reads (the MltSampler must be made with this many).
    virtual int stream_count() const = 0;
    // One path of stratum `depth` from the sampler's current numbers. Thread-safe for distinct
    // samplers and scratch buffers.
    virtual PrimaryPathSample sample(MltSampler& sampler, int depth,
                                     ScratchBuffer& scratch) const = 0;
};

// "bdpt": BDPT's paths of exactly `depth` bounces, one (s, t) strategy each (Kelemen et al.'s
// bidirectional estimator, pbrt-v4's MLTIntegrator::L), strata 0 .. max_depth.
// "path": the path tracer (NEE + MIS, Russian roulette) from a raster position, every depth up
// to max_depth in one stratum; a unidirectional cross-check of the chain machinery.
// Throws UsageError for another name. Scene and camera must outlive the estimator.
std::unique_ptr<PrimaryEstimator> make_primary_estimator(const std::string& name,
                                                         const Scene& scene,
                                                         const PerspectiveCamera& camera,
                                                         int max_depth);

}  // namespace ml
