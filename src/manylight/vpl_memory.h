// The memory a point-light set takes, estimated from the VPL count before it is built, and the
// check that stops a render whose VPLs cannot fit with a message saying how many would, rather
// than the system killing it part way.
#pragma once

#include <cstdint>
#include <string>

#include "manylight/many_lights.h"

namespace ml {

// Memory per light of a light tree with `reps` representatives (2 nodes per light: a binary tree
// over n leaves has 2n - 1): the tree kept, and the most its build holds at once, the tree
// included (light_tree.cpp, which knows the build's records).
size_t light_tree_bytes_per_light(int reps);
size_t light_tree_peak_build_bytes_per_light(int reps);

// Bytes per light at the peak of building a set and, with `reps` > 0, its light tree of that many
// representatives per node: the lights and the tree's build, or the VPL sampler's chunks and the
// set they are copied into, whichever is more. With `surfaces` (glossy VPLs kept with their
// surface: vpl.glossy=bsdf or diffuse), each VPL may also hold a surface and its Bxdf, counted
// for every VPL since how many land on glossy surfaces is not known before the build. A later set
// (vpl.sets=pass) replaces the last, which is released first.
size_t point_light_peak_bytes(int reps, bool surfaces);

// Throws UsageError when the VPLs settings.lights.vpl_count asks for (with a light tree when
// `tree`) need more than kMemoryShare of the memory available (core/memory.h), naming the
// estimate, the memory available and the VPL count that fits. `integrator` names the setting's
// owner in the message. Nothing happens where the memory available cannot be read.
void check_vpl_memory(const ManyLightSettings& settings, bool tree, const std::string& integrator);

// The share of the available memory a set and its tree may take: the rest is for the film, the
// integrator's per-thread state and the allocator's slack.
constexpr double kMemoryShare = 0.8;

}  // namespace ml
