// Unidirectional path tracing with next-event estimation, multiple importance sampling of light
// and BSDF samples (power heuristic), power-based light selection and Russian roulette: the
// unbiased reference every other integrator is checked against. With path.guiding=on it learns
// where light comes from while it renders (guided.cpp).
#pragma once

#include "lights/light_sampler.h"
#include "render/integrator.h"
#include "render/settings.h"
#include "transport/path_tracer.h"

namespace ml {

class PathIntegrator final : public PixelIntegrator {
public:
    explicit PathIntegrator(const Settings& settings);
    std::string name() const override { return "path"; }
    RenderResult render(const RenderContext& ctx) override;
    // A guided render's state is its guide, which a checkpoint does not hold.
    bool can_checkpoint() const override { return !m_guiding; }
    void prepare(const Scene& scene) override;
    RGB li(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
           Point2i pixel) const override;

private:
    // How the passes of a guided render make the image: weighted by the inverse of their
    // variance, every sample alike, or the last pass alone.
    enum class PassWeights { Variance, Samples, Last };
    RGB trace(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
              const PathTraceOptions& options) const;
    RenderResult render_guided(const RenderContext& ctx);  // guided.cpp

    int m_max_depth;
    int m_rr_depth;
    std::string m_light_sampler_name;
    std::unique_ptr<LightSampler> m_light_sampler;
    bool m_guiding = false;
    PassWeights m_pass_weights = PassWeights::Variance;
    PathTraceOptions m_options;
};

}  // namespace ml
