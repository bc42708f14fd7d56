// Ray counters (and dropped non-finite splats): per-thread, summed on demand, so counting costs
// an increment and no atomics.
#pragma once

#include <cstdint>

namespace ml::stats {

struct RayCounts {
    uint64_t camera = 0;            // primary rays (counted by the integrators)
    uint64_t closest = 0;           // all closest-hit queries
    uint64_t shadow = 0;            // all occlusion queries
    uint64_t nonfinite_splats = 0;  // splats dropped for a NaN or infinite channel
    uint64_t total() const { return closest + shadow; }
};

// This thread's counters (registered on first use, kept until the process ends).
RayCounts& local();
inline void count_ray() { ++local().closest; }
inline void count_shadow_ray() { ++local().shadow; }
inline void count_camera_ray() { ++local().camera; }
inline void count_nonfinite_splat() { ++local().nonfinite_splats; }
// The sum over every thread that has counted.
RayCounts total();
void reset();

}  // namespace ml::stats
