#include "bidir/path_vertex.h"

#include "core/stats.h"
#include "transport/volume_path.h"

namespace ml {

float BdptScene::infinite_light_density(const Vec3& w) const {
    float pdf = 0;
    for (const Light* light : scene.infinite_lights())
        pdf +=
            light->pdf_li(LightSampleContext{}, -w, Vec3(), Vec3(), 0) * light_sampler.pmf(light);
    return pdf;
}

RGB PathVertex::Le(const BdptScene& ctx, const PathVertex& v) const {
    if (!is_light()) return RGB();
    Vec3 w = v.p() - p();
    if (length_squared(w) == 0) return RGB();
    w = normalize(w);
    if (is_infinite_light()) {
        // Radiance arriving at v from direction -w, from every infinite light.
        RGB L;
        for (const Light* light : ctx.scene.infinite_lights())
            L += light->radiance_escaped(Ray{p(), -w});
        return L;
    }
    const Light* e = emitter();
    return e ? e->radiance(p(), ng(), si.uv, w) : RGB();
}

float PathVertex::pdf_area(const BdptScene& ctx, const PathVertex* prev,
                           const PathVertex& next) const {
    if (kind == VertexKind::Light) return pdf_light(ctx, next);
    Vec3 wn = next.p() - p();
    if (length_squared(wn) == 0) return 0;
    wn = normalize(wn);
    float pdf = 0;
    if (kind == VertexKind::Camera) {
        float pdf_pos;
        ctx.camera.pdf_we(Ray{p(), wn, kInfinity, si.time}, &pdf_pos, &pdf);
    } else {
        if (!prev) return 0;
        Vec3 wp = prev->p() - p();
        if (length_squared(wp) == 0) return 0;
        if (kind == VertexKind::Medium) {
            // The phase function is its own density.
            pdf = hg_phase(normalize(wp), wn, medium->g());
        } else {
            if (!bsdf) return 0;
            pdf = bsdf.pdf_solid_angle(normalize(wp), wn);
        }
    }
    return convert_density(pdf, next);
}

float PathVertex::pdf_light(const BdptScene& ctx, const PathVertex& v) const {
    Vec3 w = v.p() - p();
    float d2 = length_squared(w);
    if (d2 == 0) return 0;
    w = w / std::sqrt(d2);
    float pdf = 0;
    if (is_infinite_light()) {
        // Light paths from infinite lights start uniformly on a disk of the bounding sphere:
        // a planar density, with no 1 / d^2.
        if (ctx.scene_radius <= 0) return 0;
        pdf = 1 / (kPi * sqr(ctx.scene_radius));
    } else {
        const Light* e = emitter();
        if (!e) return 0;
        float pdf_pos, pdf_dir;
        e->pdf_le(Ray{p(), w}, ng(), &pdf_pos, &pdf_dir);
        pdf = pdf_dir / d2;
    }
    if (v.on_surface()) pdf *= abs_dot(v.ng(), w);
    return pdf;
}

float PathVertex::pdf_light_origin(const BdptScene& ctx, const PathVertex& v) const {
    Vec3 w = v.p() - p();
    if (length_squared(w) == 0) return 0;
    w = normalize(w);
    if (is_infinite_light()) return ctx.infinite_light_density(w);
    const Light* e = emitter();
    if (!e) return 0;
    float pdf_pos, pdf_dir;
    e->pdf_le(Ray{p(), w}, ng(), &pdf_pos, &pdf_dir);
    return pdf_pos * ctx.light_sampler.pmf(e);
}

const Medium* PathVertex::medium_towards(const BdptScene& ctx, const Vec3& w) const {
    switch (kind) {
        case VertexKind::Camera:
            return ctx.scene.camera_medium();
        case VertexKind::Light:
            return light ? light->medium_towards(w, ng()) : nullptr;
        case VertexKind::Surface:
            return medium_after(si, w, medium);
        case VertexKind::Medium:
            return medium;
    }
    return nullptr;
}

RGB transmittance_between(const BdptScene& ctx, const PathVertex& a, const PathVertex& b,
                          Sampler& sampler) {
    if (!ctx.scene.has_media()) return RGB(mutually_visible(ctx.scene, a, b) ? 1.f : 0.f);
    const Vec3 d = b.p() - a.p();
    if (length_squared(d) == 0) return RGB();
    return transmittance(ctx.scene, a.p(), a.offset(), b.p(), b.offset(),
                         a.medium_towards(ctx, normalize(d)), a.si.time, sampler);
}

bool mutually_visible(const Scene& scene, const PathVertex& a, const PathVertex& b) {
    // Points on surfaces (lights' included) are moved off them towards each other; the lens
    // and point lights stay put (PathVertex::offset).
    return !scene.occluded(segment_ray(a.p(), a.offset(), b.p(), b.offset(), a.si.time));
}

}  // namespace ml
