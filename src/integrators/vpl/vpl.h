// Instant radiosity, brute force: every point light (the scene's lights turned into point lights,
// plus the VPLs that light paths deposit) shades every gather point with a shadow ray each. It is
// O(lights) per pixel: the exact reference Lightcuts is measured against on the same set.
// --stats gains "vpl": {"vpl_lights": the VPLs (point lights), "lighting": those of them that
// lit some gather point of the render}.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "manylight/many_lights.h"
#include "render/integrator.h"
#include "render/settings.h"

namespace ml {

class VplIntegrator final : public PixelIntegrator {
public:
    explicit VplIntegrator(const Settings& settings);
    std::string name() const override { return "vpl"; }
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
    ManyLightSettings m_settings;
    PointLightSet m_set;
    SampledDirectLight m_direct;
    // Per point light: whether it lit some gather point of the render (unoccluded contribution
    // > 0), for --stats' vpl.lighting: the share of the VPLs that light the image.
    mutable std::unique_ptr<std::atomic<uint8_t>[]> m_lit;
};

}  // namespace ml
