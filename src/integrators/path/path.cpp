#include "integrators/path/path.h"

#include <limits>

#include "transport/direct_lighting.h"
#include "transport/path_tracer.h"
#include "transport/volume_path.h"

namespace ml {

PathIntegrator::PathIntegrator(const Settings& settings) {
    m_max_depth = settings.get_int("maxdepth", 5, {">= 0", "Longest path, in bounces."});
    m_light_sampler_name =
        settings.get_string("lightsampler", "tree",
                            {"tree, bvh, power, uniform, all",
                             "How next-event estimation picks a light: a light tree by importance "
                             "at the point (tree; bvh is pbrt-v4's name for it), by power, "
                             "uniformly, or every light at each vertex (all)."});
    // pbrt-v4's "bvh" light sampler is our light tree.
    if (m_light_sampler_name == "bvh") m_light_sampler_name = "tree";
    settings.get_bool(
        "regularize", false,
        {"", "Accepted for pbrt-v4 scenes; no effect."});  // accepted for pbrt-v4 scenes; no effect
    const std::string guiding = settings.get_string(
        "guiding", "off",
        {"on, off",
         "Path guiding: learn where light arrives from in passes of doubling samples "
         "(a spatial tree of directional quadtrees, Müller et al. 2017) and draw half of the "
         "directions at non-specular vertices from it."});
    if (guiding != "on" && guiding != "off") throw UsageError("path: guiding must be on or off");
    m_guiding = guiding == "on";
    // With guiding, no roulette unless asked for: a guided direction towards bright light is
    // likely, so its throughput is small, and roulette on it ends the very paths the guide found
    // (veach-ajar at equal time: relMSE 0.16 without it, 0.46 with it, 0.38 unguided;
    // bench/RESULTS.md, "Path guiding").
    m_rr_depth = settings.get_int(
        "rrdepth", m_guiding ? std::numeric_limits<int>::max() : 1,
        {">= 0",
         "Depth from which Russian roulette may end a path (with path.guiding=on: none unless "
         "given)."});
    const std::string weights = settings.get_string(
        "guidingpasses", "samples",
        {"samples, variance, last",
         "With guiding, how the passes make the image: every sample alike (unbiased), weighted "
         "by the inverse of their estimated variance (biased low where a pass's fireflies are "
         "missing from its estimate), or the last pass alone."});
    if (weights == "variance")
        m_pass_weights = PassWeights::Variance;
    else if (weights == "samples")
        m_pass_weights = PassWeights::Samples;
    else if (weights == "last")
        m_pass_weights = PassWeights::Last;
    else
        throw UsageError("path: guidingpasses must be variance, samples or last");
    if (m_max_depth < 0) throw UsageError("path: maxdepth must be >= 0");
    if (m_light_sampler_name != "tree" && m_light_sampler_name != "power" &&
        m_light_sampler_name != "uniform" && m_light_sampler_name != "all")
        throw UsageError("path: lightsampler must be tree, power, uniform or all");
    m_options = PathTraceOptions{m_max_depth, m_rr_depth, m_light_sampler_name == "all"};
    m_options.equiangular = settings.get_bool(
        "equiangular", true,
        {"",
         "In participating media: also sample single scattering towards point and spot "
         "lights at distances drawn equiangularly (Kulla and Fajardo 2012), weighed by MIS "
         "against delta tracking; removes the fireflies of haze next to a point light."});
}

RenderResult PathIntegrator::render(const RenderContext& ctx) {
    if (m_guiding && ctx.scene.has_media())
        throw UsageError(
            "path: guiding does not handle participating media yet (path.guiding=off)");
    return m_guiding ? render_guided(ctx) : PixelIntegrator::render(ctx);
}

void PathIntegrator::prepare(const Scene& scene) {
    // "all": every light at each vertex (PathTraceOptions::all_lights); the sampler is unused.
    m_light_sampler = std::make_unique<LightSampler>(
        m_light_sampler_name == "all" ? "power" : m_light_sampler_name, scene.lights());
}

RGB PathIntegrator::li(const Ray& camera_ray, const Scene& scene, Sampler& sampler,
                       ScratchBuffer& scratch, Point2i pixel) const {
    return trace(camera_ray, scene, sampler, scratch, m_options);
}

RGB PathIntegrator::trace(const Ray& camera_ray, const Scene& scene, Sampler& sampler,
                          ScratchBuffer& scratch, const PathTraceOptions& options) const {
    if (scene.has_media())
        return trace_volumetric(scene, camera_ray, sampler, scratch, *m_light_sampler, options);
    SurfaceInteraction si;
    bool hit = scene.intersect(camera_ray, &si);
    RGB L = emission_along(scene, camera_ray, hit ? &si : nullptr, true, 0.f, {},
                           m_light_sampler.get());
    if (!hit) return L;
    return L + continue_path(scene, si, 0, RGB(1.f), sampler, scratch, *m_light_sampler, options);
}

}  // namespace ml
