// A whole render: scene description in, image and figures out. The command line and the render
// tests both go through here, so what the tests check is what users run.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/world.h"
#include "film/image.h"
#include "integrators/bias_check.h"
#include "scene/scene_desc.h"

namespace ml {
class Scene;
}

namespace ml {

struct RenderOptions {
    std::string integrator;            // empty: the scene's (mapped), else "path"
    std::optional<int> spp;            // overrides the Sampler's "pixelsamples"
    std::optional<int> max_depth;      // overrides the integrator's "maxdepth"
    std::optional<int> width, height;  // override the Film's resolution
    // Renders the whole image even when the Film has a "cropwindow" or "pixelbounds" (the
    // viewer shows the whole view).
    bool whole_image = false;
    std::optional<uint64_t> seed;            // overrides the Sampler's "seed" (default 0)
    std::string sampler;                     // empty: the scene's
    int threads = 0;                         // 0: all cores
    double time_limit = 0;                   // seconds; > 0 renders progressively until spent
    std::map<std::string, std::string> set;  // --set NAME.KEY=VALUE
    bool progress = false;                   // draw a progress bar on a terminal
    // Given the fraction of the render done, from the render's threads (cheap and thread-safe;
    // the Python module's progress callback and Ctrl-C poll start here).
    std::function<void(double)> on_progress;
    // --look-at: eye, target and up (as the scene's LookAt) instead of the scene's camera.
    std::optional<std::array<float, 9>> look_at;
    // When set and true, the render stops starting work (the viewer drops a view it left).
    const std::atomic<bool>* cancel = nullptr;
    // The processes to split the render over (MPI ranks; null: this one). Every rank calls
    // render_scene with the same scene and options; rank 0's output holds the image and the
    // figures, the other ranks' are partial and not to be written. Only rank 0 draws progress.
    World* world = nullptr;
    // The bias check (integrators/bias_check.h): off unless asked for here; the command line
    // asks for Auto (on for the many-light integrators). Under a time limit the main render gets
    // (1 - share) of it and the check the rest; without one it runs after the render and leaves
    // the image as it is. Only rank 0 runs it (it holds the image).
    BiasCheckOptions bias_check;
    // --checkpoint: save the render's state to this file every checkpoint_every seconds and at
    // the end (or a stop); --resume: continue the render saved in this file (render/checkpoint.h).
    // Both may name the same file. Only integrators that can (Integrator::can_checkpoint).
    std::string checkpoint, resume;
    double checkpoint_every = 60;
    // What the scene is, for the checkpoint's fingerprint: load_scene's hash of the scene file
    // (render_loaded_scene sets it); a checkpoint of another scene is refused.
    std::string scene_id;
};

struct RenderFigures {
    std::string integrator, sampler;
    int spp = 0, width = 0, height = 0, threads = 0;
    double seconds_load = 0, seconds_build = 0, seconds_render = 0;
    uint64_t rays_camera = 0, rays_closest = 0, rays_shadow = 0;
    size_t triangles = 0, lights = 0, point_lights = 0, vpls = 0;
    // Integrator-specific members of the --stats object, by name (RenderResult::stats).
    nlohmann::json integrator_stats = nlohmann::json::object();
    std::string output_hint;         // the Film's "filename", if any
    double peak_rss_mb = 0;          // peak resident memory of the process, filled in by the caller
    uint64_t nonfinite_samples = 0;  // samples the film dropped: a NaN or infinite channel
    size_t pixels_without_samples = 0;  // pixels the time limit left without a camera sample
    std::vector<std::string> warnings;  // for the user: settings that were not honoured
    // Across MPI ranks (more than 1): each rank's render time, rank 0's time summing the films,
    // and the bytes this rank gave to reductions and broadcasts (the "mpi" member of --stats).
    int ranks = 1;
    std::vector<double> seconds_render_per_rank;
    double seconds_reduce = 0;
    uint64_t bytes_reduced = 0, bytes_broadcast = 0;
    // Checkpoints: saves written, and the units (samples per pixel, mutations) a resumed render
    // started from (-1: not resumed).
    int checkpoint_saves = 0;
    int64_t resumed_from = -1;
    // The bias check's figures, when it ran (its seconds are not in seconds_render; "total" in
    // --stats counts them).
    std::optional<BiasCheckResult> bias_check;
    // The --stats object.
    nlohmann::json to_json() const;
};

struct RenderOutput {
    Image image;
    std::map<std::string, Image> aovs;  // extra images the integrator made, by name
    // Images to write beside the output whatever --aov says (RenderResult::debug_images).
    std::map<std::string, Image> debug_images;
    RenderFigures figures;
};

// A scene as the command line reads it: the file at `path` parsed, or the built-in Cornell box
// when `path` is empty, and the seconds that took. Throws InputError with the place.
struct LoadedScene {
    SceneDesc desc;
    double seconds_load = 0;
    std::string id;  // a hash of the scene file's text (RenderOptions::scene_id)
};
LoadedScene load_scene(const std::string& path);

// What `manylight render` and the Python module's render() run: render_scene on a loaded scene,
// with the load time and the process's peak memory (peak_rss_mb) filled in.
RenderOutput render_loaded_scene(LoadedScene scene, const RenderOptions& options);

// Renders a parsed scene. Throws InputError for bad scene settings and UsageError for bad
// options. `seconds_load` is left for the caller to fill in.
RenderOutput render_scene(SceneDesc desc, const RenderOptions& options);

// The same on a scene already built (the viewer renders many views of one scene): the film,
// sampler, camera and integrator are made from scene.desc() and `options` as render_scene makes
// them, so the image is the one `render` gives with the same options. seconds_build stays 0.
RenderOutput render_built_scene(const Scene& scene, const RenderOptions& options);

}  // namespace ml
