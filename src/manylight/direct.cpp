#include "manylight/direct.h"

#include "lights/light.h"
#include "transport/direct_lighting.h"
#include "transport/volume_path.h"

namespace ml {

SampledDirectLight::SampledDirectLight(const Scene& scene, int samples, bool mis)
    : m_samples(samples), m_mis(mis) {
    std::vector<float> weights;
    for (const auto& l : scene.lights()) {
        float w = is_delta_light(l->type()) ? 0.f : std::max(0.f, l->power().luminance());
        // A non-delta light with no measurable power is still chosen now and then.
        if (!is_delta_light(l->type())) {
            w = std::max(w, 1e-20f);
            ++m_count;
        }
        weights.push_back(w);
    }
    if (m_count) m_choice = Distribution1D(weights);
}

float SampledDirectLight::pmf(int index) const {
    if (!m_count || index < 0 || size_t(index) >= m_choice.size()) return 0.f;
    return m_choice.pmf(size_t(index));
}

RGB SampledDirectLight::estimate(const Scene& scene, const GatherPoint& g, Sampler& sampler) const {
    if (!m_count) return RGB();
    if (g.sampler) return estimate_through_media(scene, g, sampler);
    const SurfaceInteraction& si = g.si;
    const auto& lights = scene.lights();
    RGB L;
    // Without MIS everywhere, a receiver with no glossy lobe takes its light samples alone:
    // there f is bounded and the light's own density does well; a glossy one keeps the BSDF
    // sample, without which a light sample of low density on a sharp lobe makes fireflies.
    const bool mis = m_mis || (g.bsdf.flags() & kBxdfGlossy);
    for (int i = 0; i < m_samples; ++i) {
        float u_select = sampler.get_1d();
        Vec2 u_light = sampler.get_2d();
        float uc = sampler.get_1d();
        Vec2 u_bsdf = sampler.get_2d();
        // Light sampling.
        float chosen = 0;
        size_t index = m_choice.sample_discrete(u_select, &chosen);
        if (chosen > 0)
            L += estimate_direct(scene, si, g.bsdf, *lights[index], u_light, mis, chosen) / chosen;
        if (!mis) continue;
        // BSDF sampling: its non-delta lobes only (a delta lobe is the camera path's to follow).
        auto bs = g.bsdf.sample(si.wo, uc, u_bsdf);
        if (!bs || bs->is_specular() || bs->pdf_solid_angle <= 0) continue;
        RGB f = bs->f * (abs_dot(bs->wi, si.ns) / bs->pdf_solid_angle);
        if (f.is_black()) continue;
        Ray ray = spawn_ray(si, bs->wi);
        SurfaceInteraction hit;
        LightSampleContext ctx = light_context(si);
        ctx.allow_incomplete_pdf = true;  // as estimate_direct's light samples above
        auto weighted = [&](const Light* light, const RGB& Le, const Vec3& p, const Vec3& n) {
            float p_light = pmf(light->index) * light->pdf_li(ctx, ray.d, p, n, hit.prim_id);
            return Le * power_heuristic(bs->pdf_solid_angle, p_light);
        };
        // Only an emitter's hit counts: the others skip the interaction's setup.
        if (!scene.intersect_emitter(ray, &hit)) {
            for (const Light* light : scene.infinite_lights()) {
                RGB Le = light->radiance_escaped(ray);
                if (!Le.is_black()) L += f * weighted(light, Le, Vec3(), Vec3());
            }
        } else if (hit.area_light) {
            RGB Le = hit.area_light->radiance(hit.p, hit.ng, hit.uv, hit.wo);
            if (!Le.is_black()) L += f * weighted(hit.area_light, Le, hit.p, hit.ng);
        }
    }
    return g.beta * L / float(m_samples);
}

RGB SampledDirectLight::estimate_through_media(const Scene& scene, const GatherPoint& g,
                                               Sampler& sampler) const {
    const SurfaceInteraction& si = g.si;
    const auto& lights = scene.lights();
    // A point in a medium has no surface: its context is the point alone.
    LightSampleContext ctx =
        g.in_medium ? LightSampleContext{si.p, Vec3(), Vec3()} : light_context(si);
    const bool mis = m_mis || (g.bsdf.flags() & kBxdfGlossy);
    ctx.allow_incomplete_pdf = mis;
    RGB L;
    for (int i = 0; i < m_samples; ++i) {
        const float u_select = sampler.get_1d();
        const Vec2 u_light = sampler.get_2d();
        const float uc = sampler.get_1d();
        const Vec2 u_bsdf = sampler.get_2d();
        // Light sampling, through the media's transmittance.
        float chosen = 0;
        const size_t index = m_choice.sample_discrete(u_select, &chosen);
        if (chosen > 0) {
            const Light& light = *lights[index];
            const auto ls = light.sample_li(ctx, u_light);
            if (ls && !ls->L.is_black() && ls->pdf_solid_angle > 0) {
                const RGB f = g.bsdf.eval(si.wo, ls->wi) * abs_dot(ls->wi, si.ns);
                const RGB tr = f.is_black() ? RGB()
                                            : transmittance(scene, si.p, si.offset(), ls->p_light,
                                                            ls->offset(), medium_towards(g, ls->wi),
                                                            si.time, sampler);
                if (!tr.is_black()) {
                    const float light_pdf = chosen * ls->pdf_solid_angle;
                    const float w =
                        !mis || !light.met_by_rays()
                            ? 1.f
                            : power_heuristic(light_pdf, g.bsdf.pdf_solid_angle(si.wo, ls->wi));
                    L += f * ls->L * tr * (w / light_pdf);
                }
            }
        }
        if (!mis) continue;
        // BSDF (or phase function) sampling: the first surface past the media's interfaces.
        const auto bs = g.bsdf.sample(si.wo, uc, u_bsdf);
        if (!bs || bs->is_specular() || bs->pdf_solid_angle <= 0) continue;
        const RGB f = bs->f * (abs_dot(bs->wi, si.ns) / bs->pdf_solid_angle);
        if (f.is_black()) continue;
        const Ray ray = spawn_ray(si, bs->wi);
        SurfaceInteraction hit;
        bool found = false;
        const RGB tr =
            transmittance_to_surface(scene, ray, medium_towards(g, bs->wi), sampler, &hit, &found);
        if (tr.is_black()) continue;
        LightSampleContext incomplete = ctx;
        incomplete.allow_incomplete_pdf = true;
        auto weighted = [&](const Light* light, const RGB& Le, const Vec3& p, const Vec3& n) {
            const float p_light =
                pmf(light->index) * light->pdf_li(incomplete, ray.d, p, n, hit.prim_id);
            return Le * power_heuristic(bs->pdf_solid_angle, p_light);
        };
        if (!found) {
            for (const Light* light : scene.infinite_lights()) {
                const RGB Le = light->radiance_escaped(ray);
                if (!Le.is_black()) L += f * tr * weighted(light, Le, Vec3(), Vec3());
            }
        } else if (hit.area_light) {
            const RGB Le = hit.area_light->radiance(hit.p, hit.ng, hit.uv, hit.wo);
            if (!Le.is_black()) L += f * tr * weighted(hit.area_light, Le, hit.p, hit.ng);
        }
    }
    return g.beta * L / float(m_samples);
}

}  // namespace ml
