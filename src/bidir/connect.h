// BDPT's connection strategies: a light subpath's first s vertices joined to a camera subpath's
// first t vertices, and the power-heuristic weight of that strategy against every other one that
// could have made the same path.
#pragma once

#include "bidir/path_vertex.h"
#include "sampling/sampler.h"

namespace ml {

struct Connection {
    RGB L;                 // MIS-weighted contribution (black if the strategy made no path)
    float mis_weight = 0;  // the weight applied (0 when L is black)
    bool splat = false;    // t == 1: L lands at p_raster, not at the camera subpath's pixel
    Vec2 p_raster;
};

// Strategy (s, t): s light vertices, t camera vertices (s + t >= 2, t >= 1). Draws from the
// sampler only for s == 1 (get_1d() light, get_2d() point on it) and t == 1 (get_2d() lens).
// The vertex arrays are modified during the call and restored before it returns. The vertex
// sampled anew (s == 1, t == 1) is copied to `sampled_out` when given.
Connection connect_bdpt(const BdptScene& ctx, PathVertex* light_vertices,
                        PathVertex* camera_vertices, int s, int t, Sampler& sampler,
                        PathVertex* sampled_out = nullptr);

// Power-heuristic weight of strategy (s, t) for the path it made (the balance heuristic when
// `balance`: p_s over the sum of every strategy's density). `sampled` is the vertex the strategy
// sampled anew (the light point for s == 1, the lens point for t == 1), else unused. The arrays
// are modified during the call and restored before it returns.
float mis_weight(const BdptScene& ctx, PathVertex* light_vertices, PathVertex* camera_vertices,
                 const PathVertex& sampled, int s, int t, bool balance = false);

}  // namespace ml
