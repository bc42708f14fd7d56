#include "manylight/vpl_memory.h"

#include <fmt/format.h>

#include <algorithm>

#include "core/error.h"
#include "core/memory.h"
#include "materials/bxdfs.h"
#include "materials/hair.h"
#include "transport/phase_bxdf.h"

namespace ml {

namespace {
// A Bxdf in the set's arenas, the largest kind, with the alignment and, where a chunk's arena is
// full and it is allocated on its own, the allocator's header and the arena's pointer to it.
constexpr size_t kBxdfBytes =
    std::max({sizeof(DiffuseBxdf), sizeof(DiffuseTransmissionBxdf), sizeof(ConductorBxdf),
              sizeof(DielectricBxdf), sizeof(ThinDielectricBxdf), sizeof(CoatedDiffuseBxdf),
              sizeof(CoatedConductorBxdf), sizeof(HairBxdf), sizeof(PhaseBxdf)}) +
    alignof(std::max_align_t) + 16 + 2 * sizeof(void*);
}  // namespace

size_t point_light_peak_bytes(int reps, bool surfaces) {
    // A glossy VPL's surface, in a vector that grows by doubling (up to twice its size), and its
    // Bxdf; it lives as long as the light.
    const size_t light = sizeof(PointLight) + (surfaces ? 2 * sizeof(VplSurface) + kBxdfBytes : 0);
    // The sampler's chunks of VPLs are appended to the set, then released.
    const size_t sampled = 2 * light;
    if (reps <= 0) return sampled;
    return std::max(sampled, light + light_tree_peak_build_bytes_per_light(reps));
}

void check_vpl_memory(const ManyLightSettings& settings, bool tree, const std::string& integrator) {
    const int64_t count = settings.lights.vpls ? settings.lights.vpl_count : 0;
    if (count <= 0) return;
    const std::optional<uint64_t> available = available_memory_bytes();
    if (!available) return;
    const double per_vpl = double(point_light_peak_bytes(
        tree ? settings.tree_reps : 0, settings.lights.vpl_glossy != GlossyVpls::Skip));
    const double need = per_vpl * double(count), may = kMemoryShare * double(*available);
    if (need <= may) return;
    const int64_t fit = int64_t(may / per_vpl);
    auto gb = [](double bytes) { return bytes / double(1 << 30); };
    throw UsageError(fmt::format(
        "{}: vpl.count={} needs about {:.2f} GB for its VPLs{} ({:.0f} bytes per VPL), more than "
        "{:.0f}% of the {:.2f} GB of memory available: about {} VPLs fit; lower vpl.count",
        integrator, count, gb(need), tree ? " and their light tree" : "", per_vpl,
        100 * kMemoryShare, gb(double(*available)), fit));
}

}  // namespace ml
