// The integrator interface and the per-pixel driver most integrators share.
#pragma once

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "core/progress.h"
#include "core/scratch.h"
#include "core/world.h"
#include "film/film.h"
#include "film/filter.h"
#include "render/checkpoint.h"
#include "sampling/sampler.h"
#include "scene/scene.h"

namespace ml {

// Under a time limit, the Metropolis integrators' bootstraps stop once this share of it is spent.
inline constexpr double kBootstrapTimeShare = 0.25;

struct RenderContext {
    const Scene& scene;
    const PerspectiveCamera& camera;
    const Filter& filter;
    Film& film;
    const Sampler& sampler;  // prototype: cloned per thread
    int spp = 16;            // samples per pixel (the cap when time_limit > 0)
    double time_limit = 0;   // seconds; > 0 renders progressively until spent
    Progress* progress = nullptr;
    // The render's seed (--seed, else the scene's Sampler "seed"), which the sampler was made
    // with; integrators with random choices of their own (VPLs, representatives) derive theirs
    // from it.
    uint64_t seed = 0;
    // When rendering began: the time limit counts from here, preparation (VPLs, trees) included.
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();

    double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    // Set and true: the render is abandoned (the viewer left the view); loops stop as at the
    // end of a time limit.
    const std::atomic<bool>* cancel = nullptr;

    bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }

    // True once a time limit is spent, or the render cancelled: loops stop starting work then.
    bool out_of_time() const { return cancelled() || (time_limit > 0 && elapsed() >= time_limit); }

    // Set (--checkpoint, --resume): the render saves its state at round boundaries and, when
    // resuming, starts where the checkpoint left off (render/checkpoint.h). Only integrators
    // whose can_checkpoint() is true are given one.
    Checkpoint* checkpoint = nullptr;

    // The processes the render is split over (null: this one alone). Each rank renders the work
    // items it owns (tiles, chains: item % ranks == rank) into its own film; the render job sums
    // the films on rank 0. Integrators keep every rank's calls to the world's collectives in
    // step.
    World* world = nullptr;
    int rank() const { return world ? world->rank() : 0; }
    int ranks() const { return world ? world->size() : 1; }
    bool owns(int64_t item) const { return ranks() == 1 || item % ranks() == rank(); }
    World& world_or_local() const { return world ? *world : local_world(); }
};

struct RenderResult {
    int spp = 0;                        // samples per pixel actually taken
    size_t point_lights = 0, vpls = 0;  // many-light integrators: the point-light set
    // More --stats members, by name: the integrator's figures, e.g. {"lightcuts": {...}}.
    nlohmann::json stats = nlohmann::json::object();
    std::map<std::string, Image> aovs;  // extra images by name (e.g. "cutsize")
    // Images always written beside the output as OUT.NAME.exr (debugging output an integrator
    // was asked for through its settings, e.g. bdpt.strategy_images).
    std::map<std::string, Image> debug_images;
    std::vector<std::string> warnings;  // for the user, e.g. that an error bound did not hold
};

class Integrator {
public:
    virtual ~Integrator() = default;
    virtual std::string name() const = 0;
    virtual RenderResult render(const RenderContext& ctx) = 0;
    // Whether render() honours RenderContext::checkpoint (saves its state and resumes).
    virtual bool can_checkpoint() const { return false; }
};

// The camera ray of one pixel sample, made as every pixel-sampling integrator makes it: a filter
// sample, the time and the lens position, drawn from the sampler in that order (after
// start_pixel_sample). Counts the camera ray; *filter_weight receives the filter's weight (the
// film's weight of the sample) and *camera_weight the ray's (PerspectiveCamera::generate_ray:
// the radiance along the ray is multiplied by it; 0 when the realistic camera's lens stops the
// ray). Callers that pass no camera_weight must not meet a camera with ray weights.
Ray pixel_sample_ray(const RenderContext& ctx, Point2i pixel, Sampler& sampler,
                     float* filter_weight, float* camera_weight = nullptr);

// Integrators that estimate radiance along camera rays, one pixel sample at a time, in the render
// loop's rounds (render_loop.h: render_pixels): each pixel's samples are taken in index order by
// one thread, so the image is the same for any thread count and schedule.
class PixelIntegrator : public Integrator {
public:
    RenderResult render(const RenderContext& ctx) override;
    // The samples of a pixel depend on (pixel, sample index) alone, and a block's state on the
    // seed and the block: a resumed render takes the samples it has not, as the first would.
    bool can_checkpoint() const override { return true; }
    // Called once before rendering (after the scene is ready).
    virtual void prepare(const Scene& scene) {}
    // Called after prepare(), before the first sample (a pilot pass may run here).
    virtual void before_pixels(const RenderContext& ctx) {}
    // Radiance arriving along `ray`.
    virtual RGB li(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
                   Point2i pixel) const = 0;
    // With blocks of samples (> 0; 0, the default: none), the samples run in blocks of this
    // many per pixel, and begin_block(b) runs before block b once block b - 1 has ended on every
    // pixel (render_pixel_blocks): for state the integrator draws anew per block (VPL sets).
    virtual int64_t block_samples() const { return 0; }
    virtual void begin_block(const RenderContext& ctx, int64_t block) {}
};

}  // namespace ml
