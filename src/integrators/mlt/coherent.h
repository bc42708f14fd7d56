// Coherent MLT's lens perturbation (Segovia, Iehl and Péroche 2007): multiple-try Metropolis
// (Liu, Liang and Wong 2000) over perturbations of the film position of paths E S* D (D|L) ...,
// whose rays are traced together as Embree packets.
//
// One step, from the current path x with its first non-specular vertex j:
// 1. kCoherentTries tries y_i, each x's film position moved by an offset of the lens
//    perturbation (mutations.h) and its specular chain retraced to a new vertex j joined to the
//    old j + 1: the camera rays, each bounce of the chains and the connection rays are one
//    packet each (lanes of tries that fail drop out). Weights w(y_i) = pi(y_i), the lens
//    target's luminance (lambda = 1 / T for the symmetric offsets).
// 2. y = y_J picked in proportion to w; kCoherentTries - 1 reference tries from y, traced the
//    same way, and x itself make the reference set.
// 3. The chain moves to y with probability min(1, sum w(y_i) / sum w(x*_i)).
// 4. Expected values: every try y_i is splatted with share min(1, pi(y_i) / pi(x)) / k of the
//    step's unit splat, and x with the rest. Each term is the expected value of a Metropolis
//    proposal of y_i from x with a symmetric T, so the splats are unbiased whatever the chain's
//    move (Segovia's splat of the whole family in proportion to f is not: it blurs the image at
//    the scale of the offsets).
// Every random number comes from the Sampler; the tries' paths live in per-thread buffers and
// their BSDFs in `scratch`.
#pragma once

#include <optional>

#include "integrators/mlt/mutations.h"

namespace ml {

// Tries per step: one packet of four rays.
constexpr int kCoherentTries = 4;

// nullopt when the lens perturbation does not apply to x or no try has a contribution (x then
// keeps its whole splat). Otherwise the picked try as y with the chain's acceptance probability,
// and every try's expected-value splat in `tries`.
std::optional<Proposal> mutate_lens_multiple_try(const BdptScene& ctx, const MltPath& x,
                                                 Sampler& sampler, ScratchBuffer& scratch);

}  // namespace ml
