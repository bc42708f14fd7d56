#include "core/parallel.h"
#include "core/stats.h"
#include "render/integrator.h"
#include "render/render_loop.h"

namespace ml {

namespace {

struct ThreadState {
    std::unique_ptr<Sampler> sampler;
    ScratchBuffer scratch;
};

}  // namespace

Ray pixel_sample_ray(const RenderContext& ctx, Point2i pixel, Sampler& sampler,
                     float* filter_weight, float* camera_weight) {
    FilterSample fs = ctx.filter.sample(sampler.get_pixel_2d());
    CameraSample cs;
    cs.p_film = Vec2(float(pixel.x) + 0.5f + fs.p.x, float(pixel.y) + 0.5f + fs.p.y);
    cs.time = sampler.get_1d();
    cs.p_lens = sampler.get_2d();
    stats::count_camera_ray();
    *filter_weight = fs.weight;
    return ctx.camera.generate_ray(cs, camera_weight);
}

RenderResult PixelIntegrator::render(const RenderContext& ctx) {
    prepare(ctx.scene);
    before_pixels(ctx);
    ThreadLocal<ThreadState> states([&] {
        return ThreadState{ctx.sampler.clone(), ScratchBuffer()};
    });
    RenderResult result;
    auto shade = [&](Point2i pixel, int64_t s0, int64_t s1) {
        ThreadState& ts = states.local();
        Sampler& sampler = *ts.sampler;
        for (int64_t s = s0; s < s1; ++s) {
            sampler.start_pixel_sample(pixel, int(s));
            float weight, camera_weight;
            Ray ray = pixel_sample_ray(ctx, pixel, sampler, &weight, &camera_weight);
            // A vignetted ray (weight 0) is a sample of black, as pbrt-v4 counts it.
            RGB L = camera_weight > 0
                        ? li(ray, ctx.scene, sampler, ts.scratch, pixel) * camera_weight
                        : RGB();
            ctx.film.add_sample(pixel, L, weight);
            ts.scratch.reset();
        }
    };
    const int64_t block = block_samples();
    result.spp = int(block > 0 ? render_pixel_blocks(
                                     ctx, ctx.spp, block, [&](int64_t b) { begin_block(ctx, b); },
                                     shade, ctx.checkpoint)
                               : render_pixels(ctx, ctx.spp, shade, ctx.checkpoint));
    if (ctx.checkpoint) ctx.checkpoint->save(result.spp, ctx.elapsed());
    return result;
}

}  // namespace ml
