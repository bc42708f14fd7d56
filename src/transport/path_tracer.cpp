#include "transport/path_tracer.h"

#include "materials/material.h"
#include "transport/direct_lighting.h"
#include "transport/guided_bsdf.h"

#include <array>

namespace ml {

namespace {

// A vertex that records into the guide once its path has ended: the radiance that came back
// along wi is the path's later contributions over the throughput up to the vertex.
struct GuideVertex {
    const SDTree::Region* region;
    Vec3 wi;
    RGB beta;  // throughput with the vertex's own scattering, before Russian roulette
    float pdf;
    RGB L;
};
constexpr int kMaxGuideVertices = 32;

// Guiding pays where the BSDF scatters widely; a near-specular lobe samples its own narrow cone
// far better than a guide of the whole sphere can, so the guide's share of samples there is
// wasted (and its records are few and sharp). Such a lobe is told by its density towards the
// mirror direction: a microfacet lobe's is 1 / (4 pi alpha^2) there (1.6 at alpha 0.22, the
// Trowbridge-Reitz alpha of pbrt-v4's roughness 0.05), a diffuse one's at most 1 / pi.
constexpr float kNearSpecularPdf = 2.f;
bool near_specular(const Bsdf& bsdf, const Vec3& wo, const Vec3& ns) {
    return bsdf.pdf_solid_angle(wo, reflect(wo, ns)) >= kNearSpecularPdf;
}

}  // namespace

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
    std::array<GuideVertex, kMaxGuideVertices> guide_vertices;
    int n_guide_vertices = 0;
    auto add = [&](const RGB& c) {
        L += c;
        for (int i = 0; i < n_guide_vertices; ++i)
            guide_vertices[size_t(i)].L += c / guide_vertices[size_t(i)].beta;
    };
    for (;; ++depth) {  // si: the vertex after `depth` scattering vertices
        if (depth >= options.max_depth) break;
        Bsdf bsdf = hit_bsdf(si, scratch);
        if (!bsdf) break;
        const FirstBounceWeight* weight = first;
        first = nullptr;
        if (weight && weight->vanishes(bsdf, si.wo)) break;

        // The guide's distribution here, where there is one to mix with the BSDF.
        const SDTree::Region* region = nullptr;
        const DirectionTree* guide = nullptr;
        if (options.guide && bsdf.has_nonspecular() && !(bsdf.flags() & kBxdfSpecular)) {
            region = options.guide->region(si.p);  // (it records even where it does not guide)
            if (!near_specular(bsdf, si.wo, si.ns)) guide = SDTree::distribution(region);
        }
        const GuidedBsdf guided(bsdf, guide, options.guide_bsdf_share);
        DirectionPdf direction_pdf;
        if (guide)
            direction_pdf = [&](const Vec3& wi) { return guided.pdf_solid_angle(si.wo, wi); };

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
                    add(path_weight * beta *
                        estimate_direct(scene, si, bsdf, *lights[i],
                                        i == 0 ? u_light : sampler.get_2d(), true, 1.f, ls_weight,
                                        1, direction_pdf));
            } else if (auto sl = light_sampler.sample(light_context(si), u_select)) {
                RGB Ld = estimate_direct(scene, si, bsdf, *sl->light, u_light, true, sl->pmf,
                                         ls_weight, 1, direction_pdf);
                add(path_weight * beta * Ld / sl->pmf);
            }
        }

        // Continue the path by sampling the BSDF, or the guide where there is one (uc picks).
        float uc = sampler.get_1d();
        Vec2 u = sampler.get_2d();
        auto bs = guided.sample(si.wo, uc, u);
        if (!bs) break;
        beta *= bs->f * (abs_dot(bs->wi, si.ns) / bs->pdf_solid_angle);
        if (options.guide_record && region && n_guide_vertices < kMaxGuideVertices)
            guide_vertices[size_t(n_guide_vertices++)] = {region, bs->wi, beta, bs->pdf_solid_angle,
                                                          RGB()};
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
        add(path_weight * beta *
            emission_along(scene, ray, hit ? &si : nullptr, specular_bounce, prev_pdf, prev_ctx,
                           options.all_lights ? nullptr : &light_sampler));
        if (!hit) break;
    }
    // Each vertex records its estimate of the light along wi over the density wi had.
    for (int i = 0; i < n_guide_vertices; ++i) {
        const GuideVertex& v = guide_vertices[size_t(i)];
        SDTree::record(v.region, v.wi, (double(v.L.r) + v.L.g + v.L.b) / (3.0 * v.pdf));
    }
    return L;
}

}  // namespace ml
