// Participating media on Veach's paths (Metropolis light transport in path space).
//
// MLT compares densities of whole paths, so every vertex a walk places in a medium must have a
// density that the positions alone give. BDPT's spectral tracking does not (its choice between a
// real and a null collision follows the throughput), so MLT's walks place a medium vertex at the
// first collision of the majorant's process (DistanceSampling::Majorant): a surface reached over
// an edge has the majorant's survival exp(-int sigma_maj) in its density, a medium vertex that
// times sigma_maj there. The path's f has each edge's transmittance and sigma_s at each medium
// vertex (the phase function is its scattering), per channel.
//
// Transmittance has no closed form in grid media; there each edge carries an estimate (ratio
// tracking: unbiased, never negative) made when the edge was made and kept with it while its two
// vertices stay. The chain then runs on paths and their estimates, and its stationary
// distribution's marginal over paths is still proportional to f (pseudo-marginal Metropolis-
// Hastings, Andrieu and Roberts 2009): each splat of f-hat / luminance(f-hat) has f's expected
// value. Homogeneous media give the exact transmittance.
#pragma once

#include "bidir/subpaths.h"
#include "integrators/mlt/path_space.h"
#include "sampling/sampler.h"

namespace ml {

// How MLT's walks place vertices in media: the majorant's collision process in a scene with
// media (BDPT's own tracking elsewhere, where it is the same walk).
inline DistanceSampling mlt_distance_sampling(const BdptScene& ctx) {
    return ctx.scene.has_media() ? DistanceSampling::Majorant : DistanceSampling::Tracking;
}

// Traces every edge of `y` through interfaces and the media between them: false where an edge is
// blocked by another surface. An edge whose two ends are points of an edge of `reuse` keeps that
// edge's estimates; the others are estimated anew. Nothing to do (true) in a scene without media.
bool trace_media_edges(const BdptScene& ctx, MltPath& y, const MltPath* reuse, Sampler& sampler);

// The colour the media give f(x): every edge's transmittance times sigma_s at every medium vertex
// (1 without media).
RGB media_colour(const MltPath& x);

// The part of the density of x's vertex `to` that the distance sampling along edge `e` (between
// v[e] and v[e + 1]; `to` one of them) gives it: the majorant's survival over the edge, times
// sigma_maj at `to` if that is a medium vertex (1 without media).
float media_density(const MltPath& x, int e, int to);

}  // namespace ml
