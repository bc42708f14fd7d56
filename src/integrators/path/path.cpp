#include "integrators/path/path.h"

#include "materials/material.h"
#include "transport/direct_lighting.h"

namespace ml {

PathIntegrator::PathIntegrator(const Settings& settings) {
    m_max_depth = settings.get_int("maxdepth", 5);
    m_rr_depth = settings.get_int("rrdepth", 1);
    m_light_sampler_name = settings.get_string("lightsampler", "tree");
    // pbrt-v4's "bvh" light sampler is our light tree.
    if (m_light_sampler_name == "bvh") m_light_sampler_name = "tree";
    settings.get_bool("regularize", false);  // accepted for pbrt-v4 scenes; no effect
    if (m_max_depth < 0) throw UsageError("path: maxdepth must be >= 0");
    if (m_light_sampler_name != "tree" && m_light_sampler_name != "power" &&
        m_light_sampler_name != "uniform")
        throw UsageError("path: lightsampler must be tree, power or uniform");
}

void PathIntegrator::prepare(const Scene& scene) {
    m_light_sampler = std::make_unique<LightSampler>(m_light_sampler_name, scene.lights());
}

RGB PathIntegrator::li(const Ray& camera_ray, const Scene& scene, Sampler& sampler,
                       ScratchBuffer& scratch, Point2i pixel) const {
    RGB L, beta(1.f);
    Ray ray = camera_ray;
    bool specular_bounce = false;
    float eta_scale = 1.f;  // radiance scaling by refraction, undone for Russian roulette
    float prev_pdf = 0.f;   // solid-angle pdf of the BSDF sample that made `ray`
    LightSampleContext prev_ctx;
    SurfaceInteraction si;
    for (int depth = 0;; ++depth) {
        bool hit = scene.intersect(ray, &si);
        L += beta * emission_along(scene, ray, hit ? &si : nullptr, depth == 0 || specular_bounce,
                                   prev_pdf, prev_ctx, m_light_sampler.get());
        if (!hit) break;
        if (depth == m_max_depth) break;

        Bsdf bsdf = hit_bsdf(si, scratch);
        if (!bsdf) break;

        // Next-event estimation: one light chosen for this point, one sample on it.
        float u_select = sampler.get_1d();
        Vec2 u_light = sampler.get_2d();
        if (bsdf.has_nonspecular()) {
            if (auto sl = m_light_sampler->sample(light_context(si), u_select))
                L += beta * estimate_direct(scene, si, bsdf, *sl->light, u_light, true, sl->pmf) /
                     sl->pmf;
        }

        // Continue the path by sampling the BSDF.
        float uc = sampler.get_1d();
        Vec2 u = sampler.get_2d();
        auto bs = bsdf.sample(si.wo, uc, u);
        if (!bs) break;
        beta *= bs->f * (abs_dot(bs->wi, si.ns) / bs->pdf_solid_angle);
        specular_bounce = bs->is_specular();
        prev_pdf = bs->pdf_solid_angle;
        if (bs->is_transmission()) eta_scale *= sqr(bs->eta);
        prev_ctx = light_context(si);
        ray = spawn_ray(si, bs->wi);

        // Russian roulette on the throughput without the refraction scaling.
        float rr = (beta * eta_scale).max_component();
        float u_rr = sampler.get_1d();
        if (rr < 1.f && depth >= m_rr_depth) {
            float q = std::max(0.f, 1.f - rr);
            if (u_rr < q) break;
            beta = beta / (1.f - q);
        }
        if (beta.is_black() || !beta.is_finite()) break;
    }
    return L;
}

}  // namespace ml
