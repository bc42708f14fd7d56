#include "transport/direct_lighting.h"

#include "lights/light_sampler.h"
#include "transport/volume_path.h"

namespace ml {

RGB emission_along(const Scene& scene, const Ray& ray, const SurfaceInteraction* hit,
                   bool full_weight, float prev_pdf, const LightSampleContext& prev_ctx,
                   const LightSampler* light_sampler) {
    auto weighted = [&](const Light* light, const RGB& Le, const Vec3& p, const Vec3& n,
                        uint32_t prim) {
        if (full_weight) return Le;
        float pmf = light_sampler ? light_sampler->pmf(prev_ctx, light) : 1.f;
        // The light samples this weighs against were drawn with the incomplete density
        // (estimate_direct with MIS).
        LightSampleContext ctx = prev_ctx;
        ctx.allow_incomplete_pdf = true;
        return Le * power_heuristic(prev_pdf, pmf * light->pdf_li(ctx, ray.d, p, n, prim));
    };
    RGB L;
    if (!hit) {
        for (const Light* light : scene.infinite_lights()) {
            RGB Le = light->radiance_escaped(ray);
            if (!Le.is_black()) L += weighted(light, Le, Vec3(), Vec3(), 0);
        }
    } else if (hit->area_light) {
        RGB Le = hit->area_light->radiance(hit->p, hit->ng, hit->uv, hit->wo);
        if (!Le.is_black()) L = weighted(hit->area_light, Le, hit->p, hit->ng, hit->prim_id);
    }
    return L;
}

RGB estimate_direct(const Scene& scene, const SurfaceInteraction& si, const Bsdf& bsdf,
                    const Light& light, const Vec2& u_light, bool mis, float light_pmf,
                    const LightSampleWeight& weight, int bsdf_samples,
                    const DirectionPdf& direction_pdf, const DirectMedia* media) {
    LightSampleContext ctx = vertex_context(si, media && media->in_medium);
    ctx.allow_incomplete_pdf = mis;
    auto ls = light.sample_li(ctx, u_light);
    if (!ls || ls->L.is_black() || ls->pdf_solid_angle == 0) return RGB();
    const RGB f_bsdf = bsdf.eval(si.wo, ls->wi);
    RGB f = f_bsdf * abs_dot(ls->wi, si.ns);
    if (f.is_black()) return RGB();
    const float sample_weight = weight ? weight(*ls, f_bsdf) : 1.f;
    if (sample_weight == 0.f) return RGB();
    RGB tr(1.f);
    if (media) {
        const Medium* start =
            media->in_medium ? media->arrived : medium_after(si, ls->wi, media->arrived);
        tr = transmittance(scene, si.p, si.offset(), ls->p_light, ls->offset(), start, si.time,
                           *media->sampler);
        if (tr.is_black()) return RGB();
    } else if (!scene.visible(si, ls->p_light, ls->offset())) {
        return RGB();
    }
    RGB Ld;
    if (!mis || !light.met_by_rays()) {
        Ld = f * ls->L / ls->pdf_solid_angle;
    } else {
        const float pdf_dir =
            direction_pdf ? direction_pdf(ls->wi) : bsdf.pdf_solid_angle(si.wo, ls->wi);
        float w = power_heuristic(light_pmf * ls->pdf_solid_angle, float(bsdf_samples) * pdf_dir);
        Ld = f * ls->L * (w / ls->pdf_solid_angle);
    }
    if (media) Ld *= tr;
    return weight ? Ld * sample_weight : Ld;
}

}  // namespace ml
