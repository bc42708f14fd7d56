#include "manylight/pilot.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "core/parallel.h"
#include "render/checkpoint.h"
#include "render/render_loop.h"

namespace ml {

namespace {

// The pixels of a regular grid of about `count` pixels over a w x h film, each at the middle of
// its cell.
std::vector<Point2i> grid_pixels(int w, int h, int count) {
    int step = std::max(1, int(std::lround(std::sqrt(double(w) * h / count))));
    int nx = (w + step - 1) / step, ny = (h + step - 1) / step;
    std::vector<Point2i> out;
    for (int iy = 0; iy < ny; ++iy)
        for (int ix = 0; ix < nx; ++ix)
            out.push_back(
                {std::min(w - 1, ix * step + step / 2), std::min(h - 1, iy * step + step / 2)});
    return out;
}

}  // namespace

double pilot_mean_luminance(int width, int height,
                            const std::function<RGB(Point2i pixel)>& estimate) {
    if (width <= 0 || height <= 0) return 0;
    const std::vector<Point2i> pixels = grid_pixels(width, height, kPilotPixels);
    std::vector<double> values(pixels.size(), 0.0);
    parallel_for(size_t(0), values.size(), [&](size_t i) {
        RGB v = estimate(pixels[i]);
        double l = v.luminance();
        values[i] = std::isfinite(l) ? std::max(0.0, l) : 0.0;
    });
    double sum = 0;
    for (double v : values) sum += v;  // in grid order: the same for any schedule
    return sum / double(values.size());
}

CutCapPlan choose_cut_cap(const CutProbe& probe, double film_pixels, int lowest, int max_cut,
                          double seconds) {
    CutCapPlan plan;
    plan.cap = max_cut;
    if (probe.low_seconds < 0 || probe.full_seconds < 0) {  // the probe's time ran out
        plan.cap = lowest;
        plan.samples_scale = 0;  // as few samples as a pass can take
        return plan;
    }
    // A cut stopped at cap c may end a little past it (lightcuts' last split): it ends at about
    // `overshoot` times c, as the visit at `lowest` measured.
    const double overshoot = std::max(1.0, probe.low_mean_size / double(lowest));
    auto mean_size = [&](int cap) {
        double sum = 0;
        for (int s : probe.full_sizes) sum += std::min(double(s), overshoot * cap);
        return probe.full_sizes.empty() ? 0.0 : sum / double(probe.full_sizes.size());
    };
    const double s_low = probe.low_mean_size, s_full = mean_size(max_cut);
    const double per_size =
        s_full > s_low ? std::max(0.0, probe.full_seconds - probe.low_seconds) / (s_full - s_low)
                       : 0;
    auto predicted = [&](int cap) {
        return film_pixels * (probe.low_seconds + per_size * (mean_size(cap) - s_low));
    };
    plan.full_seconds = film_pixels * probe.full_seconds;
    plan.mean_full_size = s_full;
    // Per pixel, the part of the time at `lowest` that halves with the samples, twice over: the
    // samples' own share of a pass, whatever the cap (the cap's cuts add only to the fixed part).
    const double t_low = probe.low_seconds, t_half = probe.half_seconds;
    const double sample_part = t_half > 0 && t_half < t_low ? 2 * (t_low - t_half) : 0;
    auto fixed_share = [&](double pass_seconds, double scale) {
        if (!(sample_part > 0) || !(pass_seconds > 0)) return 1.0;
        return std::clamp(1 - film_pixels * sample_part * scale / pass_seconds, 0.0, 1.0);
    };
    if (plan.full_seconds <= seconds) {
        plan.capped_seconds = plan.full_seconds;
        plan.fixed_share = fixed_share(plan.full_seconds, 1);
        return plan;
    }
    // The predicted time grows with the cap: the largest cap that fits, by bisection.
    int lo = lowest, hi = max_cut;
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        (predicted(mid) <= seconds ? lo : hi) = mid;
    }
    plan.cap = lo;
    plan.capped_seconds = predicted(lo);
    if (plan.capped_seconds <= seconds) {
        plan.fixed_share = fixed_share(plan.capped_seconds, 1);
        return plan;
    }
    // Even the least cut does not fit: fewer samples. Per pixel, t(S) through (S0, t_low) and
    // (S0 / 2, t_half), solved for the time there is.
    const double budget = seconds / film_pixels;
    if (sample_part > 0) {
        plan.samples_scale = std::clamp(0.5 + 0.5 * (budget - t_half) / (t_low - t_half), 0.0, 1.0);
        double pass = film_pixels * (t_low - sample_part * (1 - plan.samples_scale));
        plan.fixed_share = fixed_share(pass, plan.samples_scale);
    } else {
        plan.samples_scale = 0.8 * seconds / plan.capped_seconds;
    }
    return plan;
}

int pass_samples(int samples, const CutCapPlan& plan) {
    if (!(plan.samples_scale < 1)) return samples;
    return std::max(1, int(double(samples) * plan.samples_scale));
}

