#include "integrators/lighttracer/lighttracer.h"

#include "bidir/subpaths.h"

namespace ml {

LightTracerIntegrator::LightTracerIntegrator(const Settings& settings) {
    m_max_depth = settings.get_int("maxdepth", 5, {">= 0", "Longest light path, in bounces."});
    m_light_sampler_name = settings.get_string(
        "lightsampler", "power",
        {"power, uniform", "How a light path's light is chosen: by power or uniformly."});
    if (m_max_depth < 0) throw UsageError("lighttracer: maxdepth must be >= 0");
    if (m_light_sampler_name != "power" && m_light_sampler_name != "uniform")
        throw UsageError("lighttracer: lightsampler must be power or uniform");
}

LightTracerIntegrator::~LightTracerIntegrator() = default;

void LightTracerIntegrator::prepare(const RenderContext& ctx) {
    m_light_sampler = std::make_unique<LightSampler>(m_light_sampler_name, ctx.scene.lights());
    m_ctx = std::make_unique<BdptScene>(ctx.scene, ctx.camera, *m_light_sampler);
    m_media = ctx.scene.has_media();
}

void LightTracerIntegrator::render_sample(const RenderContext& ctx, Point2i, int, Sampler& sampler,
                                          ScratchBuffer& scratch, SplatList& splats) const {
    if (m_media) return render_sample_media(ctx, sampler, scratch, splats);
    // A light path of up to maxdepth + 1 vertices (maxdepth bounces before the lens).
    thread_local std::vector<PathVertex> path;
    path.resize(size_t(m_max_depth) + 1);
    // The path's time, uniform over the shutter as a camera ray's.
    float time = ctx.camera.sample_time(sampler.get_1d());
    int n = generate_light_subpath(*m_ctx, sampler, scratch, m_max_depth + 1, time, path.data());

    // Each vertex seen through a point on the lens: one get_2d() per connectible vertex.
    for (int i = 0; i < n; ++i) {
        const PathVertex& v = path[i];
        if (!v.is_connectible()) continue;
        Vec2 u = sampler.get_2d();
        bool area_origin = i == 0 && v.on_surface() && v.light &&
                           v.light->type() == LightType::Area &&
                           v.light->met_by_rays();  // (an invisible light is not seen)
        if (v.kind != VertexKind::Surface && !area_origin) continue;
        auto cs = ctx.camera.sample_wi(v.p(), u, time);
        if (!cs) continue;
        PathVertex lens = PathVertex::camera(cs->p_lens, cs->n_lens, RGB());
        lens.si.time = time;
        RGB f;
        if (i == 0) {
            // The light itself: radiance towards the lens over the density of its origin
            // (light choice times position), projected by the light's cosine.
            f = v.Le(*m_ctx, lens) * (abs_dot(cs->wi, v.ng()) / v.pdf_fwd);
        } else {
            f = v.beta * v.f(lens, TransportMode::Importance) * abs_dot(cs->wi, v.ns());
        }
        RGB L = f * (cs->We / cs->pdf_solid_angle);
        if (L.is_black() || !mutually_visible(ctx.scene, v, lens)) continue;
        splats.add(cs->p_raster, L);
    }
}

}  // namespace ml
