// pbrt-v4's "curve" shape: cubic Bezier segments (B-splines and quadratics converted to them)
// that Embree intersects as curves, and the surface interaction at a hit, with pbrt-v4's (u, v)
// and shading frame: "flat" faces the ray, "cylinder" faces the ray with the normal turned
// across the width as on a round tube, "ribbon" is oriented by the normals N.
#pragma once

#include <memory>

#include "core/params.h"
#include "geometry/interaction.h"
#include "geometry/mesh.h"

namespace ml {

// Reads P, basis, degree, type, N, width, width0, width1 and splitdepth (which Embree has no
// use for); throws InputError at the offending parameter, or at `loc` for what is missing.
std::unique_ptr<TriangleMesh> make_curves(const ParameterList& params, const FileLoc& loc);

// Moves a curve mesh's widths and ribbon normals to world space (its points are moved by
// transform_mesh): widths scale by the cube root of the transform's determinant.
void transform_curves(CurveSet& curves, const Transform& to_world);

// A cubic Bezier and its derivative at u; where the derivative vanishes (coincident end control
// points, at u = 0 or 1), the chord p[3] - p[0] stands for it.
Vec3 eval_cubic_bezier(const Vec3 p[4], float u, Vec3* deriv);

// Fills `si` for a hit on segment `seg` of curve mesh `m` at segment parameter u (Embree's),
// ray parameter t; a moving mesh where it is at `motion_time` (0 to 1 over the shutter, as
// Embree's ray time), each control point, width and normal moving linearly between time steps.
void curve_interaction(const TriangleMesh& m, uint32_t seg, float u, const Ray& ray, float t,
                       float motion_time, SurfaceInteraction* si);

}  // namespace ml
