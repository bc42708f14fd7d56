// Whitted ray tracing: perfect mirror reflection and refraction followed recursively, direct
// light at every other surface (point, spot and distant lights exactly; area and environment
// lights with one light sample each), no glossy or diffuse interreflection.
#pragma once

#include "render/integrator.h"
#include "render/settings.h"

namespace ml {

class WhittedIntegrator final : public PixelIntegrator {
public:
    explicit WhittedIntegrator(const Settings& settings);
    std::string name() const override { return "whitted"; }
    RGB li(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
           Point2i pixel) const override;

private:
    int m_max_depth;
};

}  // namespace ml
