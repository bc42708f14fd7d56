#include "integrators/whitted/whitted.h"

#include "materials/material.h"
#include "transport/direct_lighting.h"

namespace ml {

WhittedIntegrator::WhittedIntegrator(const Settings& settings) {
    m_max_depth =
        settings.get_int("maxdepth", 5, {">= 0", "Most mirror and glass bounces followed."});
    if (m_max_depth < 0) throw UsageError("whitted: maxdepth must be >= 0");
}

RGB WhittedIntegrator::li(const Ray& camera_ray, const Scene& scene, Sampler& sampler,
                          ScratchBuffer& scratch, Point2i pixel) const {
    RGB L, beta(1.f);
    Ray ray = camera_ray;
    SurfaceInteraction si;
    // Only the camera ray and perfect-specular chains reach here, so emission counts whole.
    for (int depth = 0;; ++depth) {
        bool hit = scene.intersect(ray, &si);
        L += beta * emission_along(scene, ray, hit ? &si : nullptr, true, 0.f, {}, nullptr);
        if (!hit || depth == m_max_depth) break;
        Bsdf bsdf = hit_bsdf(si, scratch);
        if (!bsdf) break;
        if (bsdf.has_nonspecular())
            for (const auto& light : scene.lights())
                L += beta * estimate_direct(scene, si, bsdf, *light, sampler.get_2d(), false);
        if (!(bsdf.flags() & kBxdfSpecular)) break;
        // Mirror or glass: follow the specular lobe (the lobe chosen by the sample, weighted by
        // the inverse of its probability, so reflection and refraction both converge).
        float uc = sampler.get_1d();
        auto bs = bsdf.sample(si.wo, uc, sampler.get_2d());
        if (!bs || !bs->is_specular()) break;
        beta *= bs->f * (abs_dot(bs->wi, si.ns) / bs->pdf_solid_angle);
        ray = spawn_ray(si, bs->wi);
        if (beta.is_black() || !beta.is_finite()) break;
    }
    return L;
}

}  // namespace ml
