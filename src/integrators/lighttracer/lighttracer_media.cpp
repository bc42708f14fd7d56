// Light tracing through participating media: the light path's distances drawn by delta tracking
// (transport/volume_path.h), a vertex at every surface and every scattering in a medium, each
// joined to the lens through the media's transmittance (ratio tracking, or closed form).

#include <cmath>

#include "integrators/lighttracer/lighttracer.h"
#include "materials/material.h"
#include "transport/spawn.h"
#include "transport/volume_path.h"

namespace ml {

void LightTracerIntegrator::render_sample_media(const RenderContext& ctx, Sampler& sampler,
                                                ScratchBuffer& scratch, SplatList& splats) const {
    const Scene& scene = ctx.scene;
    const float time = ctx.camera.sample_time(sampler.get_1d());
    const float u_select = sampler.get_1d();
    const Vec2 u_pos = sampler.get_2d();
    const Vec2 u_dir = sampler.get_2d();
    const auto sl = m_light_sampler->sample(u_select);
    if (!sl || sl->pmf == 0) return;
    const Light& light = *sl->light;
    const auto les = light.sample_le(u_pos, u_dir);
    if (!les || les->pdf_pos == 0 || les->pdf_dir == 0 || les->L.is_black()) return;
    const float pdf_origin = sl->pmf * les->pdf_pos;
    const bool on_surface = les->n_light != Vec3();

    // Splats what reaches the lens from point p (moved by `offset` off its surface), leaving
    // in medium medium_for(wi) towards it, with f(wi) the light leaving p along wi per unit of
    // importance (the lens' We over its density does the rest).
    auto join_lens = [&](const Vec3& p, const Vec3& offset, auto&& f, auto&& medium_for) {
        const Vec2 u = sampler.get_2d();
        const auto cs = ctx.camera.sample_wi(p, u, time);
        if (!cs || cs->pdf_solid_angle == 0) return;
        RGB L = f(cs->wi) * (cs->We / cs->pdf_solid_angle);
        if (L.is_black()) return;
        L *= transmittance(scene, p, offset, cs->p_lens, Vec3(), medium_for(cs->wi), time, sampler);
        if (!L.is_black()) splats.add(cs->p_raster, L);
    };

    // The light's own emission towards the lens (area lights; a pinhole never sees a point).
    Ray ray = les->ray;
    ray.time = time;
    const Medium* medium = light.medium_towards(ray.d, les->n_light);
    if (light.type() == LightType::Area && light.met_by_rays()) {
        const Vec3 offset = surface_offset(les->n_light, les->p_error);
        join_lens(
            ray.o, offset,
            [&](const Vec3& wi) {
                return light.radiance(ray.o, les->n_light, les->uv, wi) *
                       (abs_dot(wi, les->n_light) / pdf_origin);
            },
            [&](const Vec3& wi) { return light.medium_towards(wi, les->n_light); });
    }
    const float cos_light = on_surface ? abs_dot(les->n_light, ray.d) : 1.f;
    RGB beta = les->L * (cos_light / (pdf_origin * les->pdf_dir));
    if (on_surface)
        ray.o = offset_ray_origin(ray.o, surface_offset(les->n_light, les->p_error), ray.d);

    int depth = 0;  // scattering vertices so far, surface and medium alike
    RGB unused_emission;
    for (int crossings = 0; crossings < 4096 && depth < m_max_depth; ++crossings) {
        if (beta.is_black() || !beta.is_finite()) return;
        SurfaceInteraction si;
        const bool hit = scene.intersect(ray, &si);
        if (medium) {
            const UnitRay u = unit_ray(ray, hit ? si.t : kInfinity);
            const MediumCollision ev =
                track_medium(*medium, u.ray, u.tmax, sampler, &beta, &unused_emission, false);
            if (ev.event == MediumEvent::Absorb) return;
            if (ev.event == MediumEvent::Scatter) {
                ++depth;
                const Vec3 p = u.ray.at(ev.t), wo = -u.ray.d;
                const float g = medium->g();
                const Medium* here = medium;
                join_lens(
                    p, Vec3(), [&](const Vec3& wi) { return beta * hg_phase(wo, wi, g); },
                    [&](const Vec3&) { return here; });
                // The phase function is its own density: the throughput keeps its value.
                ray = Ray{p, sample_hg_phase(wo, g, sampler.get_2d()), kInfinity, time};
                continue;
            }
        }
        if (!hit) return;
        if (is_interface(si)) {
            medium = medium_after(si, ray.d, medium);
            ray = Ray{si.offset_origin(ray.d), ray.d, kInfinity, time};
            continue;
        }
        ++depth;
        const Bsdf bsdf = hit_bsdf(si, scratch);
        if (!bsdf) return;
        const Medium* arrived = medium;
        if (bsdf.has_nonspecular())
            join_lens(
                si.p, si.offset(),
                [&](const Vec3& wi) {
                    return beta * bsdf.eval(si.wo, wi, TransportMode::Importance) *
                           abs_dot(wi, si.ns);
                },
                [&](const Vec3& wi) { return medium_after(si, wi, arrived); });
        const float uc = sampler.get_1d();
        const Vec2 u = sampler.get_2d();
        const auto bs = bsdf.sample(si.wo, uc, u, TransportMode::Importance);
        if (!bs) return;
        beta *= bs->f * (abs_dot(bs->wi, si.ns) / bs->pdf_solid_angle);
        medium = medium_after(si, bs->wi, medium);
        ray = spawn_ray(si, bs->wi);
    }
}

}  // namespace ml
