// Paths as Veach's Metropolis light transport sees them (Veach's thesis, chapter 11): whole paths
// of vertices, from the lens to a light, with the values its mutations compare.
//
// A path's scalar importance is the luminance of its measurement contribution f(x). Each mutation
// compares f in its own coordinates: the whole-path (bidirectional) mutation by W = f / q, where q
// is the density with which BDPT, choosing one of its strategies uniformly, makes the path; the
// lens perturbation by f times the Jacobian from film position to the path's first vertices,
// which is the path tracing throughput with the specular lobes held fixed; the caustic
// perturbation likewise from a direction at the light side. Factors that the compared paths
// share cancel, but colours do not (luminance of a product), so every target carries every
// vertex's colour.
#pragma once

#include <optional>
#include <vector>

#include "bidir/path_vertex.h"

namespace ml {

// An edge of a path through participating media (path_media.h): the transmittance (an estimate
// in grid media, kept with the edge), the majorant's survival over it, and sigma_maj at its ends
// (a on the camera side).
struct MediaEdge {
    RGB tr{1.f};
    float tmaj = 1;
    float maj_a = 0, maj_b = 0;
};

struct MltPath {
    // Camera order: v[0] on the lens, v.back() a light endpoint (area, point or spot light);
    // surfaces and medium scattering points in between.
    std::vector<PathVertex> v;
    Vec2 p_raster;  // where the path lands on the film
    Vec2 u_lens;    // the lens sample of v[0] (for perturbations that keep the lens point)
    // The path's time as a fraction of the shutter (every vertex's si.time is the camera's
    // sample_time of it). Drawn with the path at the bootstrap, kept by every mutation: each chain
    // stays at its time, and the bootstrap's choice of chains, in proportion to contribution,
    // spreads the chains over the shutter as the time integral needs.
    float u_time = 0;
    // In scenes with media: edges[k] joins v[k] and v[k + 1] (trace_media_edges); empty
    // elsewhere.
    std::vector<MediaEdge> edges;
    int depth() const { return int(v.size()) - 2; }
};

// Whether the path's vertex k (a surface) scatters only by delta lobes.
inline bool is_specular_vertex(const MltPath& x, int k) {
    const PathVertex& v = x.v[size_t(k)];
    return v.kind == VertexKind::Surface && v.bsdf && v.bsdf.is_specular_only();
}

// The BSDF weight f |cos| of the delta lobe at vertex k that scatters from `wo` into `wi`
// (transmission or reflection, as the directions say); black if no lobe does.
RGB specular_weight(const PathVertex& v, const Vec3& wo, const Vec3& wi);

// A light endpoint for strategy s = 1, the light chosen by ctx.light_sampler and the point by
// the light's area density (as sample_le places a light subpath's origin), which is the density
// path_over_bdpt_density counts for it; BDPT's own s = 1 (the light's sample_li) draws by solid
// angle instead. Null where the light gives no point.
std::optional<PathVertex> sample_light_point_by_area(const BdptScene& ctx, Sampler& sampler);

// f(x) / q(x), q the density with which BDPT, choosing one of `depth + 2` strategies uniformly
// (one for depth 0), proposes x. Strategies that sample a specular vertex from different sides
// see it through different delta distributions, so only the run [s_lo, s_hi] of consecutive
// strategies with the most light vertices is counted, and proposals of x by other strategies
// must be refused. Black for paths BDPT cannot make.
//
// With a window [s_min, s_max], only the strategies in it count (the run is the one with the most
// light vertices inside the window): the partial bidirectional mutation's density, whose
// strategies differ only in the vertices it regenerates (bidir_mutation.h). The result keeps the
// factor depth + 2 of the whole range.
RGB path_over_bdpt_density(const BdptScene& ctx, const MltPath& x, int* s_lo = nullptr,
                           int* s_hi = nullptr, int s_min = 0, int s_max = 1 << 30);

// Lens perturbation target: f(x) times the Jacobian from the film position, for a path whose
// vertices 1..j-1 are specular and j is not (j + 1 < size). Colour and magnitude.
RGB lens_target(const BdptScene& ctx, const MltPath& x, int j);

// Caustic perturbation target: f(x) times the Jacobian from the direction leaving vertex m
// towards vertex m - 1, for a path whose vertex 1 is not specular, 2..m-1 are, and m is not.
RGB caustic_target(const BdptScene& ctx, const MltPath& x, int m);

// Continues a specular chain: the delta lobe of `v` (transmission or not) leaving from `wo`.
std::optional<Vec3> specular_direction(const PathVertex& v, const Vec3& wo, bool transmission);

}  // namespace ml
