#include "integrators/vpl/vpl.h"

#include "manylight/gather.h"

namespace ml {

VplIntegrator::VplIntegrator(const Settings& settings)
    : m_settings(ManyLightSettings::read(settings, {.tree_reps = 0, .focus = 0.5f})) {
    read_vpl_sets(settings, &m_settings);
}

void VplIntegrator::prepare(const Scene& scene) {
    build_many_lights(scene, m_settings, &m_set, &m_direct);
    m_lit = std::make_unique<std::atomic<uint8_t>[]>(m_set.lights.size());
    for (size_t i = 0; i < m_set.lights.size(); ++i) m_lit[i].store(0, std::memory_order_relaxed);
}

RenderResult VplIntegrator::render(const RenderContext& ctx) {
    m_settings.use_render_seed(ctx.seed);
    m_settings.use_scene(ctx.scene);
    m_settings.lights.camera = &ctx.camera;
    m_settings.use_time_limit(ctx, false);
    m_lit.reset();
    RenderResult r = PixelIntegrator::render(ctx);
    r.point_lights = m_set.lights.size();
    r.vpls = m_set.vpls;
    if (std::string w = vpl_budget_warning(m_set); !w.empty()) r.warnings.push_back(w);
    size_t vpl_lights = 0, lighting = 0;
    for (size_t i = 0; i < m_set.lights.size(); ++i)
        if (m_set.lights[i].is_vpl) {
            ++vpl_lights;
            if (m_lit && m_lit[i].load(std::memory_order_relaxed)) ++lighting;
        }
    r.stats["vpl"] = {{"vpl_lights", vpl_lights}, {"lighting", lighting}};
    r.stats["vpl"].update(vpl_focus_json(m_set));
    r.stats["vpl"].update(vpl_budget_json(m_set));
    return r;
}

RGB VplIntegrator::li(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
                      Point2i pixel) const {
    return gather_along(
        scene, ray, sampler, scratch, m_settings.gather(), [&](const GatherPoint& g, float) {
            RGB L = m_direct.estimate(scene, g, sampler);
            for (size_t i = 0; i < m_set.lights.size(); ++i) {
                RGB c = visible_point_light(scene, m_set, m_settings, m_set.lights[i], g);
                if (c.is_black()) continue;
                L += c;
                // (A load first: most lights are marked early, and a load
                // shares the cache line where a store would not.)
                std::atomic<uint8_t>& lit = m_lit[i];
                if (!lit.load(std::memory_order_relaxed)) lit.store(1, std::memory_order_relaxed);
            }
            return L;
        });
}

}  // namespace ml
