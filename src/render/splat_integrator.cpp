#include "render/splat_integrator.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <chrono>

namespace ml {

namespace {

constexpr int kTile = 16;          // pixels on a tile's side
constexpr int kTilesPerWave = 64;  // tiles rendered between two merges of their splats

struct ThreadState {
    std::unique_ptr<Sampler> sampler;
    ScratchBuffer scratch;
};

}  // namespace

RenderResult SplatIntegrator::render(const RenderContext& ctx) {
    prepare(ctx);
    const int w = ctx.film.width(), h = ctx.film.height();
    const int tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
    const int tile_count = tiles_x * tiles_y;
    std::vector<std::string> extra = extra_images();
    // Sums of splats: the image's, then each extra image's; 3 doubles per pixel.
    std::vector<std::vector<double>> sums(1 + extra.size(),
                                          std::vector<double>(size_t(w) * h * 3, 0.0));
    tbb::enumerable_thread_specific<ThreadState> states([&] {
        return ThreadState{ctx.sampler.clone(), ScratchBuffer()};
    });
    auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };

    // Passes of samples [s0, s1) as PixelIntegrator: one pass for a fixed count, growing passes
    // under a time limit.
    int done = 0;
    int pass_spp = ctx.time_limit > 0 ? 1 : ctx.spp;
    int64_t tiles_done = 0;
    const int64_t total_tiles = int64_t(tile_count) * ((ctx.spp + pass_spp - 1) / pass_spp);
    std::vector<std::vector<Splat>> lists(kTilesPerWave);
    while (done < ctx.spp) {
        int s0 = done, s1 = std::min(ctx.spp, done + pass_spp);
        double pass_start = elapsed();
        for (int wave = 0; wave < tile_count; wave += kTilesPerWave) {
            int wave_end = std::min(tile_count, wave + kTilesPerWave);
            tbb::parallel_for(wave, wave_end, [&](int tile) {
                ThreadState& ts = states.local();
                std::vector<Splat>& list = lists[tile - wave];
                list.clear();
                SplatList splats(list, w, h);
                int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
                for (int y = y0; y < std::min(h, y0 + kTile); ++y)
                    for (int x = x0; x < std::min(w, x0 + kTile); ++x)
                        for (int s = s0; s < s1; ++s) {
                            ts.sampler->start_pixel_sample(Point2i{x, y}, s);
                            render_sample(ctx, Point2i{x, y}, s, *ts.sampler, ts.scratch, splats);
                            ts.scratch.reset();
                        }
            });
            // Merge in tile order: the sums do not depend on which thread ran which tile.
            for (int i = 0; i < wave_end - wave; ++i)
                for (const Splat& sp : lists[i]) {
                    double* d = &sums[size_t(sp.image + 1)][size_t(sp.pixel) * 3];
                    d[0] += sp.v.r, d[1] += sp.v.g, d[2] += sp.v.b;
                }
            tiles_done += wave_end - wave;
            if (ctx.progress)
                ctx.progress->set_fraction(ctx.time_limit > 0
                                               ? elapsed() / ctx.time_limit
                                               : double(tiles_done) / double(total_tiles));
        }
        done = s1;
        if (ctx.time_limit > 0) {
            double per_spp = (elapsed() - pass_start) / (s1 - s0);
            double left = ctx.time_limit - elapsed();
            pass_spp = int(std::min(4.0 * (s1 - s0), 0.95 * left / std::max(per_spp, 1e-9)));
            if (pass_spp < 1) break;
        }
    }

    // Splats are estimates per sample of every pixel: divide by the samples per pixel.
    RenderResult result;
    result.spp = done;
    const double scale = 1.0 / std::max(done, 1);
    auto to_rgb = [&](const std::vector<double>& sum, size_t i) {
        return RGB(float(sum[3 * i] * scale), float(sum[3 * i + 1] * scale),
                   float(sum[3 * i + 2] * scale));
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = size_t(y) * w + x;
            RGB v = to_rgb(sums[0], i);
            if (!v.is_black()) ctx.film.add_splat(Vec2(x + 0.5f, y + 0.5f), v);
        }
    for (size_t k = 0; k < extra.size(); ++k) {
        Image img(w, h);
        for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = to_rgb(sums[k + 1], i);
        result.debug_images[extra[k]] = std::move(img);
    }
    return result;
}

}  // namespace ml
