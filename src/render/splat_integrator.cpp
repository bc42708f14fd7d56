#include "render/splat_integrator.h"

#include "core/parallel.h"
#include "render/render_loop.h"

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
    const SplatFilter spread(ctx.filter, w, h, ctx.film.splat_clamp());
    SplatSums sums(w, h, spread, int(extra.size()));
    ThreadLocal<ThreadState> states([&] {
        return ThreadState{ctx.sampler.clone(), ScratchBuffer()};
    });
    std::vector<std::vector<Splat>> lists(kTilesPerWave);

    // Rounds of samples [s0, s1) per pixel, each in waves of tiles.
    RoundPlan plan;
    plan.total = ctx.spp;
    const int64_t done = run_rounds(ctx, plan, [&](int64_t s0, int64_t want) {
        const int64_t n = std::min<int64_t>(want, ctx.spp - s0), s1 = s0 + n;
        for (int wave = 0; wave < tile_count; wave += kTilesPerWave) {
            int wave_end = std::min(tile_count, wave + kTilesPerWave);
            run_and_merge(wave, wave_end, lists, sums, [&](int64_t tile, SplatList& splats) {
                // Across ranks, each renders the tiles it owns (their camera samples and the
                // light paths they start); the others' splats reach rank 0 in the films' sum.
                if (!ctx.owns(tile)) return;
                ThreadState& ts = states.local();
                int x0 = int(tile % tiles_x) * kTile, y0 = int(tile / tiles_x) * kTile;
                for (int y = y0; y < std::min(h, y0 + kTile); ++y)
                    for (int x = x0; x < std::min(w, x0 + kTile); ++x)
                        for (int64_t s = s0; s < s1; ++s) {
                            ts.sampler->start_pixel_sample(Point2i{x, y}, int(s));
                            render_sample(ctx, Point2i{x, y}, int(s), *ts.sampler, ts.scratch,
                                          splats);
                            ts.scratch.reset();
                        }
            });
            report_progress(ctx,
                            (double(s0) + double(n) * wave_end / tile_count) / double(ctx.spp));
        }
        return n;
    });

    // Splats are estimates per sample of every pixel: divide by the samples per pixel.
    RenderResult result;
    result.spp = int(done);
    const double scale = 1.0 / double(std::max<int64_t>(done, 1));
    sums.add_to_film(ctx.film, scale);
    for (size_t k = 0; k < extra.size(); ++k)
        result.debug_images[extra[k]] = sums.image(int(k), scale);
    return result;
}

}  // namespace ml
