// Light transport through participating media (pbrt-v4's VolPathIntegrator, in RGB): the path
// tracer's vertex loop where a ray may scatter, be absorbed or pass on inside a medium before it
// reaches a surface.
//
// Distances are drawn by delta tracking against each medium's majorant, with spectral tracking
// for coloured media (Kutz et al. 2017): at each tentative collision the event (absorption,
// scattering, or a null collision that continues) is chosen with probabilities proportional to
// the throughput-weighted coefficients, and the throughput takes the ratio of the coefficient to
// its probability, so every channel stays unbiased. Emission in a medium is gathered at every
// tentative collision. Shadow rays pass through "interface" surfaces, their transmittance
// computed in closed form in homogeneous media and by ratio tracking elsewhere. Next-event
// estimation at surface and medium vertices is weighed by MIS against BSDF or phase sampling
// (the power heuristic on the directions' densities; the transmittance is common to both).
//
// Every random number comes from the sampler, one dimension per draw.
#pragma once

#include <cmath>
#include <optional>

#include "core/scratch.h"
#include "lights/light_sampler.h"
#include "media/medium.h"
#include "sampling/sampler.h"
#include "scene/scene.h"
#include "transport/path_tracer.h"

namespace ml {

// The radiance along `camera_ray`, which starts in the camera's medium: every path up to
// options.max_depth scattering vertices (surface and medium alike). Path guiding and
// all_lights are not used here.
RGB trace_volumetric(const Scene& scene, const Ray& camera_ray, Sampler& sampler,
                     ScratchBuffer& scratch, const LightSampler& light_sampler,
                     const PathTraceOptions& options);

// Where a homogeneous medium's extinction is the same in every channel, delta tracking draws a
// scattering point at t with density sigma_t exp(-sigma_t t) times the share of scattering in
// the throughput-weighted extinction (`track`'s choice; no null collisions come first): the
// density MIS weighs equiangular samples against. Not valid elsewhere (no equiangular
// sampling there).
struct GreyTracking {
    float sigma_t = 0, scatter_share = 0;
    bool valid = false;
    GreyTracking() = default;
    GreyTracking(const Medium& m, const RGB& beta) {
        if (!m.homogeneous()) return;
        const MediumProperties mp = m.at(Vec3());
        const RGB st = mp.sigma_a + mp.sigma_s;
        if (!(st.r > 0) || st.r != st.g || st.r != st.b) return;
        const RGB bst = beta * st, bss = beta * mp.sigma_s;
        const float c = (bst.r + bst.g + bst.b) / 3;
        if (!(c > 0)) return;
        sigma_t = st.r;
        scatter_share = (bss.r + bss.g + bss.b) / 3 / c;
        valid = scatter_share > 0;
    }
    float pdf_length(float t) const { return sigma_t * std::exp(-sigma_t * t) * scatter_share; }
};

// A vertex where another estimator hands its path to the volumetric path tracer: a surface
// point, the path having arrived in `medium`, or (in_medium) a scattering point in `medium`, of
// which si has p, wo and time.
struct VolumeVertex {
    SurfaceInteraction si;
    const Medium* medium = nullptr;
    bool in_medium = false;
};

// continue_path through media: the radiance that paths continued past v bring back along v.si.wo,
// times the throughput `beta` with which the caller reached v after `depth` scattering vertices;
// v's own emission is the caller's. `first`, if given, weighs the paths by the direction they
// leave v in (at a medium point its Bsdf is the phase function, transport/phase_bxdf.h).
RGB continue_volumetric(const Scene& scene, const VolumeVertex& v, int depth, RGB beta,
                        Sampler& sampler, ScratchBuffer& scratch, const LightSampler& light_sampler,
                        const PathTraceOptions& options, const FirstBounceWeight* first = nullptr);

// The paths continued past a vertex for the light participating media emit alone, leaving it by
// its non-delta lobes: for callers whose own estimators find every other light there (the
// gather points of the many-light integrators, whose point lights stand for the rest and whose
// camera paths follow the delta lobes themselves).
class MediaEmissionOnly final : public FirstBounceWeight {
public:
    float weight(const Bsdf&, const Vec3&, const Vec3&, bool, const RGB*) const override {
        return 0;
    }
    bool vanishes(const Bsdf&, const Vec3&) const override { return true; }
    bool weighs_media_emission() const override { return false; }
    bool takes_delta_lobes() const override { return false; }
};

// A ray with a unit direction, and the length its parameter had per unit: media work in
// world distances.
struct UnitRay {
    Ray ray;
    float tmax;
};
UnitRay unit_ray(const Ray& r, float tmax);

// What a ray meets in a medium before its end: nothing, a scattering or an absorption at
// distance t along the unit ray.
enum class MediumEvent { Pass, Scatter, Absorb };
struct MediumCollision {
    MediumEvent event = MediumEvent::Pass;
    float t = 0;
};

// Delta tracking with spectral tracking's probabilities from `ray` (unit) to tmax through `m`:
// updates the throughput `beta` and adds the medium's emission, times beta, to L where
// `emission` is set (the path may still gain a vertex).
MediumCollision track_medium(const Medium& m, const Ray& ray, float tmax, Sampler& sampler,
                             RGB* beta, RGB* L, bool emission);

// The transmittance of `m` along the unit `ray` up to tmax: closed form where it is
// homogeneous, else ratio tracking (with Russian roulette once it is small): never negative,
// unbiased.
RGB medium_transmittance(const Medium& m, const Ray& ray, float tmax, Sampler& sampler);

// The majorant's own collision process along the unit `ray` up to tmax, for estimators that need
// a distance's density in closed form (Metropolis light transport in path space): the first
// collision, with density sigma_maj(t) exp(-int_0^t sigma_maj) over length, null collisions not
// told apart from real ones (the caller weighs the point by its coefficients); nullopt, with
// probability majorant_transmittance, where there is none.
std::optional<float> first_majorant_collision(const Medium& m, const Ray& ray, float tmax,
                                              Sampler& sampler);
// exp(-int_0^tmax sigma_maj) along the unit ray.
float majorant_transmittance(const Medium& m, const Ray& ray, float tmax);
// sigma_maj at distance t of the unit ray (t <= tmax; at a boundary between segments, the
// nearer one's); 0 where the ray is outside the medium.
float majorant_at(const Medium& m, const Ray& ray, float t, float tmax);

// The medium a ray leaving surface point `si` along w is in, `current` being the one the path
// arrived in: the inside or outside of a medium boundary, else unchanged.
const Medium* medium_after(const SurfaceInteraction& si, const Vec3& w, const Medium* current);

// True where the surface only marks a medium boundary (pbrt-v4's "interface" material): rays
// pass through it unchanged.
bool is_interface(const SurfaceInteraction& si);

// The segment from `from` (moved by from_offset off its surface; zero in a medium) to `to` (moved
// by to_offset), starting in `medium`, walked through interface surfaces: stretch(m, u, first,
// last) for each stretch inside a medium m, along the unit ray u.ray up to u.tmax (first: it
// starts at `from`; last: it ends at `to`), which returns false to stop the walk. True when the
// walk reached `to`; false where another surface blocks it or a stretch stopped it.
template <class Stretch>
bool walk_segment(const Scene& scene, Vec3 from, Vec3 from_offset, const Vec3& to,
                  const Vec3& to_offset, const Medium* medium, float time, const Stretch& stretch) {
    // Each interface crossed starts a new stretch; a scene of nested boundaries crosses a few.
    for (int crossing = 0; crossing < 256; ++crossing) {
        const Ray seg = segment_ray(from, from_offset, to, to_offset, time);
        SurfaceInteraction hit;
        const bool blocked = scene.intersect(seg, &hit);
        if (blocked && !is_interface(hit)) return false;
        if (medium &&
            !stretch(*medium, unit_ray(seg, blocked ? hit.t : seg.tmax), crossing == 0, !blocked))
            return false;
        if (!blocked) return true;
        medium = medium_after(hit, seg.d, medium);
        from = hit.p;
        from_offset = hit.offset();
    }
    return false;
}

// The transmittance from `from` to `to` through interface surfaces (walk_segment), zero at any
// other surface.
RGB transmittance(const Scene& scene, const Vec3& from, const Vec3& from_offset, const Vec3& to,
                  const Vec3& to_offset, const Medium* medium, float time, Sampler& sampler);

// Equiangular sampling (Kulla and Fajardo 2012) of the distance along a unit ray, over
// [0, tmax), towards a point light at c: the density falls as 1 / r^2 from c, as the light's
// contribution does, so that scattering next to a light is found at the rate it matters.
struct Equiangular {
    float delta = 0;  // the ray's parameter closest to c
    float dist = 0;   // c's distance from the ray's line
    float theta0 = 0, theta1 = 0;
    bool valid = false;
    Equiangular(const Ray& ray, float tmax, const Vec3& c) {
        delta = dot(c - ray.o, ray.d);
        dist = length(c - ray.at(delta));
        if (!(dist > 1e-6f)) return;
        theta0 = std::atan2(-delta, dist);
        theta1 = tmax < kInfinity ? std::atan2(tmax - delta, dist) : 0.5f * kPi;
        valid = theta1 > theta0;
    }
    float sample(float u) const { return delta + dist * std::tan(lerp(u, theta0, theta1)); }
    // Over unit length.
    float pdf_length(float t) const {
        const float x = t - delta;
        return dist / ((theta1 - theta0) * (dist * dist + x * x));
    }
};

// The position of a light at a point (point, spot, goniometric and projection lights): where
// its emitted rays start, the same for every sample; nullopt for other lights.
std::optional<Vec3> light_position(const Light& light);

// The first surface along `ray` that is not an interface (*found false: the ray escapes), and the
// transmittance up to it (or to infinity) through the media from `medium` on.
RGB transmittance_to_surface(const Scene& scene, Ray ray, const Medium* medium, Sampler& sampler,
                             SurfaceInteraction* hit, bool* found);

}  // namespace ml
