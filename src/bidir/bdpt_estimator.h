// One bidirectional path of a chosen depth, for Metropolis integrators (pbrt-v4's
// MLTIntegrator::L): the primary-sample-space sampler underneath decides everything, and the
// estimator turns its numbers into a path contribution and the film position it lands on.
//
// Randomness, in order (every number comes from the Sampler; a sampler with streams is told
// which stream is next through `start_stream` before the first number of each):
//   1. stream Camera:
//        - the strategy: one get_1d() picking s in [0, depth + 2) uniformly (t = depth + 2 - s);
//          not drawn when depth == 0 (then s = 0, t = 2);
//        - the film position: get_pixel_2d(), scaled to [0, width) x [0, height);
//        - the time: get_1d(); the lens position: get_2d();
//        - each bounce of the camera subpath (t - 2 of them): get_1d() picking the BSDF lobe,
//          then get_2d() placing the direction.
//   2. stream Light (only when s > 0):
//        - get_1d() choosing the light (power-proportional), get_2d() for the position on it,
//          get_2d() for the direction;
//        - each bounce of the light subpath (s - 2 of them): get_1d(), then get_2d(), as above.
//   3. stream Connection:
//        - s == 1: get_1d() choosing the light, get_2d() for the point on it (only when the
//          camera subpath's last vertex can connect: not a delta-only BSDF);
//        - t == 1: get_2d() for the point on the lens (only when the light subpath's last
//          vertex can connect);
//        - otherwise nothing.
// A subpath that ends early (escapes, is absorbed) stops drawing numbers of its stream; the
// contribution is then zero.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "camera/camera.h"
#include "core/color.h"
#include "core/scratch.h"
#include "sampling/sampler.h"
#include "scene/scene.h"

namespace ml {

class LightSampler;

// The sample streams, in the order sample_depth() consumes them.
enum class BdptStream : int { Camera = 0, Light = 1, Connection = 2 };
inline constexpr int kBdptStreamCount = 3;

struct BdptPathSample {
    // The path's contribution: its MIS-weighted (s, t) estimate divided by the probability
    // 1 / (depth + 2) of having chosen (s, t); black when no path was made.
    RGB L;
    // Where it lands on the film, in pixels: (0, 0) is the top-left corner, x in [0, width).
    // For t == 1 this is where the light subpath's end projects, else the sampled position.
    Vec2 p_raster;
};

class BdptEstimator {
public:
    // `light_sampler`: "power" (what pbrt-v4's BDPT and MLT use) or "uniform". The scene and the
    // camera must outlive the estimator.
    BdptEstimator(const Scene& scene, const PerspectiveCamera& camera,
                  const std::string& light_sampler = "power");
    ~BdptEstimator();
    BdptEstimator(const BdptEstimator&) = delete;
    BdptEstimator& operator=(const BdptEstimator&) = delete;

    // A path of exactly `depth` bounces (depth + 1 segments), by the strategy the sampler picks.
    // Thread-safe for distinct samplers and scratch buffers; `scratch` holds the BSDFs until the
    // caller resets it.
    BdptPathSample sample_depth(Sampler& sampler, int depth, ScratchBuffer& scratch,
                                const std::function<void(BdptStream)>& start_stream = {}) const;

private:
    const Scene& m_scene;
    const PerspectiveCamera& m_camera;
    std::unique_ptr<LightSampler> m_light_sampler;
};

}  // namespace ml
