#include "render/render_loop.h"

#include <algorithm>
#include <atomic>

#include "core/assert.h"
#include "core/parallel.h"

namespace ml {

namespace {

constexpr int kPixelTile = 8;  // pixels on a side of the tiles render_pixels hands to threads

}  // namespace

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
    int64_t done = 0;
    int64_t units = timed ? std::min(plan.first_timed, plan.most) : plan.most;
    while (done < plan.total && units > 0) {
        double round_start = ctx.elapsed();
        int64_t ran = round(done, units);
        ML_ASSERT(ran >= 0 && ran <= units, "a round ran more units than it was given");
        if (ran == 0) break;
        done += ran;
        report_progress(ctx, double(done) / double(plan.total));
        if (timed)
            units = next_round_size(ran, ctx.elapsed() - round_start, ctx.elapsed(), ctx.time_limit,
                                    plan.most);
    }
    return done;
}

int64_t render_pixels(const RenderContext& ctx, int64_t units,
                      const std::function<void(Point2i pixel, int64_t u0, int64_t u1)>& fn) {
    const int w = ctx.film.width(), h = ctx.film.height();
    // Progress within a round: rows of pixels done, each counted for its units.
    std::atomic<int64_t> rows_done{0};
    const double total_rows = double(h) * double(units);
    RoundPlan plan;
    plan.total = units;
    return run_rounds(ctx, plan, [&](int64_t u0, int64_t want) {
        const int64_t n = std::min(want, units - u0), u1 = u0 + n;
        std::atomic<bool> cut_short{false};
        parallel_for_tiles(w, h, kPixelTile, [&](int y0, int y1, int x0, int x1) {
            for (int y = y0; y < y1; ++y) {
                // Past the time limit no tile or row starts (see render_loop.h).
                if (ctx.out_of_time()) {
                    cut_short = true;
                    return;
                }
                for (int x = x0; x < x1; ++x) fn(Point2i{x, y}, u0, u1);
                if (ctx.progress) {
                    int64_t rows = n * (x1 - x0) / w;
                    report_progress(ctx, double(rows_done.fetch_add(rows) + rows) / total_rows);
                }
            }
        });
        return cut_short ? int64_t(0) : n;
    });
}

}  // namespace ml
