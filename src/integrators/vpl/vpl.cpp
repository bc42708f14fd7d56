#include "integrators/vpl/vpl.h"

#include "manylight/gather.h"

namespace ml {

VplIntegrator::VplIntegrator(const Settings& settings)
    : m_settings(ManyLightSettings::read(settings)) {}

void VplIntegrator::prepare(const Scene& scene) {
    build_many_lights(scene, m_settings, &m_set, &m_direct);
}

RenderResult VplIntegrator::render(const RenderContext& ctx) {
    m_settings.use_render_seed(ctx.seed);
    m_settings.lights.camera = &ctx.camera;
    RenderResult r = PixelIntegrator::render(ctx);
    r.point_lights = m_set.lights.size();
    r.vpls = m_set.vpls;
    return r;
}

RGB VplIntegrator::li(const Ray& ray, const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
                      Point2i pixel) const {
    return gather_along(scene, ray, sampler, scratch, m_settings.max_depth,
                        [&](const GatherPoint& g, float) {
                            RGB L = m_direct.estimate(scene, g, sampler);
                            for (const PointLight& pl : m_set.lights)
                                L += visible_point_light(scene, m_set, m_settings, pl, g);
                            return L;
                        });
}

}  // namespace ml
