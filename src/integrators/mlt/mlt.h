// Metropolis light transport in path space (Veach and Guibas 1997; Veach's thesis, chapter 11),
// with bidirectional mutations, lens perturbations and caustic perturbations (mutations.h). As
// pbrt-v4's MLT, chains keep one depth: a bootstrap of BDPT paths per depth estimates the image's
// brightness b and picks the chains' starting paths in proportion to their luminance; each
// mutation splats the proposed and the current path by their expected shares. `--spp` is
// mutations per pixel; under `--time-limit` the chains run in segments until the time is spent
// (the bootstrap excluded).
//
// The bidirectional mutation (bidir_mutation.h) is Veach's: it deletes the subpath between two
// kept vertices, short deletions the likeliest (p_d = 0.5 for one vertex, then 2^-k_d over the
// k_d deleted edges; the lens and the light may go too), and regrows as many vertices as it
// deleted, l_E from the eye side and l_L from the light side (split uniformly), by BDPT's random
// walks from the kept ends, joined by one visibility-tested connection. It is accepted with
// min(1, f(y) T(y -> x) / (f(x) T(x -> y))), where T sums the added vertices' densities over
// every split (BDPT's strategy densities restricted to the deleted subpath; the kept vertices'
// factors cancel). Deleting everything (probability 2^-(n+1) / sum for n vertices) is the old
// whole-path proposal (a new BDPT path of the same depth, accepted by W = f / q), which keeps the
// chain ergodic; that alone is too rare: a path such as E S S D S S D L can change only its last
// vertices by partial deletions (the others would connect at a specular vertex) and no
// perturbation applies to it, so its chain stays in one pixel for thousands of mutations. Half
// of the bidirectional mutations (whole_prob) therefore replace the whole path;
// `bidirectional=whole` makes them all do so. Partial proposals are accepted about three times
// as often as whole ones, but on veach-bidir and cornell-box (256x256, 128 mutations per pixel)
// the mix is no better than whole replacement alone (relMSE +1% and +6%).
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
// bidirectional_prob (0.3), lens_prob (0.4); the rest of the mutations are caustic perturbations;
// bidirectional (partial | whole; partial), whole_prob (0.5: with partial, the share of
// bidirectional mutations that replace the whole path). `--stats` reports each mutation's
// acceptance rate.
// Lights: area, point and spot (environment and distant lights are refused). Participating media
// (mlt, not cmlt): medium vertices placed by the majorant's collision process, the edges'
// transmittances in f (path_media.h); emitting media are refused. Splats are spread by the pixel
// filter: mlt draws camera rays over the film and the margin a border pixel's filter reaches
// past its edge (PerspectiveCamera::raster_point), so that the border pixels get what camera
// samples there give them; cmlt keeps its paths on the film, and its border pixels lose the part
// of the splats that falls off it (about 1% of a 48x36 image with the default Gaussian).
#pragma once

#include "render/integrator.h"
#include "render/settings.h"

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
    bool m_partial;      // bidirectional=partial: Veach's deletion and regrowth of a subpath
    float m_whole_prob;  // with partial: the share of whole-path bidirectional proposals
    bool m_coherent;
};

}  // namespace ml
