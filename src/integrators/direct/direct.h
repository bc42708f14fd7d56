// Distribution ray tracing (Cook et al. 1984): direct light from every light with one MIS
// sample each (area lights give soft shadows), glossy and specular surfaces followed along
// one BSDF-sampled ray (glossy reflection, refraction), diffuse surfaces end the path. No
// diffuse interreflection: the image is direct lighting seen directly or through
// glossy/specular chains.
#pragma once

#include "render/integrator.h"
#include "render/settings.h"

namespace ml {

class DirectIntegrator final : public PixelIntegrator {
public:
    explicit DirectIntegrator(const Settings& settings);
    std::string name() const override { return "direct"; }
    RGB li(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
           Point2i pixel) const override;

private:
    int m_max_depth;
};

}  // namespace ml
