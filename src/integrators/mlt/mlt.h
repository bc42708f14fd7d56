// Metropolis light transport in path space (Veach and Guibas 1997; Veach's thesis, chapter 11),
// with bidirectional mutations that replace the whole path by a BDPT path of the same depth, lens
// perturbations and caustic perturbations (mutations.h). As pbrt-v4's MLT, chains keep one
// depth: a bootstrap of BDPT paths per depth estimates the image's brightness b and picks the
// chains' starting paths in proportion to their luminance; each mutation splats the proposed and
// the current path by their expected shares. `--spp` is mutations per pixel; under
// `--time-limit` the chains run in segments until the time is spent (the bootstrap excluded).
//
// `cmlt` is the same with coherent MLT's lens perturbation (Segovia et al. 2007, coherent.h):
// multiple-try Metropolis over four perturbations of the film position, whose camera rays, each
// bounce of their specular chains and their connection rays are traced as Embree packets of four,
// and so are the three reference tries; every try is splatted by its expected value. A step
// costs about seven lens perturbations of mlt for four splats, and packets of such spread rays
// are no faster than single rays here: cmlt needs about 1.6x (cornell-box) to 2.8x (veach-bidir)
// mlt's time for mlt's relMSE at 30 s (256x256, two threads).
//
// Settings (mlt.KEY or cmlt.KEY): maxdepth (5), bootstrap (100000 paths per depth), chains (256),
// bidirectional_prob (0.3), lens_prob (0.4); the rest of the mutations are caustic perturbations.
// Lights: area, point and spot (environment and distant lights are refused). Pixel filter: box
// (splats).
#pragma once

#include "integrators/integrator.h"
#include "integrators/settings.h"

namespace ml {

class MltIntegrator final : public Integrator {
public:
    // `coherent`: the multiple-try, packet-traced lens perturbation (cmlt).
    MltIntegrator(const Settings& settings, bool coherent);
    std::string name() const override { return m_coherent ? "cmlt" : "mlt"; }
    RenderResult render(const RenderContext& ctx) override;

private:
    int m_max_depth, m_bootstrap, m_chains;
    float m_bidirectional_prob, m_lens_prob;
    bool m_coherent;
};

}  // namespace ml
