// The split weights of Bidirectional Lightcuts (Walter, Khungurn and Bala 2012; seed 003). A
// full path x_1 ... x_k (x_1 seen by the camera, x_k on a light) is made at split j by a virtual
// sensor point (VSP) at eye vertex x_j joined to a virtual point light (VPL) at x_{j+1}; split k
// is the eye path finding the emitter itself. The path's weights, shortest eye path first:
//   w_j = max(0, min(w_j^E, w_j^C, w_j^D, w_j^V)), S_j = w_1 + ... + w_{j-1},
//   energy:    w_j^E = 1 - S_j (the weights never sum above 1);
//   clamping:  w_j^C = min(1, C_clamp / (M_j T_{j,j+1} D_{j+1}));
//   diffuse:   w_j^D = min(1, C_D / D_{j+1});
//   variance:  w_j^V = mu_j - S_j, mu_j = mu(Theta_j), Theta_j = sum_{i<j} (pi M_i)^(-1/2);
// with, in the largest channel of f, M_i = f_i(x_{i-1}, x_{i+1}) |cos| at x_i towards x_{i+1} (the
// eye side's lobe as a density of directions), T = 1 / distance^2 and D_{i+1} = f_{i+1}(x_i,
// x_{i+2}) |cos| at x_{i+1} towards x_i (the light side's lobe); at an emitter D is its emission's
// directional density (cos / pi for a diffuse area light, 1 / (4 pi) for an omni light), at a
// distant light 0 (no clamping). A split whose VSP or VPL scatters by a delta lobe on the path
// weighs 0. Every w_j depends on x_1 ... x_{j+1} only, so each split computes the same weights for
// the same path; the sum over the splits is at most 1, and exactly 1 (unbiased) when the energy
// weight alone is on: w_1 = 1 at the first connectable vertex. Clamping moves the clamped part of a
// connection to longer eye paths; what no split up to the eye-path length takes is lost (the
// bias, always a darkening with the energy weight on).
#pragma once

#include <limits>

namespace ml {

struct SplitWeightOptions {
    bool energy = true, clamp = true, diffuse = true, variance = true;
    // Defaults: bench/RESULTS.md, "Issue 17, Bidirectional Lightcuts"; C_clamp from "Issue 17,
    // session 16" (0.03 before).
    float c_clamp = 0.01f;  // C_clamp
    float c_d = 1.f;        // C_D
    // mu(Theta) = 1 up to spread / 2, falling linearly to 0 at `spread` (radians).
    float spread = 8.f;
};

// mu_j of an eye path whose directional spread is theta.
inline float spread_mu(const SplitWeightOptions& o, float theta) {
    if (!(theta < o.spread)) return 0.f;
    float m = 2.f - 2.f * theta / o.spread;
    return m > 1.f ? 1.f : m;
}

// (pi M)^(-1/2): the spread a lobe of density M adds (infinite for M <= 0).
float lobe_spread(float m);

// w_j for a split whose earlier weights sum to `prefix`, with mtd = M_j T_{j,j+1} D_{j+1},
// d = D_{j+1} and mu = mu_j. Disabled weights count as +infinity; the result is in [0, 1].
float split_weight(const SplitWeightOptions& o, float prefix, float mtd, float d, float mu);

// The weight of the eye path finding an emitter at x_k (the last split): what the earlier splits
// left, 1 - S_k (1 without the energy weight). No later split can take a part of this path, so
// neither clamping (there is no connection) nor the variance weight applies: capped at mu_k, the
// path lost 1 - mu_k of its light whenever the eye path had spread (about 1% of a forward-
// scattering cloud's light at max depth 2, each vertex in it spreading by up to 5 radians).
float emission_weight(const SplitWeightOptions& o, float prefix);

// An upper bound, over every light, of the weights of a VSP's pairs (SplitWeighting::weight).
// pending_mt: M_{j-1} T_{j-1,j} (< 0: no split j-1); dj_max: an upper bound of D_j over every
// light direction (+infinity where unknown). split_weight falls as M T D and D grow, so w_{j-1}
// is at least its value at dj_max, and w_j at most what energy and variance leave after that.
// 0 where the eye path alone has used the weights up: with the energy weight alone, every VSP
// after a non-delta eye vertex (w_{j-1} = 1 - S_{j-1}); with the diffuse weight, one at a diffuse
// surface after a non-delta vertex (D_j <= albedo / pi < C_D, so w_{j-1} = 1 - S_{j-1}). Such a
// VSP joins no light with any weight, and is left out of the VSP tree: in it, it would be drawn
// as clusters' representative in proportion to its throughput and shade them 0, a 0-or-large
// estimate that the cut's refinement (which splits where the estimates are high) turns into a
// darkening (bench/RESULTS.md, issue 13, session 11).
float vsp_weight_bound(const SplitWeightOptions& o, float prefix, float pending_mt, float dj_max,
                       float pending_mu, float mu);

// The remainder r = 1 - (w_1 + ... + w_J) of a path x_1 ... x_k (k >= J + 2) that no split up to
// the eye-path length J takes, the weight with which `bdlightcuts.rest=path` path traces it past
// x_{J+1}: `prefix` is w_1 + ... + w_{J-1}, pending_mt = M_J T_{J,J+1} (< 0: split J weighs 0 on
// this path, x_J or x_{J+1} scattering by a delta lobe), pending_mu = mu_J and d = D_{J+1}, the
// lobe at x_{J+1} between x_J and x_{J+2}. In [0, 1]; it only grows with d. Never below 0:
// without the energy weight the splits may take more than 1 (a brightening), and the remainder
// adds what they miss without taking anything off.
float remainder_weight(const SplitWeightOptions& o, float prefix, float pending_mt, float d,
                       float pending_mu);

// Whether the remainder is 0 for every D_{J+1} up to d_max (+infinity where unknown): then no
// path through x_{J+1} needs tracing. Within 1e-6 of 0 counts as 0 (the weights' rounding).
bool remainder_vanishes(const SplitWeightOptions& o, float prefix, float pending_mt, float d_max,
                        float pending_mu);

}  // namespace ml
