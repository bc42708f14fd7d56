// Metropolis light transport in path space (Veach and Guibas 1997; Veach's thesis, chapter 11),
// with bidirectional mutations that replace the whole path by a BDPT path of the same depth, lens
// perturbations and caustic perturbations (mutations.h). As pbrt-v4's MLT, chains keep one
// depth: a bootstrap of BDPT paths per depth estimates the image's brightness b and picks the
// chains' starting paths in proportion to their luminance; each mutation splats the proposed and
// the current path by their expected shares. `--spp` is mutations per pixel; under
// `--time-limit` the chains run in segments until the time is spent (the bootstrap excluded).
//
// Settings: maxdepth (5), bootstrap (100000 paths per depth), chains (256), bidirectional_prob
// (0.3), lens_prob (0.4); the rest of the mutations are caustic perturbations. Lights: area,
// point and spot (environment and distant lights are refused). Pixel filter: box (splats).
#pragma once

#include "integrators/integrator.h"
#include "integrators/settings.h"

namespace ml {

class MltIntegrator final : public Integrator {
public:
    explicit MltIntegrator(const Settings& settings);
    std::string name() const override { return "mlt"; }
    RenderResult render(const RenderContext& ctx) override;

private:
    int m_max_depth, m_bootstrap, m_chains;
    float m_bidirectional_prob, m_lens_prob;
};

}  // namespace ml
