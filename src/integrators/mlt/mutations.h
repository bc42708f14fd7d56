// Veach's mutations of a whole path (Veach's thesis, section 11.4), each proposing a path and
// the acceptance probability that keeps the chain's distribution proportional to the luminance of
// f(x):
// - bidirectional: the whole path replaced by a new one of the same depth made by BDPT with a
//   strategy chosen uniformly (an independence proposal of density q: accept by W = f / q);
// - lens perturbation: for paths E S* D (D|L) ..., the film position moved by a small offset
//   (exponentially distributed between 0.1 pixel and 5% of the image), the specular chain from
//   the lens retraced with the same lobes, and the first non-specular vertex joined to the
//   unchanged rest;
// - caustic perturbation: for paths E D S+ (D|L) ..., the direction leaving the first
//   non-specular vertex on the light side turned by a small angle, the specular chain retraced
//   towards the camera, and the new visible vertex joined to the lens point.
// Perturbations keep the lobe (reflection or transmission) of every specular vertex and the lens
// point. Every random number comes from the Sampler.
#pragma once

#include <optional>

#include "core/scratch.h"
#include "integrators/mlt/path_space.h"
#include "sampling/sampler.h"

namespace ml {

struct Proposal {
    MltPath y;
    float accept = 0;  // acceptance probability
    RGB colour;        // f(y) / luminance(f(y))
    RGB W;             // f(y) / q(y) when known (bidirectional proposals), else black
};

// Whether a path can be made by BDPT here: its light is an area, point or spot light, and no
// vertex scattered through the delta lobe of a BSDF that also has others.
bool mlt_supported(const MltPath& x);

// Re-evaluates the BSDFs of y's surfaces into `scratch` (paths outlive the buffer they were made
// in).
void rebind_bsdfs(MltPath& y, ScratchBuffer& scratch);

// A BDPT path of exactly `depth` bounces: nullopt if the strategy made nothing. The strategy
// (its count of light vertices) goes to `strategy`.
std::optional<MltPath> sample_bdpt_path(const BdptScene& ctx, Sampler& sampler, int depth,
                                        ScratchBuffer& scratch, int* strategy = nullptr);

// A bidirectional proposal's path and its f / q, or black where q does not count the strategy
// that made it (path_over_bdpt_density): such proposals are refused.
RGB proposal_weight(const BdptScene& ctx, const MltPath& y, int strategy);

// The three mutations of current state x (its W when known: black to recompute). nullopt when
// the mutation does not apply to x or its proposal has no contribution (rejection).
std::optional<Proposal> mutate_bidirectional(const BdptScene& ctx, const MltPath& x, RGB* Wx,
                                             Sampler& sampler, ScratchBuffer& scratch);
std::optional<Proposal> mutate_lens(const BdptScene& ctx, const MltPath& x, Sampler& sampler,
                                    ScratchBuffer& scratch);
// Coherent MLT's lens perturbation (Segovia et al. 2007): multiple-try Metropolis with four tries
// whose camera rays are traced as one Embree packet, weights pi(y) (lambda = 1 / T for the
// symmetric offsets), and three reference tries from the picked one (plus x); accepted with
// min(1, sum of weights / sum of references).
std::optional<Proposal> mutate_lens_multiple_try(const BdptScene& ctx, const MltPath& x,
                                                 Sampler& sampler, ScratchBuffer& scratch);
std::optional<Proposal> mutate_caustic(const BdptScene& ctx, const MltPath& x, Sampler& sampler,
                                       ScratchBuffer& scratch);

}  // namespace ml
