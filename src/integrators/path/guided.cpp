// Guided path tracing's render: passes of 1, 2, 4... samples per pixel. Each pass is traced with
// the guide the passes before it trained (none in the first: plain path tracing) while it trains
// the next one; each pass is an unbiased image of its own, and the passes are combined at the end
// (PathIntegrator::PassWeights).
//
// The last pass takes what is left, without training: of the sample budget, once what is left
// is less than three times the pass (so that the next pass would not double); under a time
// limit, once the time left is less than three times what the pass would take at the cost per
// sample of the pass before (training, the tree's refinement included, counts in the limit).
#include <cmath>
#include <vector>

#include "core/parallel.h"
#include "integrators/path/path.h"
#include "render/render_loop.h"

namespace ml {

namespace {

struct ThreadState {
    std::unique_ptr<Sampler> sampler;
    ScratchBuffer scratch;
};

// One pass's sums at one pixel: filter-weighted radiance, and the luminance's first two
// moments for the pass's variance.
struct PassPixel {
    double rgb[3] = {0, 0, 0};
    double weight = 0;
    double y = 0, y2 = 0;
    int64_t n = 0;
};

struct Pass {
    int64_t first_sample = 0, samples = 0;
    double seconds = 0;
    std::vector<PassPixel> pixels;
    // The variance of the pass's pixel estimates (their mean over the pixels), estimated from
    // the samples' spread; negative where a pixel has fewer than two samples.
    double variance() const {
        double sum = 0;
        for (const PassPixel& px : pixels) {
            if (px.n < 2) return -1;
            const double n = double(px.n);
            sum += std::max(0.0, px.y2 - px.y * px.y / n) / (n - 1) / n;
        }
        return sum / double(pixels.size());
    }
};

}  // namespace

RenderResult PathIntegrator::render_guided(const RenderContext& ctx) {
    RenderResult result;
    if (ctx.ranks() > 1) {
        result = PixelIntegrator::render(ctx);
        result.warnings.push_back("path: guiding runs in one process; rendered without it");
        return result;
    }
    prepare(ctx.scene);
    const int w = ctx.film.width(), h = ctx.film.height();
    const float clamp = ctx.film.splat_clamp();
    SDTree tree(ctx.scene.bounds());
    ThreadLocal<ThreadState> states([&] {
        return ThreadState{ctx.sampler.clone(), ScratchBuffer()};
    });

    std::vector<Pass> passes;
    double refine_seconds = 0;
    int64_t done = 0;
    for (int k = 0; done < ctx.spp; ++k) {
        // 1. The pass's size, and whether it is the last.
        int64_t n = std::min<int64_t>(int64_t(1) << std::min(k, 40), ctx.spp - done);
        bool last = ctx.spp - done - n < 2 * n;
        if (ctx.time_limit > 0 && !passes.empty()) {
            const Pass& before = passes.back();
            const double per_sample = before.seconds / double(before.samples);
            if (ctx.time_limit - ctx.elapsed() < 3 * double(n) * per_sample) last = true;
        }
        if (last) n = ctx.spp - done;

        // 2. Trace it, guided by what the passes before learned, training the next guide.
        PathTraceOptions options = m_options;
        options.guide = &tree;  // (the first pass finds no distribution in it: plain paths)
        options.guide_record = !last;
        Pass pass;
        pass.first_sample = done;
        pass.pixels.resize(size_t(w) * h);
        const double start = ctx.elapsed();
        if (ctx.progress && !(ctx.time_limit > 0))
            ctx.progress->set_span(double(done) / double(ctx.spp),
                                   double(done + n) / double(ctx.spp));
        const int64_t ran = render_pixels(ctx, n, [&](Point2i pixel, int64_t s0, int64_t s1) {
            ThreadState& ts = states.local();
            Sampler& sampler = *ts.sampler;
            PassPixel& px = pass.pixels[size_t(pixel.y) * w + pixel.x];
            for (int64_t s = s0; s < s1; ++s) {
                sampler.start_pixel_sample(pixel, int(pass.first_sample + s));
                float weight, camera_weight;
                Ray ray = pixel_sample_ray(ctx, pixel, sampler, &weight, &camera_weight);
                RGB L = camera_weight > 0
                            ? trace(ray, ctx.scene, sampler, ts.scratch, options) * camera_weight
                            : RGB();
                ts.scratch.reset();
                if (!L.is_finite()) {
                    ctx.film.add_sample(pixel, L, weight);  // dropped there, and counted
                    continue;
                }
                // The film's clamp, per sample (the film sees only the passes' means).
                const float m = L.max_component();
                if (m > clamp) L *= clamp / m;
                for (int c = 0; c < 3; ++c) px.rgb[c] += double(L[c]) * weight;
                px.weight += weight;
                const double y = (double(L.r) + L.g + L.b) / 3 * weight;
                px.y += y;
                px.y2 += y * y;
                ++px.n;
            }
        });
        pass.samples = ran;
        done += ran;
        // 3. What this pass trained guides the next.
        const bool more = !last && ran == n && done < ctx.spp;
        if (more) {
            const double refine_start = ctx.elapsed();
            tree.refine(double(ran) * w * h);
            refine_seconds += ctx.elapsed() - refine_start;
        }
        pass.seconds = ctx.elapsed() - start;
        passes.push_back(std::move(pass));
        if (!more) break;
    }
    if (ctx.progress) ctx.progress->set_span(0, 1);

    // 4. The image: each pass's pixel means, weighted.
    std::vector<double> pass_weight(passes.size(), 1.0);
    nlohmann::json pass_stats = nlohmann::json::array();
    for (size_t k = 0; k < passes.size(); ++k) {
        const double variance = passes[k].variance();
        if (m_pass_weights == PassWeights::Variance)
            pass_weight[k] = variance > 0 ? 1 / variance : 0;
        else if (m_pass_weights == PassWeights::Last)
            pass_weight[k] = k + 1 == passes.size() ? 1 : 0;
        pass_stats.push_back({{"spp", passes[k].samples},
                              {"seconds", passes[k].seconds},
                              {"variance", variance},
                              {"weight", pass_weight[k]}});
    }
    // A pixel the weighted passes left without samples (a pass the time limit cut short) takes
    // every sample it has alike.
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * w + x;
            bool any = false;
            for (size_t k = 0; k < passes.size(); ++k)
                any |= pass_weight[k] > 0 && passes[k].pixels[i].n > 0;
            for (size_t k = 0; k < passes.size(); ++k) {
                const PassPixel& px = passes[k].pixels[i];
                if (px.n == 0 || px.weight == 0 || (any && pass_weight[k] == 0)) continue;
                const RGB mean(float(px.rgb[0] / px.weight), float(px.rgb[1] / px.weight),
                               float(px.rgb[2] / px.weight));
                const bool by_samples = !any || m_pass_weights == PassWeights::Samples;
                ctx.film.add_sample({x, y}, mean, float(by_samples ? px.weight : pass_weight[k]));
            }
        }
    result.spp = int(done);
    result.stats["guiding"] = {
        {"passes", pass_stats}, {"regions", tree.regions()}, {"refine_seconds", refine_seconds}};
    return result;
}

}  // namespace ml
