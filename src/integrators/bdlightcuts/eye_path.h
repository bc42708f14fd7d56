// The eye path of Bidirectional Lightcuts between its vertices: the state its split weights and
// the MIS of its BSDF samples' emission carry from vertex to vertex, the emission a ray meets
// weighted as the path's last split, and the state past a BSDF sample (bdlightcuts.cpp's
// trace_eye, which also gives every extra BSDF sample of bdlightcuts.emission_samples its own).
#pragma once

#include <functional>

#include "core/color.h"
#include "geometry/interaction.h"
#include "integrators/bdlightcuts/split_weights.h"
#include "lights/light.h"
#include "materials/bsdf.h"
#include "scene/scene.h"
#include "transport/volume_path.h"

namespace ml {

class LightSampler;

// What an eye path carries from vertex to vertex for its splits' weights and for the MIS of the
// emission its BSDF samples meet.
struct EyeState {
    RGB beta{1.f};
    float prefix = 0, theta = 0;
    // The split at the last non-delta eye vertex, waiting for D at the next vertex.
    bool pending = false;
    float pending_m = 0, pending_mu = 1;
    Vec3 pending_p;
    // Whether the previous vertex's light sample weighs the emission that its BSDF sample finds
    // (MIS; none from the camera or after a delta lobe's sample), and whether that light sample
    // was its split to an emitter (`lights.direct=sample`).
    bool prev_nee = false, prev_direct = false;
    // The BSDF sample's density for that MIS, times the vertex's BSDF samples for emission.
    float prev_pdf = 0;
    LightSampleContext prev_ctx;
};

// D at an eye vertex with normal n: its lobe between the eye (wo) and wi, f(wo, wi) |cos wo|
// at a surface (f: the largest channel of the BSDF's value); at a scattering point in a medium
// the phase function itself, f |cos wo| |cos wi| of its Bxdf (transport/phase_bxdf.h).
inline float eye_lobe_density(float f, const Vec3& wo, const Vec3& wi, const Vec3& n,
                              bool in_medium) {
    const float d = f * abs_dot(wo, n);
    return in_medium ? d * abs_dot(wi, n) : d;
}

// The emission met along `ray` (hit: the surface, else null), weighted as the path's last split
// (what the earlier splits left), and the previous vertex's split to that emitter by its BSDF
// sample's share. t_prev: 1 / the squared length of the segment from the pending split's vertex.
RGB met_emission(const Scene& scene, const Ray& ray, const SurfaceInteraction* hit,
                 const EyeState& s, float t_prev, const SplitWeightOptions& o,
                 const LightSampler* nee);

// The path's state past vertex si (BSDF bsdf, shading normal n; in_medium: a scattering point
// in a medium, bsdf its phase function) along BSDF sample bs: its split there pending, and the
// MIS of what bs meets weighed by `bsdf_samples` BSDF samples. False when the path ends (no
// throughput).
bool scatter(EyeState& s, const SurfaceInteraction& si, bool in_medium, const Bsdf& bsdf,
             const BsdfSample& bs, bool direct_mis, bool last_by_light, int bsdf_samples,
             float t_prev, const SplitWeightOptions& o, bool direct_sample, bool emission_mis);

// What an eye path meets next in a scene with media.
enum class EyeHit { Escaped, Surface, Medium, Absorbed };

// The next vertex along *ray, which starts in *medium: delta tracking (with spectral tracking,
// *beta taking its weights) finds a scattering in a medium (si: the point, *phase its phase
// function, as a medium gather point has them) or lets the ray pass to the first surface that is
// not an interface (*ray: its last stretch, for the emission met); the interfaces it crosses
// move *medium on. `stretch`, where given, is called with each stretch through a medium and
// the throughput at its start, before the tracking. `emitted`, where given, takes the light the
// media emit along the way, times the throughput (as `path` counts it).
using StretchFn = std::function<void(const Medium&, const UnitRay&, const RGB& beta)>;
EyeHit next_eye_hit(const Scene& scene, Ray* ray, Sampler& sampler, ScratchBuffer& scratch,
                    const Medium** medium, RGB* beta, SurfaceInteraction* si, Bsdf* phase,
                    const StretchFn& stretch, RGB* emitted = nullptr);

}  // namespace ml
