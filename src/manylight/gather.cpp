#include "manylight/gather.h"

#include "materials/material.h"
#include "media/phase_bxdf.h"
#include "transport/direct_lighting.h"
#include "transport/volume_path.h"

namespace ml {

const Medium* medium_towards(const GatherPoint& g, const Vec3& wi) {
    // A point in a medium has no mesh: medium_after keeps its medium.
    return medium_after(g.si, wi, g.medium);
}

RGB point_light_transmittance(const Scene& scene, const GatherPoint& g, const PointLight& pl) {
    const SurfaceInteraction& si = g.si;
    if (pl.kind != PointLightKind::Directional)
        return transmittance(scene, si.p, si.offset(), pl.p, pl.offset,
                             medium_towards(g, normalize(pl.p - si.p)), si.time, *g.sampler);
    // A point past the scene's bounds along the light's reverse direction.
    const Bounds3 b = scene.bounds();
    const Vec3 centre = (b.lo + b.hi) * 0.5f;
    const float radius = length(b.hi - b.lo) * 0.5f;
    const Vec3 wi = -pl.n;
    const Vec3 far = si.p + wi * (2 * std::max(radius, 1.f) + length(si.p - centre));
    return transmittance(scene, si.p, si.offset(), far, Vec3(), medium_towards(g, wi), si.time,
                         *g.sampler);
}

namespace detail {

bool next_gather_hit_media(const Scene& scene, Ray ray, Sampler& sampler, ScratchBuffer& scratch,
                           const Medium** medium, RGB* beta, RGB* L, GatherPoint* g) {
    // Interfaces crossed in a row; a scene of nested boundaries crosses a few.
    for (int crossing = 0; crossing < 256; ++crossing) {
        SurfaceInteraction si;
        const bool hit = scene.intersect(ray, &si);
        if (*medium) {
            const UnitRay u = unit_ray(ray, hit ? si.t : kInfinity);
            // Emission inside media is refused by the many-light integrators (no VPL carries it).
            RGB unused;
            const MediumCollision ev =
                track_medium(**medium, u.ray, u.tmax, sampler, beta, &unused, false);
            if (ev.event == MediumEvent::Absorb || beta->is_black() || !beta->is_finite())
                return false;
            if (ev.event == MediumEvent::Scatter) {
                *g = GatherPoint();
                g->si.p = u.ray.at(ev.t);
                g->si.wo = -u.ray.d;
                g->si.ng = g->si.ns = g->si.wo;
                g->si.time = ray.time;
                g->bsdf = phase_bsdf(g->si.wo, (*medium)->g(), scratch);
                g->medium = *medium;
                g->in_medium = true;
                return true;
            }
        }
        // Only the camera ray and delta chains get here: emission counts whole.
        *L += *beta * emission_along(scene, ray, hit ? &si : nullptr, true, 0.f, {}, nullptr);
        if (!hit) return false;
        if (is_interface(si)) {
            *medium = medium_after(si, ray.d, *medium);
            ray = Ray{si.offset_origin(ray.d), ray.d, kInfinity, ray.time};
            continue;
        }
        *g = GatherPoint();
        g->si = si;
        g->bsdf = hit_bsdf(g->si, scratch);
        g->medium = *medium;
        return bool(g->bsdf);
    }
    return false;
}

bool next_gather_hit(const Scene& scene, const Ray& ray, ScratchBuffer& scratch, const RGB& beta,
                     RGB* L, GatherPoint* g) {
    bool hit = scene.intersect(ray, &g->si);
    // Only the camera ray and delta chains get here, so emission counts whole: the point lights
    // stand for emitters seen through non-delta lobes only.
    *L += beta * emission_along(scene, ray, hit ? &g->si : nullptr, true, 0.f, {}, nullptr);
    if (!hit) return false;
    g->bsdf = hit_bsdf(g->si, scratch);
    return bool(g->bsdf);
}

bool continue_through_delta(const GatherPoint& g, Sampler& sampler, RGB* beta, Ray* ray) {
    float uc = sampler.get_1d();
    auto bs = g.bsdf.sample(g.si.wo, uc, sampler.get_2d());
    if (!bs || !bs->is_specular()) return false;
    *beta *= bs->f * (abs_dot(bs->wi, g.si.ns) / bs->pdf_solid_angle);
    if (beta->is_black() || !beta->is_finite()) return false;
    *ray = spawn_ray(g.si, bs->wi);
    return true;
}

}  // namespace detail

bool point_light_contribution(const PointLightSet& set, const PointLight& pl, const GatherPoint& g,
                              RGB* value, Ray* shadow, PointLightTerms* terms) {
    const SurfaceInteraction& si = g.si;
    Vec3 wi;
    RGB I;
    float inv_d2 = 1;
    if (pl.kind == PointLightKind::Directional) {
        wi = -pl.n;
        I = pl.intensity;
        *shadow = Ray{si.offset_origin(wi), wi, kInfinity, si.time};
    } else {
        Vec3 d = pl.p - si.p;
        float d2 = length_squared(d);
        if (!(d2 > 0)) return false;
        wi = d / std::sqrt(d2);
        I = point_light_intensity(set, pl, -wi);
        if (I.is_black()) return false;
        inv_d2 = 1 / d2;
        I = I / d2;
    }
    RGB f_bsdf = g.bsdf.eval(si.wo, wi);
    RGB f = f_bsdf * abs_dot(wi, si.ns);
    if (f.is_black()) return false;
    *value = g.beta * f * I;
    if (terms) *terms = {wi, inv_d2, f_bsdf};
    // The shadow ray last: the lights the BSDF turns away need none (a fifth of the pairs of an
    // igi frame of the kitchen).
    if (pl.kind != PointLightKind::Directional)
        *shadow = segment_ray(si.p, si.offset(), pl.p, pl.offset, si.time);
    return true;
}

}  // namespace ml
