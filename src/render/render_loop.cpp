#include "render/render_loop.h"

#include <algorithm>
#include <atomic>
#include <vector>

#include "core/assert.h"
#include "core/parallel.h"

namespace ml {

namespace {

constexpr int kPixelTile = 8;  // pixels on a side of the tiles render_pixels hands to threads

using RowFn = std::function<void(int y, int x0, int x1, int64_t u0, int64_t u1)>;

// render_rows for units [first, first + units) of a longer loop (render_pixel_blocks' blocks):
// fn sees units counted from `first`; a checkpoint's per-pixel units are absolute.
int64_t render_rows_from(const RenderContext& ctx, int64_t first, int64_t units, const RowFn& fn,
                         Checkpoint* checkpoint);

}  // namespace

bool cancelled_everywhere(const RenderContext& ctx) {
    if (ctx.ranks() == 1) return ctx.cancelled();
    return ctx.world->all_min(ctx.cancelled() ? 0 : 1) == 0;
}

int64_t next_round_size(int64_t last_units, double last_seconds, double elapsed, double time_limit,
                        int64_t most) {
    double per_unit =
        std::max(last_seconds / double(std::max<int64_t>(last_units, 1)), kMinSecondsPerUnit);
    double left = time_limit - elapsed;
    double units = std::min(
        {kMaxRoundGrowth * double(last_units), kRoundTimeShare * left / per_unit, double(most)});
    return int64_t(std::max(0.0, units));
}

void report_progress(const RenderContext& ctx, double work_fraction) {
    if (!ctx.progress) return;
    ctx.progress->set_fraction(ctx.time_limit > 0 ? ctx.elapsed() / ctx.time_limit : work_fraction);
}

int64_t run_rounds(const RenderContext& ctx, const RoundPlan& plan,
                   const std::function<int64_t(int64_t done, int64_t units)>& round) {
    const bool timed = ctx.time_limit > 0;
    int64_t done = plan.done;
    const bool growing = !timed && plan.untimed_most > 0;
    int64_t units = timed     ? std::min(plan.first_timed, plan.most)
                    : growing ? std::min<int64_t>(1, plan.most)
                              : plan.most;
    while (done < plan.total && units > 0 && !cancelled_everywhere(ctx)) {
        double round_start = ctx.elapsed();
        int64_t ran = round(done, units);
        ML_ASSERT(ran >= 0 && ran <= units, "a round ran more units than it was given");
        // Across ranks: a round cut short on any rank counts on none, and the next round is the
        // least any rank expects to finish in time, so every rank runs the same rounds.
        if (ctx.ranks() > 1) ran = ctx.world->all_min(ran);
        if (ran == 0) break;
        done += ran;
        report_progress(ctx, double(done) / double(plan.total));
        if (plan.after_round) plan.after_round(done);
        if (growing) units = std::min({2 * units, plan.untimed_most, plan.most});
        if (timed) {
            units = next_round_size(ran, ctx.elapsed() - round_start, ctx.elapsed(), ctx.time_limit,
                                    plan.most);
            if (ctx.ranks() > 1) units = ctx.world->all_min(units);
        }
    }
    return done;
}

int64_t render_pixels(const RenderContext& ctx, int64_t units,
                      const std::function<void(Point2i pixel, int64_t u0, int64_t u1)>& fn,
                      Checkpoint* checkpoint) {
    return render_rows(
        ctx, units,
        [&](int y, int x0, int x1, int64_t u0, int64_t u1) {
            for (int x = x0; x < x1; ++x) fn(Point2i{x, y}, u0, u1);
        },
        checkpoint);
}

int64_t render_pixel_blocks(const RenderContext& ctx, int64_t units, int64_t block,
                            const std::function<void(int64_t b)>& begin_block,
                            const std::function<void(Point2i pixel, int64_t u0, int64_t u1)>& fn,
                            Checkpoint* checkpoint, int64_t from, int64_t to) {
    ML_ASSERT(block > 0, "render_pixel_blocks needs blocks of at least one unit");
    ML_ASSERT(from >= 0 && from % block == 0, "render_pixel_blocks starts at a block");
    const int64_t end = to < 0 ? units : std::min(to, units);
    const double start = ctx.elapsed();
    // A resumed render begins at the block its checkpoint stopped in.
    const int64_t b0 = std::max(from, checkpoint && checkpoint->resuming()
                                          ? std::min(checkpoint->units(), end)
                                          : int64_t(0)) /
                       block,
                  done0 = std::min(end, b0 * block);
    int64_t done = done0;
    for (int64_t b = b0; done < end; ++b) {
        if (ctx.time_limit > 0 && done > done0) {
            const double per_unit = (ctx.elapsed() - start) / double(done - done0);
            int64_t go = per_unit <= kRoundTimeShare * (ctx.time_limit - ctx.elapsed()) ? 1 : 0;
            if (ctx.ranks() > 1) go = ctx.world->all_min(go);
            if (!go) break;
        }
        begin_block(b);
        const int64_t first = done, n = std::min(block, end - done);
        // (Under a time limit the fraction is the time's, which needs no span.)
        if (ctx.progress && !(ctx.time_limit > 0))
            ctx.progress->set_span(double(first) / double(units),
                                   double(first + n) / double(units));
        const int64_t ran = render_rows_from(
            ctx, first, n,
            [&](int y, int x0, int x1, int64_t u0, int64_t u1) {
                for (int x = x0; x < x1; ++x) fn(Point2i{x, y}, first + u0, first + u1);
            },
            checkpoint);
        done += ran;
        if (ran < n) break;
    }
    if (ctx.progress) ctx.progress->set_span(0, 1);
    return done;
}

int64_t render_rows(const RenderContext& ctx, int64_t units, const RowFn& fn,
                    Checkpoint* checkpoint) {
    return render_rows_from(ctx, 0, units, fn, checkpoint);
}

namespace {

int64_t render_rows_from(const RenderContext& ctx, int64_t first, int64_t units, const RowFn& fn,
                         Checkpoint* checkpoint) {
    const int w = ctx.film.width(), h = ctx.film.height();
    // Across ranks each takes the tiles it owns (tile index % ranks == rank): every pixel is
    // rendered by one rank, as by one process, and the films add up exactly.
    std::vector<int> owned;
    const int tiles_x = (w + kPixelTile - 1) / kPixelTile,
              tiles_y = (h + kPixelTile - 1) / kPixelTile;
    int64_t owned_pixels = int64_t(w) * h;
    if (ctx.ranks() > 1) {
        owned_pixels = 0;
        for (int t = 0; t < tiles_x * tiles_y; ++t)
            if (ctx.owns(t)) {
                owned.push_back(t);
                int x0 = (t % tiles_x) * kPixelTile, y0 = (t / tiles_x) * kPixelTile;
                owned_pixels += int64_t(std::min(w, x0 + kPixelTile) - x0) *
                                (std::min(h, y0 + kPixelTile) - y0);
            }
    }
    // Progress within a round: pixels done, each counted for its units.
    std::atomic<int64_t> pixel_units_done{0};
    const double total_pixel_units = double(owned_pixels) * double(units);
    RoundPlan plan;
    plan.total = units;
    plan.untimed_most = kUntimedRoundSamples;
    if (checkpoint) {
        // Rounds of one unit, each offered to the checkpoint; a resumed render starts where the
        // checkpoint's round did (pixels a stop left ahead skip what they have done, below).
        plan.most = 1;
        if (checkpoint->resuming())
            plan.done = std::clamp<int64_t>(checkpoint->units() - first, 0, units);
        plan.after_round = [&](int64_t done) {
            checkpoint->round_done(first + done, ctx.elapsed());
        };
    }
    return run_rounds(ctx, plan, [&](int64_t u0, int64_t want) {
        const int64_t n = std::min(want, units - u0), u1 = u0 + n;
        std::atomic<bool> cut_short{false};
        auto tile = [&](int y0, int y1, int x0, int x1) {
            for (int y = y0; y < y1; ++y) {
                // Past the time limit no tile or row starts (see render_loop.h).
                if (ctx.out_of_time()) {
                    cut_short = true;
                    return;
                }
                if (checkpoint) {
                    // The row's pixels are done together: the first says how far they are.
                    const size_t p0 = size_t(y) * size_t(w) + size_t(x0);
                    const int64_t from = std::max(u0, checkpoint->pixel_units(p0) - first);
                    if (from < u1) fn(y, x0, x1, from, u1);
                    for (int x = x0; x < x1; ++x)
                        checkpoint->set_pixel_units(p0 + size_t(x - x0), first + u1);
                } else {
                    fn(y, x0, x1, u0, u1);
                }
                if (ctx.progress) {
                    // (Pixel units: a tile's row of a round of one unit is less than a row.)
                    const int64_t done = n * (x1 - x0);
                    report_progress(
                        ctx, double(pixel_units_done.fetch_add(done) + done) / total_pixel_units);
                }
            }
        };
        if (ctx.ranks() == 1)
            parallel_for_tiles(w, h, kPixelTile, tile);
        else
            parallel_for(size_t(0), owned.size(), [&](size_t i) {
                int x0 = (owned[i] % tiles_x) * kPixelTile, y0 = (owned[i] / tiles_x) * kPixelTile;
                tile(y0, std::min(h, y0 + kPixelTile), x0, std::min(w, x0 + kPixelTile));
            });
        return cut_short ? int64_t(0) : n;
    });
}

}  // namespace

}  // namespace ml
