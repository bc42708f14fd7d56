// Bidirectional path tracing (Veach and Guibas 1995; Veach's thesis, chapter 10): a camera
// subpath and a light subpath per pixel sample, joined by every (s, t) strategy, each weighted by
// the power heuristic over the strategies that could have made the same path. Strategies with
// t = 1 land elsewhere on the film and are splatted.
//
// Settings: maxdepth (5; bounces, as path's), lightsampler ("power" or "uniform"), regularize
// (accepted for pbrt-v4 scenes; no effect), strategy_images (false): when true, one more image
// per strategy, bdpt_s{S}_t{T}, written beside the output as OUT.bdpt_s{S}_t{T}.exr, holding
// that strategy's MIS-weighted contribution (they add up to the image); pbrt-v4's
// visualizestrategies and visualizeweights ask for the same images.
#pragma once

#include <memory>

#include "bidir/path_vertex.h"
#include "render/settings.h"
#include "render/splat_integrator.h"

namespace ml {

class BdptIntegrator final : public SplatIntegrator {
public:
    explicit BdptIntegrator(const Settings& settings);
    ~BdptIntegrator() override;
    std::string name() const override { return "bdpt"; }

    // The index of strategy (s, t) among the strategy images (t >= 1, (s, t) != (1, 1)).
    static int strategy_index(int s, int t);
    static int strategy_count(int max_depth) { return (1 + max_depth) * (6 + max_depth) / 2; }

protected:
    void prepare(const RenderContext& ctx) override;
    void render_sample(const RenderContext& ctx, Point2i pixel, int index, Sampler& sampler,
                       ScratchBuffer& scratch, SplatList& splats) const override;
    std::vector<std::string> extra_images() const override;

private:
    int m_max_depth;
    bool m_strategy_images;
    std::string m_light_sampler_name;
    std::unique_ptr<LightSampler> m_light_sampler;
    std::unique_ptr<BdptScene> m_ctx;
};

}  // namespace ml
