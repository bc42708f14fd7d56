// Shading with point lights: where a camera path gathers (every hit with a non-delta part along
// its delta chain), and what one point light gives there. Shared by the brute-force `vpl`
// integrator and `lightcuts`, so both shade with exactly the same arithmetic.
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "core/scratch.h"
#include "lights/point_lights.h"
#include "materials/bsdf.h"
#include "sampling/sampler.h"
#include "scene/scene.h"

namespace ml {

class Medium;

struct GatherPoint {
    SurfaceInteraction si;
    Bsdf bsdf;
    RGB beta;  // throughput of the delta chain that led here (1 for a direct hit)
    // In a scene with participating media: the medium the camera path arrived in, and whether
    // the point is a scattering inside it rather than on a surface. A point in a medium has only
    // si.p, si.wo, si.time and a normal along wo; its bsdf is the medium's phase function
    // (transport/phase_bxdf.h), so that f |cos| is the phase function. `sampler` draws the shadow
    // rays' transmittance (ratio tracking through media that are not homogeneous).
    const Medium* medium = nullptr;
    bool in_medium = false;
    Sampler* sampler = nullptr;
};

// A gather point at p inside `medium`, reached along the unit ray direction d: si has p, wo =
// -d, the normals along wo and the time, its bsdf the medium's phase function.
GatherPoint medium_gather_point(const Vec3& p, const Vec3& d, float time, const Medium* medium,
                                const RGB& beta, ScratchBuffer& scratch);

// The medium a ray leaving g towards unit direction wi starts in.
const Medium* medium_towards(const GatherPoint& g, const Vec3& wi);

// The gather points of a camera path: it follows `ray` through delta surfaces (mirrors, glass)
// for at most `max_depth` bounces, adding the emission it sees to *L (times throughput), and
// calls shade(g, u) at every hit with a non-delta part, which returns the radiance the point
// lights give there (times g.beta); u is a sample in [0, 1) for the shading's own choices (drawn
// for every integrator, so that `vpl` and `lightcuts` consume their samplers alike and gather at
// the same points). A surface with both (a diffuse base under a smooth coat) is
// gathered at and also continued through: its BSDF is sampled, and a delta sample carries the
// path on (weighted by f / pdf, which counts the lobe's choice), while a non-delta one ends it,
// since the gather has that part. Returns the radiance along `ray`.
// How a camera path gathers: `max_depth` delta bounces at most; in homogeneous media,
// `medium_points` gather points on each stretch of a ray through them (0: one where delta
// tracking finds the ray scatter, the ray ending there; see detail::next_gather_hit_media).
// A light at a point that gather points in homogeneous media are also drawn towards,
// equiangularly (see medium_gather_targets), with the probability of choosing it.
struct EquiangularTarget {
    Vec3 p;
    float pmf = 0;
};
struct GatherOptions {
    int max_depth = 5;
    int medium_points = 0;
    // Not null and not empty (with medium_points > 0): each stretch through a homogeneous medium
    // also gets one gather point drawn equiangularly towards a target chosen by its pmf, every
    // point of the stretch weighted by the balance heuristic over both strategies.
    const std::vector<EquiangularTarget>* toward = nullptr;
};
// The scene's lights at a point (point, spot, goniometric, projection), chosen in proportion to
// power, as targets for gather points in media; none in a scene without media or with more than
// 64 of them (every gather point's weight sums the densities over all targets).
std::vector<EquiangularTarget> medium_gather_targets(const Scene& scene);
template <typename Shade>
RGB gather_along(const Scene& scene, Ray ray, Sampler& sampler, ScratchBuffer& scratch,
                 const GatherOptions& options, Shade&& shade);
template <typename Shade>
RGB gather_along(const Scene& scene, Ray ray, Sampler& sampler, ScratchBuffer& scratch,
                 int max_depth, Shade&& shade);

// What point_light_contribution computes on the way, for a caller that weighs the pair by the
// same terms (bdlightcuts' split weights) without evaluating the BSDF again.
struct PointLightTerms {
    Vec3 wi;           // unit, from the gather point towards the light
    float inv_d2 = 1;  // 1 / distance squared (directional: 1)
    RGB f;             // the gather point's BSDF value f(wo, wi), without the cosine
};

// What `pl` gives at the gather point without visibility: f(wo, wi) |cos| I / d^2 (directional:
// f |cos| E), and the shadow ray that decides visibility. False when it gives nothing; else
// `terms`, where given, receives the terms above.
bool point_light_contribution(const PointLightSet& set, const PointLight& pl, const GatherPoint& g,
                              RGB* value, Ray* shadow, PointLightTerms* terms = nullptr);

// In a scene with media (g.sampler set by gather_along): the transmittance between g and `pl`
// through the media and the interfaces that bound them, zero where anything else blocks it; it
// stands for the shadow ray of point_light_contribution.
RGB point_light_transmittance(const Scene& scene, const GatherPoint& g, const PointLight& pl);

template <typename Shade>
RGB gather_along(const Scene& scene, Ray ray, Sampler& sampler, ScratchBuffer& scratch,
                 int max_depth, Shade&& shade) {
    return gather_along(scene, ray, sampler, scratch, GatherOptions{max_depth, 0, nullptr},
                        std::forward<Shade>(shade));
}

// Implementation of gather_along: the next hit along a delta chain, in gather.cpp.
namespace detail {
// The surface hit by `ray` and its BSDF (false when the ray escapes or hits no material); adds
// the emission met to *L times beta.
bool next_gather_hit(const Scene& scene, const Ray& ray, ScratchBuffer& scratch, const RGB& beta,
                     RGB* L, GatherPoint* g);
// The same in a scene with media, the ray starting in *medium, through the interfaces that only
// bound media (*medium follows them). In a homogeneous medium with `medium_points` > 0, that many
// gather points in_medium are appended to *points on each stretch of the ray in it, at distances
// drawn stratified from the transmittance (each weighted by transmittance times sigma_s over
// its density and their count), and the ray goes on to the surface weighted by the stretch's
// transmittance. Elsewhere delta tracking finds one scattering (appended to *points, the ray
// ending there) or lets the ray pass, *beta taking its weights. Returns the surface's gather
// point as next_gather_hit does.
bool next_gather_hit_media(const Scene& scene, Ray ray, Sampler& sampler, ScratchBuffer& scratch,
                           const GatherOptions& options, const Medium** medium, RGB* beta, RGB* L,
                           GatherPoint* g, std::vector<GatherPoint>* points, bool media_emission);
// The light that participating media emit, brought to gather point g (reached after `depth`
// scattering vertices) by paths continued past it through its non-delta lobes: the point lights
// carry none of it (no light path starts in a medium).
RGB media_emission_after(const Scene& scene, const GatherPoint& g, int depth, int max_depth,
                         Sampler& sampler, ScratchBuffer& scratch);
// Samples g's BSDF: true with the new ray and throughput when the sample is a delta lobe.
bool continue_through_delta(const GatherPoint& g, Sampler& sampler, RGB* beta, Ray* ray);
}  // namespace detail

template <typename Shade>
RGB gather_along(const Scene& scene, Ray ray, Sampler& sampler, ScratchBuffer& scratch,
                 const GatherOptions& options, Shade&& shade) {
    RGB L, beta(1.f);
    GatherPoint g;
    const bool media = scene.has_media();
    const Medium* medium = scene.camera_medium();
    // In media only; kept per thread so that camera rays do not allocate (gather_along does not
    // nest: no shade() gathers again).
    thread_local std::vector<GatherPoint> points;
    // Light emitted by media: along the camera path as it goes, and past each gather point.
    const bool glowing = media && scene.has_emitting_media();
    for (int depth = 0;; ++depth) {
        if (media) {
            points.clear();
            const bool surface = detail::next_gather_hit_media(
                scene, ray, sampler, scratch, options, &medium, &beta, &L, &g, &points,
                glowing && depth < options.max_depth);
            for (GatherPoint& p : points) {
                p.sampler = &sampler;
                float u = sampler.get_1d();
                L += shade(p, u);
                if (glowing)
                    L += detail::media_emission_after(scene, p, depth, options.max_depth, sampler,
                                                      scratch);
            }
            if (!surface) return L;
            g.sampler = &sampler;
        } else if (!detail::next_gather_hit(scene, ray, scratch, beta, &L, &g)) {
            return L;
        }
        g.beta = beta;
        if (g.bsdf.has_nonspecular()) {
            float u = sampler.get_1d();
            L += shade(g, u);
            if (glowing)
                L += detail::media_emission_after(scene, g, depth, options.max_depth, sampler,
                                                  scratch);
        }
        if (depth == options.max_depth || !(g.bsdf.flags() & kBxdfSpecular)) return L;
        if (!detail::continue_through_delta(g, sampler, &beta, &ray)) return L;
        if (media) medium = medium_towards(g, ray.d);
    }
}

}  // namespace ml
