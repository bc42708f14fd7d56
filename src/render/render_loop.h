// The render loop every integrator runs: work in rounds, under a sample budget or a time limit,
// with progress, and the same image for a seed whatever the thread count or schedule.
//   - Pixel integrators (path, lightcuts, mdlightcuts...): rounds of samples (or passes) per
//     pixel; pixels in tiles in parallel, each pixel's units in order by one thread
//     (render_pixels).
//   - Splat integrators (lighttracer, bdpt) and Markov chains (mlt, pssmlt): work items (tiles,
//     chains) in parallel, each writing its splats to its own list; the lists are summed in item
//     order (splats.h: run_and_merge), never in the order threads finish.
// Under a time limit, run_rounds sizes each round from the last one's cost so that it ends in
// time; no round is started that is not expected to.
// Across MPI ranks (RenderContext::world) each rank takes the items it owns (RenderContext::owns:
// pixel tiles, splat tiles, chains), run_rounds keeps the ranks' rounds in step, and the render
// job sums the ranks' films on rank 0.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>

#include "core/math.h"
#include "render/integrator.h"

namespace ml {

// Under a time limit a round plans to fill this share of the time left: the rest absorbs the
// error of the cost estimate, measured on the last round.
constexpr double kRoundTimeShare = 0.95;
// A round is at most this many times the last, so that the cost estimate stays fresh.
constexpr double kMaxRoundGrowth = 4.0;
// The least cost per unit a round is assumed to have (seconds): a round too fast to measure
// does not make the next one infinite.
constexpr double kMinSecondsPerUnit = 1e-9;
// Without a time limit, the largest round of samples per pixel (RoundPlan::untimed_most) that
// pixel and splat integrators run.
constexpr int64_t kUntimedRoundSamples = 64;

// Under a time limit, how many units (samples, passes, mutations) the next round may take: what
// fills kRoundTimeShare of the time left at the last round's cost per unit, at most
// kMaxRoundGrowth times the last round and at most `most`; 0 when no unit fits any more.
int64_t next_round_size(int64_t last_units, double last_seconds, double elapsed, double time_limit,
                        int64_t most = std::numeric_limits<int64_t>::max());

struct RoundPlan {
    int64_t total = 0;        // units in all (the sample or mutation budget)
    int64_t done = 0;         // units already done (a render resumed from a checkpoint)
    int64_t first_timed = 1;  // units of the first round under a time limit: a cheap measure
    int64_t most = std::numeric_limits<int64_t>::max();  // no round is larger
    // Without a time limit, rounds of 1, 2, 4... units up to this many, as pbrt-v4's waves: every
    // pixel has samples early, so a stop (Ctrl-C) keeps an image of the whole frame and waits for
    // no long round. 0: one round of the whole budget (at most `most`).
    int64_t untimed_most = 0;
    // Called after every round that counted with the units done so far (on every rank): where
    // a checkpoint is offered a save.
    std::function<void(int64_t done)> after_round;
};

// Runs rounds from `plan.done` until `plan.total` units are done: round(done, units) runs up to
// `units` more units (the caller clips them to what is left) and returns how many it ran; 0
// (nothing left to run, or a round cut short by the time limit, which then does not count) ends the
// loop. Without a time limit, rounds of plan.most units (the whole budget by default), or growing
// to plan.untimed_most when that is set; under one, a
// first round of plan.first_timed units, then each as next_round_size says, timed from the render's
// start (RenderContext::elapsed). Reports progress after each round. A cancelled render starts no
// round. Returns the units done (plan.done included).
// Across ranks, round() must return the same count on every rank (a sum over the ranks where
// each runs a share), or 0 where it was cut short: run_rounds takes the least over the ranks,
// and the least next round size, so that every rank runs the same rounds.
int64_t run_rounds(const RenderContext& ctx, const RoundPlan& plan,
                   const std::function<int64_t(int64_t done, int64_t units)>& round);

// The progress bar's fraction: the time spent under a time limit, else the share of the work.
void report_progress(const RenderContext& ctx, double work_fraction);

// Runs fn(pixel, u0, u1) for every pixel of the film, in rounds of units [u0, u1) planned by
// run_rounds (without a time limit, one round of all `units`). Pixels run in tiles in parallel;
// each pixel's units run in order on one thread, so the image does not depend on the schedule.
// Past the time limit no tile or row of a tile starts, even within a round: the contract is the
// time; the round then does not count (the film's weights keep the pixels' means right).
// Across ranks each renders the 8x8 tiles it owns (tile % ranks == rank). Returns the units done.
// With a checkpoint (a render that saves or resumes its state), rounds are of one unit, each
// pixel starts past the units the checkpoint says it has done, and every round ends with an
// offer to save (Checkpoint::round_done).
int64_t render_pixels(const RenderContext& ctx, int64_t units,
                      const std::function<void(Point2i pixel, int64_t u0, int64_t u1)>& fn,
                      Checkpoint* checkpoint = nullptr);

// render_pixels in blocks of `block` units, each begun by begin_block(b) (b = 0, 1, ...) once
// the last block has ended on every pixel: for integrators that shade each block with state of
// its own (a new VPL set for every pass of samples). Under a time limit a block after the first
// begins only where the mean time of a unit so far (begin_block's included) fits
// kRoundTimeShare of the time left; a block the limit cuts short ends the loop. Returns the
// units done, counted from 0. With a checkpoint, a resumed render begins at the block the
// checkpoint stopped in (begin_block(b) must make the same state whenever it is called: from the
// seed and b). With `from` and `to` (multiples of `block`; to < 0: `units`) it runs the units
// [from, to) of the loop alone, as a part of it (work of its own between the parts): blocks,
// units, progress and the checkpoint's units count over the whole loop all the same.
int64_t render_pixel_blocks(const RenderContext& ctx, int64_t units, int64_t block,
                            const std::function<void(int64_t b)>& begin_block,
                            const std::function<void(Point2i pixel, int64_t u0, int64_t u1)>& fn,
                            Checkpoint* checkpoint = nullptr, int64_t from = 0, int64_t to = -1);

// The same loop a row of a tile at a time: fn(y, x0, x1, u0, u1) runs units [u0, u1) of the
// pixels x0 <= x < x1 of row y (at most 8 of them), in an order of its choosing, for integrators
// that shade neighbouring pixels together (igi: one shadow-ray packet per light for the row).
// render_pixels is this with the pixels one after the other.
int64_t render_rows(const RenderContext& ctx, int64_t units,
                    const std::function<void(int y, int x0, int x1, int64_t u0, int64_t u1)>& fn,
                    Checkpoint* checkpoint = nullptr);

// Whether the render stops now, the same answer on every rank (one that is cancelled stops all).
bool cancelled_everywhere(const RenderContext& ctx);

}  // namespace ml
