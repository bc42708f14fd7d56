// Camera and light subpaths for bidirectional estimators: random walks that record, at every
// vertex, the throughput and the forward and reverse area densities MIS needs.
#pragma once

#include "bidir/path_vertex.h"
#include "core/scratch.h"
#include "sampling/sampler.h"

namespace ml {

// How a walk decides where a ray in a participating medium scatters.
// - Tracking: delta tracking with spectral tracking's probabilities (as `path`), the throughput
//   carrying the medium's colour; a medium vertex's density leaves the distance's out (BDPT's MIS
//   is the same for every strategy).
// - Majorant: the first collision of the majorant's process (first_majorant_collision), whose
//   density has a closed form; the throughput leaves the medium out, and the caller weighs the
//   path itself (Metropolis light transport in path space, integrators/mlt/path_media.h).
enum class DistanceSampling { Tracking, Majorant };

// Up to `max_vertices` vertices starting at the camera with `ray` (vertex 0 on the lens). Per
// bounce: get_1d() (lobe), get_2d() (direction). Escaped rays end the path on a light vertex
// standing for the infinite lights. Returns the vertex count.
//
// With `medium_emission` (max_vertices entries), entry k receives the light that participating
// media emit along the stretch after the path's k-th scattering vertex (k = 0: along the camera
// ray), times the throughput there: strategy s = 0 of a path whose last segment ends in the
// medium, which no light subpath can make (no light subpath starts in a medium), so it takes
// all of that light unweighted. As `path` counts it, it belongs to depth k + 1.
int generate_camera_subpath(const BdptScene& ctx, const Ray& ray, Sampler& sampler,
                            ScratchBuffer& scratch, int max_vertices, PathVertex* path,
                            RGB* medium_emission = nullptr,
                            DistanceSampling sampling = DistanceSampling::Tracking);

// Up to `max_vertices` vertices starting on a light: get_1d() (which light), get_2d()
// (position), get_2d() (direction), then per bounce get_1d(), get_2d(). Returns the vertex
// count (0 when no light could emit). `time` is the path's (its camera ray's, or one drawn over
// the shutter by camera.sample_time): every ray of the subpath is traced at it.
int generate_light_subpath(const BdptScene& ctx, Sampler& sampler, ScratchBuffer& scratch,
                           int max_vertices, float time, PathVertex* path,
                           DistanceSampling sampling = DistanceSampling::Tracking);

// Continues a subpath whose last vertex is path[-1] along `ray`, which that vertex chose with
// solid-angle density `pdf_dir` (0 for a delta lobe), in participating medium `medium` (null:
// none): up to `max_vertices` vertices, each bounce drawing as above, throughputs counted from
// one. Returns the vertex count. (The partial bidirectional mutation regrows a path from kept
// vertices with it.)
int continue_subpath(const BdptScene& ctx, const Ray& ray, float pdf_dir, Sampler& sampler,
                     ScratchBuffer& scratch, int max_vertices, TransportMode mode, PathVertex* path,
                     const Medium* medium = nullptr,
                     DistanceSampling sampling = DistanceSampling::Tracking);

}  // namespace ml
