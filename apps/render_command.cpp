#include <fmt/format.h>
#include <fmt/ranges.h>

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "commands.h"
#include "integrators/registry.h"
#include "integrators/render_job.h"
#include "options.h"
#include "render/settings.h"
#include "scene/scene_desc.h"

namespace ml {

void add_render_command(CLI::App& app, RenderArgs& a) {
    const std::vector<std::string> integrators = integrator_names();
    CLI::App* r = app.add_subcommand("render", "render a pbrt-v4 scene (default: the Cornell box)");
    r->add_option("scene", a.scene, "scene file (.pbrt); none: the built-in Cornell box");
    r->add_option("-o,--output", a.output, "output image: .exr, .png or .pfm")
        ->check(output_image());
    r->add_option("--integrator", a.integrator,
                  "one of: " + fmt::format("{}", fmt::join(integrators, ", ")) + " (" +
                      kManyLightAlias + ": " + kRecommendedManyLight + ")")
        ->check(one_of(integrators, "integrator"));
    r->add_option("--spp", a.spp, "samples per pixel")->check(positive_integer());
    r->add_option("--max-depth", a.max_depth, "maximum path depth")->check(non_negative_integer());
    r->add_option("--resolution", a.resolution, "image size WxH")->check(image_size());
    r->add_option("--threads", a.threads, "threads (default: all cores)")
        ->check(positive_integer());
    r->add_option("--seed", a.seed, "random seed")->check(seed_value());
    r->add_option("--sampler", a.sampler, "independent, stratified or sobol")
        ->check(one_of({"independent", "stratified", "sobol"}, "sampler"));
    r->add_option("--time-limit", a.time_limit, "render progressively for this many seconds")
        ->check(positive_seconds());
    // One value per flag, so that `--set a.b=1 scene.pbrt` leaves the scene positional.
    r->add_option("--set", a.set,
                  "integrator setting NAME.KEY=VALUE (repeatable; `manylight integrators` lists "
                  "them with their defaults)")
        ->allow_extra_args(false)
        ->check(setting());
    r->add_option("--stats", a.stats, "write figures as JSON to this file")
        ->check(file_in_existing_folder());
    r->add_option("--aov", a.aovs,
                  "also write an extra image the integrator makes (lightcuts: cutsize) to "
                  "OUT.NAME.exr (repeatable)")
        ->allow_extra_args(false);
    r->add_option("--look-at", a.look_at,
                  "the camera at EX EY EZ looking at TX TY TZ with up UX UY UZ (as the scene's "
                  "LookAt; `manylight view` prints it)")
        ->expected(9)
        ->allow_extra_args(false);
    r->add_option("--bias-check", a.bias_check,
                  "path trace a few random pixels too and say whether the image's mean is off "
                  "by more than 1%: auto (on for the many-light integrators), on or off")
        ->check(one_of({"auto", "on", "off"}, "bias check mode"));
    r->add_option("--bias-check-share", a.bias_check_share,
                  "the share of the time the bias check may take (default 0.1)")
        ->check(share_of_time());
    r->add_option("--bias-check-pixels", a.bias_check_pixels,
                  "pixels the bias check path traces (default 256)")
        ->check(positive_integer());
    r->add_option("--bias-check-spp", a.bias_check_spp,
                  "path samples per bias-check pixel (default: from the share; a cap under "
                  "--time-limit)")
        ->check(positive_integer());
    r->add_option("--checkpoint", a.checkpoint,
                  "save the render's state to this file every --checkpoint-every seconds and at "
                  "the end (or on Ctrl-C), to continue it with --resume")
        ->check(file_in_existing_folder());
    r->add_option("--checkpoint-every", a.checkpoint_every,
                  "seconds between checkpoints (default 60; 0: after every pass)")
        ->check(non_negative_seconds());
    r->add_option("--resume", a.resume,
                  "continue the render saved in this checkpoint (same scene, integrator, "
                  "settings, resolution, seed and spp); may be the --checkpoint file too")
        ->check(CLI::ExistingFile);
    r->add_flag("-q,--quiet", a.quiet, "no progress bar or summary");
}

namespace {

void parse_resolution(const std::string& s, RenderOptions& o) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || w <= 0 || h <= 0)
        throw UsageError("--resolution: expected WIDTHxHEIGHT, got \"" + s + "\"");
    o.width = w;
    o.height = h;
}

std::string f_name(const RenderOutput& out) { return out.figures.integrator; }

// Ctrl-C and SIGTERM: the first stops the render at the next tile (the render loops watch this
// flag, as they watch the viewer's), the second ends the process at once. The handler only
// touches a lock-free atomic and calls _exit: both are async-signal-safe.
std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free);

void on_stop_signal(int) {
    if (g_stop.exchange(true)) ::_exit(kInterruptedExit);
}

void catch_stop_signals() {
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    action.sa_flags = SA_RESTART;  // a write under way (the image, a checkpoint) goes on
    sigemptyset(&action.sa_mask);
    ::sigaction(SIGINT, &action, nullptr);
    ::sigaction(SIGTERM, &action, nullptr);
}

}  // namespace

