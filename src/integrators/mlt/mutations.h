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

#include <array>
#include <optional>

#include "core/scratch.h"
#include "integrators/mlt/path_space.h"
#include "sampling/sampler.h"

namespace ml {

// A splat on the film at a raster position.
struct TrySplat {
    Vec2 p_raster;
    RGB v;
};

struct Proposal {
    MltPath y;
    float accept = 0;  // acceptance probability
    RGB colour;        // f(y) / luminance(f(y))
    RGB W;             // f(y) / q(y) when known (bidirectional proposals), else black
    // Multiple-try proposals (coherent.h) splat every try by its expected value instead of y by
    // `accept`: n_tries splats, which take `tries_share` of the current path's splat.
    std::array<TrySplat, 8> tries;
    int n_tries = 0;
    float tries_share = 0;
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
std::optional<Proposal> mutate_caustic(const BdptScene& ctx, const MltPath& x, Sampler& sampler,
                                       ScratchBuffer& scratch);

// Shared with the multiple-try lens perturbation (coherent.h): the first non-specular vertex j
// of a path E S* D (D|L) ... (-1 for other paths), the largest film offset, a film offset from
// two uniform numbers, and whether vertex k of x refracts (its neighbours lie on opposite sides).
int lens_vertex(const MltPath& x);
float lens_offset_max(const PerspectiveCamera& cam);
Vec2 lens_offset(const PerspectiveCamera& cam, float u_size, float u_angle);
bool transmits(const MltPath& x, int k);

}  // namespace ml
