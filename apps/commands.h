// The subcommands of the manylight program.
#pragma once

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "core/world.h"

namespace ml {

struct RenderArgs {
    std::string scene, output, integrator, resolution, stats, sampler;
    int spp = 0, max_depth = -1, threads = 0;
    long long seed = -1;
    double time_limit = 0;
    std::vector<std::string> set;
    std::vector<std::string> aovs;
    std::vector<float> look_at;  // --look-at: eye, target, up (9 numbers)
    bool quiet = false;
    // The bias check (integrators/bias_check.h): auto, on or off; its share of the time, its
    // pixels and (0: from the share) its path samples per pixel.
    std::string bias_check = "auto";
    double bias_check_share = 0.1;
    int bias_check_pixels = 256, bias_check_spp = 0;
    // --checkpoint FILE (save every checkpoint_every seconds and at the end), --resume FILE.
    std::string checkpoint, resume;
    double checkpoint_every = 60;
};
void add_render_command(CLI::App& app, RenderArgs& args);
// Under mpirun, `world` holds the ranks: every rank renders its share, rank 0 writes the image,
// --stats and the summary.
int run_render(const RenderArgs& args, World& world);

struct DiffArgs {
    std::string a, b;
    bool json = false;
    int block = 0;
    bool block_average = false;
};
void add_diff_command(CLI::App& app, DiffArgs& args);
int run_diff(const DiffArgs& args);

struct IntegratorsArgs {
    std::string name;  // empty: all
    bool markdown = false;
};
void add_integrators_command(CLI::App& app, IntegratorsArgs& args);
int run_integrators(const IntegratorsArgs& args);

struct InfoArgs {
    std::string scene;
};
void add_info_command(CLI::App& app, InfoArgs& args);
int run_info(const InfoArgs& args);

struct ViewArgs {
    std::string scene, bind = "127.0.0.1", integrator, resolution, output_dir = ".";
    int port = 8080, threads = 0, spp = 0;
    int preview = 2;       // moving frames at 1/preview of the resolution
    int bench_frames = 0;  // > 0: time this many moving frames, print them, exit (no server)
    std::vector<std::string> set;
    double exit_after = 0;  // seconds; > 0: stop by itself (tests)
};
void add_view_command(CLI::App& app, ViewArgs& args);
int run_view(const ViewArgs& args);

}  // namespace ml