int passes_per_set(double set_seconds, double pass_seconds, double share, double mean_cut) {
    if (!(set_seconds > 0) || !(pass_seconds > 0) || !(share > 0)) return 1;
    if (!(mean_cut <= kSetReuseMaxCut)) return 1;
    return int(std::clamp(std::ceil(set_seconds / (share * pass_seconds)), 1.0, 1e6));
}

int remainder_samples(int pass_samples, double pass_seconds, double fixed_share, double seconds) {
    const double a = std::clamp(fixed_share, 0.0, 1.0);
    if (pass_samples < 2 || !(pass_seconds > 0) || !(seconds > 0) || a >= 1) return 0;
    double k = double(pass_samples) * (kRoundTimeShare * seconds / pass_seconds - a) / (1 - a);
    return int(std::clamp(std::floor(k), 0.0, double(pass_samples - 1)));
}

LastPass last_pass(int pass_samples, double pass_seconds, double fixed_share, double seconds) {
    LastPass out;
    out.samples = remainder_samples(pass_samples, pass_seconds, fixed_share, seconds);
    if (out.samples > 0 || !(pass_seconds > 0) || !(seconds > 0) || !(fixed_share < 1)) return out;
    const double phi = std::min(1.0, kRoundTimeShare * seconds / pass_seconds);
    if (phi < kMinLastPassShare) return out;
    out.samples = std::clamp(int(std::floor(phi * pass_samples)), 1, pass_samples);
    out.cut_share = phi;
    return out;
}

int last_pass_cap(const LastPass& plan, double mean_size, int cap) {
    if (!(plan.cut_share < 1)) return cap;
    const double c = std::floor(plan.cut_share * mean_size);
    return std::min(cap, std::max(kMinLastPassCut, std::isfinite(c) ? int(c) : cap));
}

SamplePasses render_sample_passes(
    const RenderContext& ctx, int pass_samples, double fixed_share,
    const std::function<void(Point2i pixel, int first, int samples)>& fn,
    const std::function<void(const LastPass& plan)>& last, const std::function<void()>& after_first,
    const std::function<void(int64_t pass)>& begin_pass) {
    const int64_t n = pass_samples, passes = (int64_t(ctx.spp) + n - 1) / n;
    const double start = ctx.elapsed();
    // With a checkpoint the passes are its units: a resumed render goes on from the pass it
    // stopped in (its earlier passes' time is not this run's).
    Checkpoint* checkpoint = ctx.checkpoint;
    const int64_t resumed =
        checkpoint && checkpoint->resuming() ? std::min(checkpoint->units(), passes) : 0;
    SamplePasses out;
    // Passes [from, to), each pixel taking its passes in order; returns the passes done from 0.
    auto run = [&](int64_t from, int64_t to) {
        auto shade = [&](Point2i pixel, int64_t p0, int64_t p1) {
            for (int64_t p = p0; p < p1; ++p) fn(pixel, int(p * n), int(n));
        };
        if (!begin_pass && !checkpoint)
            return from + render_pixels(ctx, to - from, [&](Point2i pixel, int64_t p0, int64_t p1) {
                       shade(pixel, from + p0, from + p1);
                   });
        return render_pixel_blocks(
            ctx, passes, 1,
            [&](int64_t b) {
                if (begin_pass) begin_pass(b);
            },
            shade, checkpoint, from, to);
    };
    if (after_first && passes > 1) {
        out.whole = run(0, 1);
        if (out.whole == 1) {
            after_first();
            out.whole = run(1, passes);
        }
    } else {
        out.whole = run(0, passes);
    }
    out.samples = out.whole * n;
    if (out.whole > resumed)
        out.pass_seconds = (ctx.elapsed() - start) / double(out.whole - resumed);
    // The passes done, as a checkpoint counts them (the last pass below is one).
    int64_t units = out.whole;
    auto finish = [&] {
        if (checkpoint) checkpoint->save(units, ctx.elapsed());
        return out;
    };
    // A round cut short by the limit leaves its samples in some tiles: none is taken again.
    // (The passes done are the same on every rank; whether the time is spent is rank 0's
    // decision: a rank that ended here on its own clock while another went on to the all_min
    // below left that one waiting for good, as Mpi.ReducedVplCountIsAgreedAcrossRanks did once in
    // five runs on a loaded machine.)
    if (!(ctx.time_limit > 0) || out.whole == 0 || out.whole >= passes ||
        ctx.world_or_local().root_decides(ctx.out_of_time()))
        return finish();
    LastPass plan =
        last_pass(pass_samples, out.pass_seconds, fixed_share, ctx.time_limit - ctx.elapsed());
    int64_t k = std::min<int64_t>(plan.samples, int64_t(ctx.spp) - out.samples);
    if (ctx.ranks() > 1) {
        // Every rank takes the least pass: the fewest samples and the smallest cut share.
        k = ctx.world->all_min(k);
        plan.cut_share =
            double(ctx.world->all_min(int64_t(std::floor(plan.cut_share * 1e6)))) * 1e-6;
    }
    if (k <= 0) return finish();
    plan.samples = int(k);
    if (last) last(plan);
    // The last pass is pass `whole` of the loop: with a checkpoint its pixels count it done.
    const int first = int(out.samples);
    auto shade_last = [&](Point2i pixel, int64_t, int64_t) { fn(pixel, first, int(k)); };
    int64_t ran = 0;
    if (checkpoint) {
        ran = render_pixel_blocks(
                  ctx, out.whole + 1, 1,
                  [&](int64_t b) {
                      if (begin_pass) begin_pass(b);
                  },
                  shade_last, checkpoint, out.whole) -
              out.whole;
    } else {
        if (begin_pass) begin_pass(out.whole);
        ran = render_pixels(ctx, 1, shade_last);
    }
    if (ran == 1) {
        out.samples += k;
        out.last_samples = int(k);
        out.last_cut_share = plan.cut_share;
        ++units;
    }
    return finish();
}

