// Light tracing (particle tracing, Arvo 1986; Veach's thesis, section 10.2, strategy t = 1):
// paths start on the lights, and every vertex is joined to a point on the lens and splatted to
// wherever it lands on the film. One light path per pixel sample (the pixel only seeds the
// sampler), so `--spp N` traces N x width x height light paths.
//
// What it cannot see: light reaching the lens only through delta lobes (a mirror or glass seen
// by the camera), point lights seen directly (a pinhole cannot be hit), and infinite lights seen
// directly. Settings: maxdepth (5; bounces, as path's), lightsampler ("power" or "uniform").
//
// In a scene with participating media, the light path scatters in them too (delta tracking, as
// `path`), and each vertex reaches the lens through the media's transmittance
// (lighttracer_media.cpp). Media that emit are refused: no light path starts in them.
#pragma once

#include <memory>

#include "bidir/path_vertex.h"
#include "render/settings.h"
#include "render/splat_integrator.h"

namespace ml {

class LightTracerIntegrator final : public SplatIntegrator {
public:
    explicit LightTracerIntegrator(const Settings& settings);
    ~LightTracerIntegrator() override;
    std::string name() const override { return "lighttracer"; }

protected:
    void prepare(const RenderContext& ctx) override;
    void render_sample(const RenderContext& ctx, Point2i pixel, int index, Sampler& sampler,
                       ScratchBuffer& scratch, SplatList& splats) const override;

private:
    // One light path through participating media, each vertex joined to the lens.
    void render_sample_media(const RenderContext& ctx, Sampler& sampler, ScratchBuffer& scratch,
                             SplatList& splats) const;

    int m_max_depth;
    bool m_media = false;  // the scene has participating media
    std::string m_light_sampler_name;
    std::unique_ptr<LightSampler> m_light_sampler;
    std::unique_ptr<BdptScene> m_ctx;
};

}  // namespace ml
