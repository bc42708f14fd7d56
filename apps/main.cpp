// manylight: the command line (DESIGN.md section 3). Exit 0 on success, 1 on bad input (with
// `file:line:col: message`), 2 on bad usage.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>

#include "commands.h"
#include "core/error.h"
#include "distributed/mpi_world.h"
#include "options.h"

int main(int argc, char** argv) {
    CLI::App app{"manylight: a many-light renderer (pbrt-v4 scenes in, images out)"};
    app.require_subcommand(1);
    // One prefix on every message; set before the subcommands, which copy it.
    app.failure_message([](const CLI::App*, const CLI::Error& e) {
        return std::string(ml::kMessagePrefix) + e.what() + "\n";
    });
    app.set_version_flag("--version", "manylight 0.1");
    ml::RenderArgs render_args;
    ml::add_render_command(app, render_args);
    ml::DiffArgs diff_args;
    ml::add_diff_command(app, diff_args);
    ml::InfoArgs info_args;
    ml::add_info_command(app, info_args);
    ml::IntegratorsArgs integrators_args;
    ml::add_integrators_command(app, integrators_args);
    ml::ViewArgs view_args;
    ml::add_view_command(app, view_args);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }
    // Under mpirun (render only): an error on any rank ends every rank (MPI_Abort) with its
    // message, rather than leaving the others waiting for it in a collective.
    ml::World* world = nullptr;
    auto fail = [&](std::string message, int code) {
        if (world && world->size() > 1) {
            const std::string prefix = ml::kMessagePrefix;
            if (message.rfind(prefix, 0) == 0) message.erase(0, prefix.size());
            world->abort(
                fmt::format("manylight (rank {} of {}): {}", world->rank(), world->size(), message),
                code);
        }
        std::fflush(stdout);
        std::cerr << message << "\n";
        return code;
    };
    try {
        if (app.got_subcommand("render")) {
            world = &ml::process_world(&argc, &argv);
            return ml::run_render(render_args, *world);
        }
        if (ml::launched_ranks() > 1)
            throw ml::UsageError("only `manylight render` runs under mpirun");
        if (app.got_subcommand("diff")) return ml::run_diff(diff_args);
        if (app.got_subcommand("info")) return ml::run_info(info_args);
        if (app.got_subcommand("integrators")) return ml::run_integrators(integrators_args);
        if (app.got_subcommand("view")) return ml::run_view(view_args);
    } catch (const ml::InputError& e) {
        return fail(e.formatted(), 1);
    } catch (const ml::UsageError& e) {
        return fail(std::string(ml::kMessagePrefix) + e.what(), 2);
    } catch (const std::exception& e) {
        return fail(std::string(ml::kMessagePrefix) + e.what(), 1);
    }
    return 2;
}
