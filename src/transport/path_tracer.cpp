#include "transport/path_tracer.h"

#include "materials/material.h"
#include "transport/direct_lighting.h"

namespace ml {

RGB continue_path(const Scene& scene, SurfaceInteraction si, int depth, RGB beta, Sampler& sampler,
                  ScratchBuffer& scratch, const LightSampler& light_sampler,
                  const PathTraceOptions& options, const FirstBounceWeight* first) {
    RGB L;
    // The first bounce's weight, kept out of beta: Russian roulette looks at the throughput
    // alone, as in a path without the weight (on the weighted throughput, paths of small weight
    // that survive carry their whole contribution: more fireflies, bench/RESULTS.md, issue 17,
    // session 12).
    float path_weight = 1.f;
    float eta_scale = 1.f;  // radiance scaling by refraction, undone for Russian roulette
    for (;; ++depth) {      // si: the vertex after `depth` scattering vertices
        if (depth >= options.max_depth) break;
        Bsdf bsdf = hit_bsdf(si, scratch);
        if (!bsdf) break;
        const FirstBounceWeight* weight = first;
        first = nullptr;
        if (weight && weight->vanishes(bsdf, si.wo)) break;

        // Next-event estimation: one light chosen for this point, one sample on it.
        float u_select = sampler.get_1d();
        Vec2 u_light = sampler.get_2d();
        if (bsdf.has_nonspecular()) {
            LightSampleWeight ls_weight;
            if (weight)
                ls_weight = [&](const LightLiSample& ls, const RGB& f) {
                    return weight->weight(bsdf, si.wo, ls.wi, false, &f);
                };
            if (options.all_lights) {
                const auto& lights = scene.lights();
                for (size_t i = 0; i < lights.size(); ++i)
                    L += path_weight * beta *
                         estimate_direct(scene, si, bsdf, *lights[i],
                                         i == 0 ? u_light : sampler.get_2d(), true, 1.f, ls_weight);
            } else if (auto sl = light_sampler.sample(light_context(si), u_select)) {
                RGB Ld =
                    estimate_direct(scene, si, bsdf, *sl->light, u_light, true, sl->pmf, ls_weight);
                L += path_weight * beta * Ld / sl->pmf;
            }
        }

        // Continue the path by sampling the BSDF.
        float uc = sampler.get_1d();
        Vec2 u = sampler.get_2d();
        auto bs = bsdf.sample(si.wo, uc, u);
        if (!bs) break;
        beta *= bs->f * (abs_dot(bs->wi, si.ns) / bs->pdf_solid_angle);
        if (weight) path_weight = weight->weight(bsdf, si.wo, bs->wi, bs->is_specular(), nullptr);
        if (path_weight == 0.f) break;
        const bool specular_bounce = bs->is_specular();
        const float prev_pdf = bs->pdf_solid_angle;
        if (bs->is_transmission()) eta_scale *= sqr(bs->eta);
        const LightSampleContext prev_ctx = light_context(si);
        Ray ray = spawn_ray(si, bs->wi);

        // Russian roulette on the throughput without the refraction scaling.
        float rr = (beta * eta_scale).max_component();
        float u_rr = sampler.get_1d();
        if (rr < 1.f && depth >= options.rr_depth) {
            float q = std::max(0.f, 1.f - rr);
            if (u_rr < q) break;
            beta = beta / (1.f - q);
        }
        if (beta.is_black() || !beta.is_finite()) break;

        // The emission the BSDF sample finds, weighted against the light samples.
        bool hit = scene.intersect(ray, &si);
        L += path_weight * beta *
             emission_along(scene, ray, hit ? &si : nullptr, specular_bounce, prev_pdf, prev_ctx,
                            options.all_lights ? nullptr : &light_sampler);
        if (!hit) break;
    }
    return L;
}

}  // namespace ml
