#include "manylight/gather.h"

#include "integrators/common.h"
#include "materials/material.h"

namespace ml {

std::optional<GatherPoint> trace_to_gather_point(const Scene& scene, Ray ray, Sampler& sampler,
                                                 ScratchBuffer& scratch, int max_depth, RGB* L) {
    GatherPoint g;
    g.beta = RGB(1.f);
    for (int depth = 0;; ++depth) {
        bool hit = scene.intersect(ray, &g.si);
        // Only the camera ray and delta chains get here, so emission counts whole.
        *L += g.beta * emission_along(scene, ray, hit ? &g.si : nullptr, true, 0.f, {}, nullptr);
        if (!hit) return std::nullopt;
        g.bsdf = hit_bsdf(g.si, scratch);
        if (!g.bsdf) return std::nullopt;
        if (g.bsdf.has_nonspecular()) return g;
        if (depth == max_depth) return std::nullopt;
        float uc = sampler.get_1d();
        auto bs = g.bsdf.sample(g.si.wo, uc, sampler.get_2d());
        if (!bs) return std::nullopt;
        g.beta *= bs->f * (abs_dot(bs->wi, g.si.ns) / bs->pdf_solid_angle);
        if (g.beta.is_black() || !g.beta.is_finite()) return std::nullopt;
        ray = spawn_ray(g.si, bs->wi);
    }
}

bool point_light_contribution(const PointLightSet& set, const PointLight& pl, const GatherPoint& g,
                              RGB* value, Ray* shadow) {
    const SurfaceInteraction& si = g.si;
    Vec3 wi;
    RGB I;
    if (pl.kind == PointLightKind::Directional) {
        wi = -pl.n;
        I = pl.intensity;
        Vec3 o = si.offset_origin(wi);
        *shadow = Ray{o, wi, kInfinity, si.time};
    } else {
        Vec3 d = pl.p - si.p;
        float d2 = length_squared(d);
        if (!(d2 > 0)) return false;
        wi = d / std::sqrt(d2);
        I = point_light_intensity(set, pl, -wi);
        if (I.is_black()) return false;
        I = I / d2;
        Vec3 o = si.offset_origin(wi);
        *shadow = Ray{o, pl.p - o, 1.f - 1e-4f, si.time};
    }
    RGB f = g.bsdf.eval(si.wo, wi) * abs_dot(wi, si.ns);
    if (f.is_black()) return false;
    *value = g.beta * f * I;
    return true;
}

}  // namespace ml
