#include "integrators/direct/direct.h"

#include "materials/material.h"
#include "transport/direct_lighting.h"

namespace ml {

DirectIntegrator::DirectIntegrator(const Settings& settings) {
    m_max_depth =
        settings.get_int("maxdepth", 5, {">= 0", "Most specular and glossy bounces followed."});
    if (m_max_depth < 0) throw UsageError("direct: maxdepth must be >= 0");
}

RGB DirectIntegrator::li(const Ray& camera_ray, const Scene& scene, Sampler& sampler,
                         ScratchBuffer& scratch, Point2i pixel) const {
    RGB L, beta(1.f);
    Ray ray = camera_ray;
    bool specular_bounce = false;
    float prev_pdf = 0.f;
    LightSampleContext prev_ctx;
    SurfaceInteraction si;
    bool last = false;  // set after a diffuse sample: take its emission, then stop
    for (int depth = 0;; ++depth) {
        bool hit = scene.intersect(ray, &si);
        L += beta * emission_along(scene, ray, hit ? &si : nullptr, depth == 0 || specular_bounce,
                                   prev_pdf, prev_ctx, nullptr);
        if (!hit || last || depth == m_max_depth) break;
        Bsdf bsdf = hit_bsdf(si, scratch);
        if (!bsdf) break;

        // Direct light: one MIS sample of every light.
        if (bsdf.has_nonspecular())
            for (const auto& light : scene.lights())
                L += beta * estimate_direct(scene, si, bsdf, *light, sampler.get_2d());

        // One BSDF sample: followed on from glossy and specular lobes; from a diffuse lobe it
        // only collects the emission it hits (the MIS partner of the light samples above).
        float uc = sampler.get_1d();
        Vec2 u = sampler.get_2d();
        auto bs = bsdf.sample(si.wo, uc, u);
        if (!bs) break;
        last = !(bs->flags & (kBxdfSpecular | kBxdfGlossy));
        beta *= bs->f * (abs_dot(bs->wi, si.ns) / bs->pdf_solid_angle);
        specular_bounce = bs->is_specular();
        prev_pdf = bs->pdf_solid_angle;
        prev_ctx = light_context(si);
        ray = spawn_ray(si, bs->wi);
        if (beta.is_black() || !beta.is_finite()) break;
    }
    return L;
}

}  // namespace ml