CutProbe probe_cuts(int width, int height, int lowest, int max_cut, int samples, double seconds,
                    const std::function<int(Point2i pixel, int cap, int samples)>& shade) {
    CutProbe probe;
    if (width <= 0 || height <= 0) return probe;
    // Blocks of kCutProbeBlock x kCutProbeBlock neighbouring pixels, centred on a grid, each
    // shaded in order by one thread: as coherent as the pass's tiles, whose cost the probe
    // predicts (scattered single pixels ran about 1.4x slower per pixel on the kitchen).
    constexpr int b = kCutProbeBlock;
    std::vector<Point2i> pixels;
    for (Point2i c : grid_pixels(width, height, std::max(1, kCutProbePixels / (b * b)))) {
        int x0 = std::clamp(c.x - b / 2, 0, std::max(0, width - b));
        int y0 = std::clamp(c.y - b / 2, 0, std::max(0, height - b));
        for (int y = y0; y < std::min(height, y0 + b); ++y)
            for (int x = x0; x < std::min(width, x0 + b); ++x) pixels.push_back({x, y});
    }
    const size_t per_block = size_t(std::min(b, width)) * size_t(std::min(b, height));
    // A visit of the grid at one cap: the pixels' cut sizes (-1 where the visit's share of the
    // time ran out before the pixel started), and the wall seconds per pixel visited.
    std::vector<int> sizes(pixels.size());
    auto visit = [&](int cap, int n) {
        auto t0 = std::chrono::steady_clock::now();
        auto spent = [&] {
            return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        };
        parallel_for(size_t(0), pixels.size() / per_block, [&](size_t block) {
            for (size_t i = block * per_block; i < (block + 1) * per_block; ++i)
                sizes[i] = spent() < kCutProbeShare * seconds ? shade(pixels[i], cap, n) : -1;
        });
        double t = spent();
        std::erase_if(sizes, [](int s) { return s < 0; });
        return sizes.empty() ? -1.0 : t / double(sizes.size());
    };
    // The first visit also pays for what a render's first touches cost (pages of the trees and
    // the scene, the threads' buffers growing): it warms up, and the next one is timed.
    visit(lowest, samples);
    sizes.assign(pixels.size(), 0);
    probe.low_seconds = visit(lowest, samples);
    for (int s : sizes) probe.low_mean_size += s;
    if (!sizes.empty()) probe.low_mean_size /= double(sizes.size());
    sizes.assign(pixels.size(), 0);
    probe.full_seconds = visit(max_cut, samples);
    probe.full_sizes = std::move(sizes);
    if (samples >= 2) {
        sizes.assign(pixels.size(), 0);
        probe.half_seconds = visit(lowest, samples / 2);
    }
    return probe;
}

CutCapPlan plan_pass_cut_cap(const RenderContext& ctx, int max_cut, int samples,
                             const std::function<int(Point2i pixel, int cap, int samples)>& shade) {
    const int lowest = std::min(kPilotMaxCut, max_cut);
    if (!(ctx.time_limit > 0) || lowest >= max_cut) return CutCapPlan{max_cut};
    // The time left, as this rank's share of the film sees it.
    auto left = [&] { return std::max(0.0, ctx.time_limit - ctx.elapsed()) * double(ctx.ranks()); };
    const int w = ctx.film.width(), h = ctx.film.height();
    CutProbe probe = probe_cuts(w, h, lowest, max_cut, samples, left(), shade);
    CutCapPlan plan =
        choose_cut_cap(probe, double(w) * double(h), lowest, max_cut, kFirstPassTimeShare * left());
    if (ctx.ranks() > 1) {
        plan.cap = int(ctx.world->all_min(int64_t(plan.cap)));
        // The samples too (in millionths), so that every rank's passes are alike.
        plan.samples_scale = double(ctx.world->all_min(int64_t(plan.samples_scale * 1e6))) * 1e-6;
    }
    return plan;
}

}  // namespace ml
