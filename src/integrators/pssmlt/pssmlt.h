// Primary-sample-space Metropolis light transport (Kelemen et al. 2002) over the bidirectional
// estimator, as in pbrt-v4's MLTIntegrator: a bootstrap estimates the image's brightness and
// seeds the chains; chains mutate primary samples by small and large steps and splat the
// expected value of every proposal. The budget is mutations per pixel (--spp) or a time limit.
//
// Settings (--set pssmlt.KEY=VALUE): maxdepth (5), large_step_prob (0.3), sigma (0.01, the small
// steps' standard deviation), bootstrap (100000 paths per depth), chains (1000), estimator
// ("bdpt", or "path" for the path tracer). The image is the same for a seed whatever the thread
// count: each chain's randomness is its own, and splats are summed in chain order.
#pragma once

#include "integrators/pssmlt/bootstrap.h"
#include "render/integrator.h"
#include "render/settings.h"

namespace ml {

class PssmltIntegrator final : public Integrator {
public:
    explicit PssmltIntegrator(const Settings& settings);
    std::string name() const override { return "pssmlt"; }
    RenderResult render(const RenderContext& ctx) override;
    // Saves the chains' states and the splat sums: a resumed render goes on exactly.
    bool can_checkpoint() const override { return true; }

private:
    int m_max_depth;
    int m_bootstrap;
    int m_chains;
    MltParams m_params;  // the seed comes from the render's sampler
    std::string m_estimator;
};

}  // namespace ml
