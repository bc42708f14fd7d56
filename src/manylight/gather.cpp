#include "manylight/gather.h"

#include "materials/material.h"
#include "transport/direct_lighting.h"

namespace ml {

namespace detail {

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
