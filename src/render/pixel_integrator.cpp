#include <tbb/blocked_range2d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <chrono>

#include "core/stats.h"
#include "render/integrator.h"

namespace ml {

namespace {

struct ThreadState {
    std::unique_ptr<Sampler> sampler;
    ScratchBuffer scratch;
};

}  // namespace

Ray pixel_sample_ray(const RenderContext& ctx, Point2i pixel, Sampler& sampler,
                     float* filter_weight) {
    FilterSample fs = ctx.filter.sample(sampler.get_pixel_2d());
    CameraSample cs;
    cs.p_film = Vec2(float(pixel.x) + 0.5f + fs.p.x, float(pixel.y) + 0.5f + fs.p.y);
    cs.time = sampler.get_1d();
    cs.p_lens = sampler.get_2d();
    stats::count_camera_ray();
    *filter_weight = fs.weight;
    return ctx.camera.generate_ray(cs);
}

int next_round_size(int last_units, double last_seconds, double elapsed, double time_limit) {
    double per_unit = std::max(last_seconds / std::max(last_units, 1), 1e-9);
    double left = time_limit - elapsed;
    return int(std::max(0.0, std::min(4.0 * last_units, 0.95 * left / per_unit)));
}

RenderResult PixelIntegrator::render(const RenderContext& ctx) {
    prepare(ctx.scene);
    const int w = ctx.film.width(), h = ctx.film.height();
    tbb::enumerable_thread_specific<ThreadState> states([&] {
        return ThreadState{ctx.sampler.clone(), ScratchBuffer()};
    });
    auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };

    // Passes of samples [s0, s1): one pass for a fixed count; doubling passes under a time
    // limit, each started only if it is expected to end in time.
    int done = 0;
    int pass_spp = ctx.time_limit > 0 ? 1 : ctx.spp;
    std::atomic<int64_t> rows_done{0};
    const int64_t total_rows = int64_t(h) * ctx.spp;
    while (done < ctx.spp) {
        int s0 = done, s1 = std::min(ctx.spp, done + pass_spp);
        double pass_start = elapsed();
        tbb::parallel_for(
            tbb::blocked_range2d<int>(0, h, 8, 0, w, 8), [&](const tbb::blocked_range2d<int>& r) {
                ThreadState& ts = states.local();
                Sampler& sampler = *ts.sampler;
                for (int y = r.rows().begin(); y < r.rows().end(); ++y) {
                    for (int x = r.cols().begin(); x < r.cols().end(); ++x) {
                        Point2i pixel{x, y};
                        for (int s = s0; s < s1; ++s) {
                            sampler.start_pixel_sample(pixel, s);
                            float weight;
                            Ray ray = pixel_sample_ray(ctx, pixel, sampler, &weight);
                            RGB L = li(ray, ctx.scene, sampler, ts.scratch, pixel);
                            ctx.film.add_sample(pixel, L, weight);
                            ts.scratch.reset();
                        }
                    }
                    if (ctx.progress) {
                        int64_t rd = rows_done.fetch_add(int64_t(s1 - s0) * r.cols().size() / w) +
                                     int64_t(s1 - s0) * r.cols().size() / w;
                        double f = ctx.time_limit > 0 ? elapsed() / ctx.time_limit
                                                      : double(rd) / double(total_rows);
                        ctx.progress->set_fraction(f);
                    }
                }
            });
        done = s1;
        if (ctx.time_limit > 0) {
            pass_spp = next_round_size(s1 - s0, elapsed() - pass_start, elapsed(), ctx.time_limit);
            if (pass_spp < 1) break;
        }
    }
    RenderResult result;
    result.spp = done;
    return result;
}

}  // namespace ml
