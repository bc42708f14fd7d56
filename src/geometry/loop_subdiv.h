// pbrt-v4's "loopsubdiv" shape: a triangle mesh refined `levels` times by Loop subdivision, its
// vertices then moved to the limit surface, with the limit surface's normals. The rules are
// pbrt-v4's (util/loopsubdiv.cpp), so that a scene renders the same surface:
//   - even (old) vertices: (1 - n beta) v + beta * sum of the n neighbours, with Warren's
//     beta = 3/16 for n = 3, else 3 / (8 n) (not Loop's original beta, which OpenSubdiv's Loop
//     scheme uses: the two differ for valences other than 3 and 6);
//   - odd (edge) vertices: 3/8 of the edge's ends plus 1/8 of the two opposite vertices;
//   - on the boundary: 3/4 v + 1/8 of its two boundary neighbours, edge midpoints;
//   - limit positions: gamma = 1 / (n + 3 / (8 beta)) for interior vertices, 3/5 v + 1/5 of the
//     boundary neighbours on the boundary;
//   - normals: the cross product of the limit tangents from cos/sin weights around the ring
//     (pbrt-v4's ring runs against the faces' winding, so a mesh wound counter-clockwise seen
//     from outside gets normals pointing in, as in pbrt-v4), boundary tangents by valence.
// The mesh must be manifold and consistently wound: anything else is an InputError.
#pragma once

#include <memory>

#include "core/params.h"
#include "geometry/mesh.h"

namespace ml {

// Reads "levels" (default 3), "indices", "P" and "scheme" ("loop", the only one) from `params`.
std::unique_ptr<TriangleMesh> make_loop_subdiv(const ParameterList& params, const FileLoc& loc);

// The refinement itself, object space: positions and triangles in; the limit mesh (p, n,
// indices) out. Throws InputError at `loc` for a non-manifold or inconsistently wound mesh.
std::unique_ptr<TriangleMesh> loop_subdivide(std::vector<Vec3> p,
                                             const std::vector<uint32_t>& indices, int levels,
                                             const FileLoc& loc);

}  // namespace ml
