// pbrt-v4 shapes as object-space triangle meshes: "trianglemesh" as given (validated), "sphere",
// "disk" and "cylinder" tessellated finely enough that the facets do not show, with analytic
// per-vertex normals and pbrt's (u, v) parameterisation. Then the move to world space.
#pragma once

#include <memory>
#include <vector>

#include "core/math.h"
#include "core/params.h"
#include "geometry/mesh.h"

namespace ml {

// Each reads its parameters from `params` (the caller checks for unused ones afterwards) and
// throws InputError at the offending parameter, or at `loc` for what is missing.
std::unique_ptr<TriangleMesh> make_triangle_mesh(const ParameterList& params, const FileLoc& loc);
// "bilinearmesh": each patch (p00, p10, p01, p11) split into two triangles along p00-p11.
std::unique_ptr<TriangleMesh> make_bilinear_mesh(const ParameterList& params, const FileLoc& loc);
std::unique_ptr<TriangleMesh> make_sphere(const ParameterList& params, const FileLoc& loc);
std::unique_ptr<TriangleMesh> make_disk(const ParameterList& params, const FileLoc& loc);
// pbrt-v4's "cylinder" (radius, zmin, zmax, phimax) about the z axis, open at both ends.
std::unique_ptr<TriangleMesh> make_cylinder(const ParameterList& params, const FileLoc& loc);

// Moves an object-space mesh to world space in place: points by `to_world`, normals by its
// inverse transpose (renormalised). Sets flip_normals = reverse_orientation xor the transform's
// change of handedness. Where the mesh has shading normals, pbrt-v4 turns each triangle's
// geometric normal to their side (and ReverseOrientation negates them); we reorder each
// triangle's vertices so that triangle_normal() agrees with that.
void transform_mesh(TriangleMesh& mesh, const Transform& to_world, bool reverse_orientation);

// A moving mesh: `steps` (at least two) are its world transforms at times spread evenly over the
// motion; fills motion_p and motion_n (and p, n from the first step, as transform_mesh).
void transform_mesh_motion(TriangleMesh& mesh, const std::vector<Transform>& steps,
                           bool reverse_orientation);
// How many linear segments follow a motion that turns through `radians` closely enough: one per
// 2 degrees (a vertex at distance r strays at most r (1 - cos 1deg) = 1.5e-4 r from the arc),
// between 1 and 64.
int motion_segments(float radians);

}  // namespace ml