int run_render(const RenderArgs& a, World& world) {
    catch_stop_signals();  // from the start: a stop while the scene loads renders nothing
    RenderOptions o;
    o.world = &world;
    o.integrator = a.integrator;
    if (a.spp > 0) o.spp = a.spp;
    if (a.max_depth >= 0) o.max_depth = a.max_depth;
    if (!a.resolution.empty()) parse_resolution(a.resolution, o);
    if (a.seed >= 0) o.seed = uint64_t(a.seed);
    if (!a.sampler.empty()) o.sampler = a.sampler;
    o.threads = a.threads;
    o.time_limit = a.time_limit;
    o.progress = !a.quiet;
    o.checkpoint = a.checkpoint;
    o.checkpoint_every = a.checkpoint_every;
    o.resume = a.resume;
    o.cancel = &g_stop;
    o.bias_check.mode = parse_bias_check_mode(a.bias_check);
    o.bias_check.share = a.bias_check_share;
    o.bias_check.pixels = a.bias_check_pixels;
    if (a.bias_check_spp > 0) o.bias_check.spp = a.bias_check_spp;
    if (!a.look_at.empty()) {
        std::array<float, 9> v;
        std::copy(a.look_at.begin(), a.look_at.end(), v.begin());
        o.look_at = v;
    }
    for (const std::string& kv : a.set) {  // checked by setting(): NAME.KEY=VALUE
        size_t eq = kv.find('=');
        o.set[kv.substr(0, eq)] = kv.substr(eq + 1);
    }

    LoadedScene scene = load_scene(a.scene);

    // Where the image goes: -o, else the scene's Film filename, else manylight.png.
    const ParameterList& film = scene.desc.film.params;
    std::string film_name = film.has("filename") ? film.get_string("filename", "") : std::string();
    std::string output = a.output;
    if (output.empty()) output = a.scene.empty() || film_name.empty() ? "manylight.png" : film_name;
    std::string ext = std::filesystem::path(output).extension().string();
    for (char& c : ext) c = char(std::tolower(c));
    if (ext != ".exr" && ext != ".png" && ext != ".pfm")
        throw UsageError("output " + output + ": use .exr, .png or .pfm");

    RenderOutput out = render_loaded_scene(std::move(scene), o);
    const bool stopped = g_stop.load();
    // Across ranks only rank 0 holds the whole image and figures; the others write nothing.
    if (!world.root()) return stopped ? kInterruptedExit : 0;
    // Extra images next to the output, checked before anything is written.
    std::vector<std::pair<std::string, const Image*>> aov_files;
    for (const std::string& name : a.aovs) {
        auto it = out.aovs.find(name);
        if (it == out.aovs.end())
            throw UsageError("--aov " + name + ": integrator \"" + f_name(out) +
                             "\" makes no such image");
        std::filesystem::path p(output);
        aov_files.emplace_back((p.parent_path() / p.stem()).string() + "." + name + ".exr",
                               &it->second);
    }
    for (const auto& [name, img] : out.debug_images) {
        std::filesystem::path p(output);
        aov_files.emplace_back((p.parent_path() / p.stem()).string() + "." + name + ".exr", &img);
    }
    write_image(output, out.image);
    for (auto& [file, img] : aov_files) write_image(file, *img);

    const RenderFigures& f = out.figures;
    if (!a.quiet)
        for (const std::string& w : f.warnings)
            std::fprintf(stderr, "%swarning: %s\n", kMessagePrefix, w.c_str());
    if (!a.stats.empty()) {
        std::string tmp = a.stats + ".tmp";
        {
            std::ofstream js(tmp);
            js << f.to_json().dump(1) << "\n";
            if (!js) throw Error("cannot write " + a.stats);
        }
        std::filesystem::rename(tmp, a.stats);
    }
    if (!a.quiet) {
        uint64_t rays = f.rays_closest + f.rays_shadow;
        std::printf(
            "manylight: %s %dx%d %d spp %s in %.2f s (load %.2f s, build %.2f s, render %.2f s), "
            "%.1f M rays/s -> %s\n",
            a.scene.empty() ? "<cornell-box>" : a.scene.c_str(), f.width, f.height, f.spp,
            f.integrator.c_str(), f.seconds_load + f.seconds_build + f.seconds_render,
            f.seconds_load, f.seconds_build, f.seconds_render,
            f.seconds_render > 0 ? rays / f.seconds_render * 1e-6 : 0.0, output.c_str());
        if (f.bias_check) std::printf("%s%s\n", kMessagePrefix, f.bias_check->summary().c_str());
    }
    if (stopped) {
        // Always said, --quiet or not: the image is not the one asked for.
        std::fflush(stdout);
        std::string message = fmt::format(
            "{}interrupted: wrote the image so far to {} ({} samples per pixel done in full; "
            "each pixel is the mean of the samples it got)",
            kMessagePrefix, output, f.spp);
        if (!a.checkpoint.empty())
            message += "; the render's state is in " + a.checkpoint + ": continue with --resume " +
                       a.checkpoint;
        std::fprintf(stderr, "%s\n", message.c_str());
        return kInterruptedExit;
    }
    return 0;
}

}  // namespace ml
