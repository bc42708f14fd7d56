// Veach's bidirectional mutation (Veach's thesis, section 11.4.2): a subpath of the current path
// is deleted and regrown from the kept vertices on both sides, so that most of the path, and
// often its pixel, survives the mutation.
//
// In camera order x_0 (lens) .. x_{n-1} (light), the kept vertices are x_0..x_a and x_b..x_{n-1}
// (a = -1: the lens is deleted too; b = n: the light), and x_{a+1}..x_{b-1} are deleted:
//   1. the deletion's length k_d = b - a edges with probability p_d[k_d] (Veach's 0.5 for
//      k_d = 2, 2^-k_d beyond; k_d = 1 deletes no vertex, the identity at one depth, so it is
//      left out), its position uniformly among the n + 2 - k_d of that length;
//   2. as many vertices are added as were deleted (chains keep one depth), l_E of them from the
//      eye side and l_L from the light side, l_E uniform among its m + 1 values (m when the lens
//      is deleted: the eye side must make at least the lens);
//   3. each kept side is extended by BDPT's random walk (a deleted lens or light is sampled anew
//      first, as a camera or light subpath starts), and the two ends are joined by one
//      connection whose visibility is traced; the connection samples the lens (t = 1) or the
//      light (s = 1) when the deletion took it and no vertex of that side is added.
// The proposal density T(x -> y) is p_d / positions times the mean over the splits of the
// density of the added vertices; with (s, t) the BDPT strategy of a split, the kept vertices'
// densities are common factors, so T(x -> y) is proportional to the sum of BDPT's strategy
// densities p_s(y) over the splits' strategies s in [n - b, n - a - 1], and the acceptance
//   a = min(1, f(y) T(y -> x) / (f(x) T(x -> y)))
// is the ratio of f / sum p_s of the two paths over that window (path_over_bdpt_density). As for
// the whole-path proposal, splits on either side of a delta vertex see it through different delta
// distributions: only the run of consecutive splits with the most light vertices counts, and
// proposals made by other splits are refused.
#pragma once

#include <optional>

#include "integrators/mlt/mutations.h"

namespace ml {

// The deletion and split a partial bidirectional proposal used, and its acceptance ratio before
// the min(1, .), for tests.
struct BidirChoice {
    int a = -1, b = -1;  // last kept eye vertex, first kept light vertex
    int eye = 0;         // vertices added from the eye side (l_E)
    double ratio = 0;    // f(y) T(y -> x) / (f(x) T(x -> y)), luminance
};

// p_d: the probability of deleting k_d edges (k_d - 1 vertices) of a path of n vertices, over
// k_d in [2, n + 1].
double deletion_probability(int n, int k_d);

// The partial bidirectional mutation of x. nullopt when the regrown path has no contribution, or
// was made by a split that does not count (rejection). `choice`, when given, receives the
// deletion and the split.
std::optional<Proposal> mutate_bidirectional_partial(const BdptScene& ctx, const MltPath& x,
                                                     Sampler& sampler, ScratchBuffer& scratch,
                                                     BidirChoice* choice = nullptr);

}  // namespace ml
