// Stochastic Lightcuts (Yuksel 2019): the same point lights and light tree as `lightcuts`; at
// each gather point a cut of at most `stochasticlightcuts.cut` clusters is chosen by Lightcuts'
// error bounds (always splitting the cluster of largest bound, with no error threshold), then
// each cluster is shaded by one of its lights, drawn by descending its subtree with each child
// taken in proportion to its importance at the point (manylight/cluster_sampling.h), and its
// shadow ray: the light's contribution over its probability. Every light that can give the
// point light has a non-zero probability, so the estimate's expectation is exactly the `vpl`
// sum over the same lights (with the same vpl.clamp), in every channel, with no error bound to
// meet. Clusters whose bound or importance is zero give nothing and are left out of the cut (a
// spot light's importance follows its cone, cluster_sampling.h); single lights in the cut are
// shaded exactly.
#pragma once

#include <atomic>
#include <vector>

#include "manylight/cluster_sampling.h"
#include "manylight/gather.h"
#include "manylight/light_tree.h"
#include "manylight/many_lights.h"
#include "render/integrator.h"
#include "render/settings.h"

namespace ml {

class StochasticLightcutsIntegrator final : public PixelIntegrator {
public:
    explicit StochasticLightcutsIntegrator(const Settings& settings);
    std::string name() const override { return "stochasticlightcuts"; }
    void prepare(const Scene& scene) override;
    RGB li(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
           Point2i pixel) const override;
    RenderResult render(const RenderContext& ctx) override;
    // vpl.sets=pass: a new VPL set every kPixelPassSamples samples (many_lights.h).
    int64_t block_samples() const override {
        return m_settings.set_per_pass ? kPixelPassSamples : 0;
    }
    void begin_block(const RenderContext& ctx, int64_t block) override {
        if (m_settings.use_set(block, m_set)) prepare(ctx.scene);
    }

private:
    // The radiance the point lights give at g (times g.beta); *cut_size receives the number of
    // clusters and single lights shaded. Draws one sampler dimension per cluster.
    RGB shade(const Scene& scene, const GatherPoint& g, Sampler& sampler, int* cut_size) const;

    ManyLightSettings m_settings;
    int m_cut = 16;  // defaults: bench/RESULTS.md, "Issue 13, stochastic lightcuts"
    PointLightSet m_set;
    SampledDirectLight m_direct;
    LightTree m_tree;
    ClusterSampler m_sampler;  // over m_tree
    double m_tree_seconds = 0;
    mutable std::atomic<uint64_t> m_cut_sum{0}, m_gather_points{0};
};

}  // namespace ml
