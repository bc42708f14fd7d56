#include "render/splat_integrator.h"

#include <atomic>

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
    // Samples per pixel each tile has taken: a stop (Ctrl-C) leaves some tiles a round ahead.
    std::vector<int64_t> tile_units(size_t(tile_count), 0);

    // A checkpoint keeps the splat sums and the tiles' progress; a resumed render starts there.
    Checkpoint* checkpoint = ctx.checkpoint;
    RoundPlan plan;
    plan.total = ctx.spp;
    plan.untimed_most = kUntimedRoundSamples;
    if (checkpoint) {
        if (checkpoint->resuming()) {
            const nlohmann::json& state = checkpoint->integrator_state();
            for (int k = -1; k + 1 < sums.images(); ++k)
                sums.set_sums(k, from_binary<double>(state.at("sums").at(size_t(k + 1)),
                                                     size_t(w) * size_t(h) * 3));
            tile_units = from_binary<int64_t>(state.at("tiles"), size_t(tile_count));
            plan.done = std::min<int64_t>(checkpoint->units(), ctx.spp);
        }
        checkpoint->set_state([&] {
            nlohmann::json all = nlohmann::json::array();
            for (int k = -1; k + 1 < sums.images(); ++k) all.push_back(to_binary(sums.sums(k)));
            return nlohmann::json{{"sums", all}, {"tiles", to_binary(tile_units)}};
        });
        plan.most = 1;
        plan.after_round = [&](int64_t done) { checkpoint->round_done(done, ctx.elapsed()); };
    }

    // Rounds of samples [s0, s1) per pixel, each in waves of tiles.
    const int64_t done = run_rounds(ctx, plan, [&](int64_t s0, int64_t want) {
        const int64_t n = std::min<int64_t>(want, ctx.spp - s0), s1 = s0 + n;
        std::atomic<bool> cut_short{false};
        for (int wave = 0; wave < tile_count; wave += kTilesPerWave) {
            int wave_end = std::min(tile_count, wave + kTilesPerWave);
            run_and_merge(wave, wave_end, lists, sums, [&](int64_t tile, SplatList& splats) {
                // Across ranks, each renders the tiles it owns (their camera samples and the
                // light paths they start); the others' splats reach rank 0 in the films' sum.
                if (!ctx.owns(tile)) return;
                // A stop (Ctrl-C) starts no tile; the round then does not count.
                if (ctx.cancelled()) {
                    cut_short = true;
                    return;
                }
                int64_t& from = tile_units[size_t(tile)];
                ThreadState& ts = states.local();
                int x0 = int(tile % tiles_x) * kTile, y0 = int(tile / tiles_x) * kTile;
                for (int y = y0; y < std::min(h, y0 + kTile); ++y)
                    for (int x = x0; x < std::min(w, x0 + kTile); ++x)
                        for (int64_t s = std::max(s0, from); s < s1; ++s) {
                            ts.sampler->start_pixel_sample(Point2i{x, y}, int(s));
                            render_sample(ctx, Point2i{x, y}, int(s), *ts.sampler, ts.scratch,
                                          splats);
                            ts.scratch.reset();
                        }
                from = std::max(from, s1);
            });
            report_progress(ctx,
                            (double(s0) + double(n) * wave_end / tile_count) / double(ctx.spp));
        }
        return cut_short ? int64_t(0) : n;
    });
    if (checkpoint) checkpoint->save(done, ctx.elapsed());

    // Splats are estimates per sample of every pixel: divide by the samples per pixel, or where
    // a stop left tiles apart, by the light paths traced per pixel.
    RenderResult result;
    result.spp = int(done);
    double scale = 1.0 / double(std::max<int64_t>(done, 1));
    int64_t behind = 0, samples = 0;
    for (int t = 0; t < tile_count; ++t) {
        if (!ctx.owns(t)) continue;
        const int x0 = (t % tiles_x) * kTile, y0 = (t / tiles_x) * kTile;
        const int64_t pixels =
            int64_t(std::min(w, x0 + kTile) - x0) * (std::min(h, y0 + kTile) - y0);
        behind += tile_units[size_t(t)] != done;
        samples += pixels * tile_units[size_t(t)];
    }
    if (ctx.ranks() > 1) behind = ctx.world->all_sum(behind), samples = ctx.world->all_sum(samples);
    if (behind > 0 && samples > 0) scale = double(w) * double(h) / double(samples);
    sums.add_to_film(ctx.film, scale);
    for (size_t k = 0; k < extra.size(); ++k)
        result.debug_images[extra[k]] = sums.image(int(k), scale);
    return result;
}

}  // namespace ml
