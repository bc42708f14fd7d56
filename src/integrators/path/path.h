// Unidirectional path tracing with next-event estimation, multiple importance sampling of light
// and BSDF samples (power heuristic), power-based light selection and Russian roulette: the
// unbiased reference every other integrator is checked against.
#pragma once

#include "lights/light_sampler.h"
#include "render/integrator.h"
#include "render/settings.h"

namespace ml {

class PathIntegrator final : public PixelIntegrator {
public:
    explicit PathIntegrator(const Settings& settings);
    std::string name() const override { return "path"; }
    void prepare(const Scene& scene) override;
    RGB li(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
           Point2i pixel) const override;

private:
    int m_max_depth;
    int m_rr_depth;
    std::string m_light_sampler_name;
    std::unique_ptr<LightSampler> m_light_sampler;
};

}  // namespace ml
