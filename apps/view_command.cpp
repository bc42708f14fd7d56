// `manylight view scene.pbrt`: look around a scene in the browser before rendering it.
#include <fmt/format.h>

#include <sys/resource.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "commands.h"
#include "core/parallel.h"
#include "options.h"
#include "scene/scene.h"
#include "view_renderer.h"
#include "view_server.h"

namespace ml {

namespace {

// The viewer's default size: the scene's film, halved until it is at most 640 pixels wide.
constexpr int kDefaultViewWidth = 640;

// The viewer's eye turned by `degrees` about the vertical (up) axis through its target.
std::array<float, 9> orbit(const std::array<float, 9>& v, float degrees) {
    Vec3 eye(v[0], v[1], v[2]), target(v[3], v[4], v[5]), up = normalize(Vec3(v[6], v[7], v[8]));
    Vec3 d = eye - target;
    Vec3 along = up * dot(d, up), across = d - along, side = cross(up, across);
    float a = degrees * kPi / 180.f;
    Vec3 e = target + along + across * std::cos(a) + side * std::sin(a);
    return {e.x, e.y, e.z, v[3], v[4], v[5], v[6], v[7], v[8]};
}

// --bench-frames: the time from a camera move to the frame message the clients get (render
// and tone mapping), for views 2 degrees apart, alternating the preview (the first frame after
// a move) and the full resolution (after the view stops), so that a shared machine's load
// falls on both alike.
void bench_moving_frames(const ViewRenderer& renderer, int frames) {
    const ViewSettings s = renderer.settings();
    nlohmann::json preview_ms = nlohmann::json::array(), full_ms = nlohmann::json::array();
    nlohmann::json preview_cpu = nlohmann::json::array(), full_cpu = nlohmann::json::array();
    // The process's CPU seconds (user and system, all threads): on a shared machine the wall
    // time counts the others' work too; on a quiet one, wall = CPU / threads at best.
    auto cpu_seconds = [] {
        struct rusage u {};
        getrusage(RUSAGE_SELF, &u);
        return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
               1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
    };
    for (int i = 0; i < frames; ++i) {
        std::array<float, 9> view = orbit(renderer.home(), 2.f * float(i + 1));
        for (int divider : {s.preview, 1}) {
            auto t0 = std::chrono::steady_clock::now();
            double c0 = cpu_seconds();
            auto frame = renderer.moving_frame(view, s, divider);
            renderer.frame_message(frame.image, nlohmann::json::object(), s.exposure);
            double ms =
                1000 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            (divider == 1 ? full_ms : preview_ms).push_back(ms);
            (divider == 1 ? full_cpu : preview_cpu).push_back(cpu_seconds() - c0);
            if (s.preview == 1) break;
        }
    }
    nlohmann::json out = {{"frames", frames},
                          {"preview", s.preview},
                          {"vpls", s.vpls},
                          {"interleave", s.interleave},
                          {"filter", s.filter},
                          // With --preview 1 every frame is a full one (the loop above
                          // fills the full lists only).
                          {"preview_ms", s.preview == 1 ? full_ms : preview_ms},
                          {"full_ms", full_ms},
                          {"preview_cpu_s", s.preview == 1 ? full_cpu : preview_cpu},
                          {"full_cpu_s", full_cpu}};
    std::printf("%s\n", out.dump().c_str());
}

}  // namespace

void add_view_command(CLI::App& app, ViewArgs& a) {
    CLI::App* v = app.add_subcommand(
        "view", "look around a scene in the browser: igi frames while moving, then refined");
    v->add_option("scene", a.scene, "scene file (.pbrt)")->required();
    v->add_option("--bind", a.bind, "address to listen on (default 127.0.0.1: this machine only)");
    v->add_option("--port", a.port, "port (default 8080; 0: any free port)")
        ->check(CLI::Range(0, 65535));
    v->add_option("--resolution", a.resolution,
                  "view size WxH (default: the scene's, halved to at most 640 wide)")
        ->check(image_size());
    v->add_option("--integrator", a.integrator,
                  "the integrator the view refines with at rest: path, lightcuts or mdlightcuts")
        ->check(one_of(view_refine_integrators(), "integrator"));
    v->add_option("--spp", a.spp, "samples per pixel the refinement stops at (default 64)")
        ->check(positive_integer());
    v->add_option("--threads", a.threads, "threads (default: all cores)")
        ->check(positive_integer());
    v->add_option("--set", a.set, "setting of the refining integrator NAME.KEY=VALUE (repeatable)")
        ->allow_extra_args(false)
        ->check(setting());
    v->add_option("--output-dir", a.output_dir, "where Save EXR writes view-NNN.exr (default: .)")
        ->check(CLI::ExistingDirectory);
    v->add_option("--preview", a.preview,
                  "moving frames at 1/N of the width and height, then one at full resolution when "
                  "the view stops (default 2; 1: always full)")
        ->check(CLI::Range(1, 8));
    v->add_option("--bench-frames", a.bench_frames,
                  "no server: time N moving frames of an orbit about the view's target, at the "
                  "preview's and at full resolution, print them as JSON and exit (bench/)")
        ->check(positive_integer());
    v->add_option("--exit-after", a.exit_after, "stop by itself after this many seconds (tests)")
        ->check(positive_seconds());
}

namespace {

// The viewer's renderer for the scene of `a`: parsed, built into *scene (which must outlive it).
std::unique_ptr<ViewRenderer> load_view(const ViewArgs& a, std::unique_ptr<Scene>* scene) {
    // A slow load, for the tests of pages that connect meanwhile (tests/test_viewer_stress.cpp):
    // a large scene on a busy machine, in a second or two.
    if (const char* wait = std::getenv("MANYLIGHT_TEST_VIEW_LOAD_SECONDS"))
        std::this_thread::sleep_for(std::chrono::duration<double>(std::atof(wait)));
    SceneDesc desc = parse_scene_file(a.scene);
    ViewConfig config;
    config.scene_path = a.scene;
    config.threads = a.threads;
    config.save_dir = a.output_dir;
    config.preview = a.preview;
    config.spp = a.spp > 0 ? a.spp : 64;
    config.integrator = a.integrator.empty() ? "path" : a.integrator;
    for (const std::string& kv : a.set) {
        size_t eq = kv.find('=');
        config.set[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
    if (!a.resolution.empty()) {
        std::sscanf(a.resolution.c_str(), "%dx%d", &config.width, &config.height);
    } else {
        config.width = desc.film.params.get_int("xresolution", 1280);
        config.height = desc.film.params.get_int("yresolution", 720);
        while (config.width > kDefaultViewWidth && config.width % 2 == 0 &&
               config.height % 2 == 0) {
            config.width /= 2;
            config.height /= 2;
        }
    }
    {
        ThreadLimit limit(a.threads > 0 ? a.threads : default_thread_count());
        *scene = std::make_unique<Scene>(std::move(desc));
    }
    return std::make_unique<ViewRenderer>(**scene, config);
}

}  // namespace

int run_view(const ViewArgs& a) {
#ifdef __GLIBC__
    // Frame after frame allocates and frees buffers of the same sizes (film, G-buffer): keep
    // the freed memory in the heap instead of unmapping it, so that each frame does not fault
    // in and zero fresh pages (measured: about 7% of a frame's CPU time, bench/RESULTS.md).
    mallopt(M_MMAP_THRESHOLD, 256 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
    std::unique_ptr<Scene> scene;
    if (a.bench_frames > 0) {
        bench_moving_frames(*load_view(a, &scene), a.bench_frames);
        return 0;
    }
    // The server listens before the scene loads: a page opened at once is told it loads.
    ViewServerOptions server;
    server.scene = a.scene;
    server.bind = a.bind;
    server.port = a.port;
    server.exit_after = a.exit_after;
    serve_viewer([&] { return load_view(a, &scene); }, server);
    return 0;
}

}  // namespace ml
