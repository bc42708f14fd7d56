#include "transport/volume_path.h"

#include <cmath>

#include "materials/material.h"
#include "transport/direct_lighting.h"
#include "transport/mis.h"
#include "transport/phase_bxdf.h"
#include "transport/spawn.h"

namespace ml {

namespace {

float channel_mean(const RGB& c) { return (c.r + c.g + c.b) / 3; }

RGB exp_neg(const RGB& x) {
    auto e = [](float v) { return v > 0 ? std::exp(-v) : 1.f; };
    return RGB(e(x.r), e(x.g), e(x.b));
}

// Collisions along the unit `ray` up to tmax with density sigma_maj exp(-int sigma_maj),
// segment by segment of m's majorants: an optical depth drawn once per collision (when first
// needed) is spent across the segments it passes. at(t, sigma_maj) is called at each collision
// and returns false to stop there; returns whether it stopped.
template <class AtCollision>
bool for_each_collision(const Medium& m, const Ray& ray, float tmax, Sampler& sampler,
                        const AtCollision& at) {
    MajorantIterator segments = m.majorants(ray, tmax);
    float tau = -1;  // -1: none drawn yet
    while (const std::optional<MajorantSegment> seg = segments.next()) {
        const float sigma_maj = seg->sigma_maj;
        if (!(sigma_maj > 0)) continue;  // nothing there
        float t = seg->t0;
        for (;;) {
            if (tau < 0) tau = -std::log1p(-sampler.get_1d());
            if (!(tau < sigma_maj * (seg->t1 - t))) {
                tau -= sigma_maj * (seg->t1 - t);
                break;
            }
            t += tau / sigma_maj;
            tau = -1;  // spent: the next collision draws its own
            if (!at(t, sigma_maj)) return true;
        }
    }
    return false;
}

}  // namespace

RGB medium_transmittance(const Medium& m, const Ray& ray, float tmax, Sampler& sampler) {
    if (m.homogeneous()) {
        const std::optional<MajorantSegment> seg = m.majorant(ray, tmax);
        if (!seg || !(seg->sigma_maj > 0)) return RGB(1.f);
        const MediumProperties mp = m.at(ray.o);
        return exp_neg((mp.sigma_a + mp.sigma_s) * (seg->t1 - seg->t0));
    }
    RGB tr(1.f);
    const bool stopped = for_each_collision(m, ray, tmax, sampler, [&](float t, float sigma_maj) {
        const MediumProperties mp = m.at(ray.at(t));
        tr *= clamp_zero(RGB(1.f) - (mp.sigma_a + mp.sigma_s) / sigma_maj);
        const float mx = tr.max_component();
        if (!(mx > 0)) return false;
        if (mx < 0.1f) {
            if (sampler.get_1d() < 0.5f) return false;
            tr *= 2.f;
        }
        return true;
    });
    if (stopped) return RGB();
    return tr;
}

std::optional<float> first_majorant_collision(const Medium& m, const Ray& ray, float tmax,
                                              Sampler& sampler) {
    std::optional<float> hit;
    for_each_collision(m, ray, tmax, sampler, [&](float t, float) {
        hit = t;
        return false;
    });
    return hit;
}

float majorant_transmittance(const Medium& m, const Ray& ray, float tmax) {
    MajorantIterator segments = m.majorants(ray, tmax);
    double tau = 0;
    while (const std::optional<MajorantSegment> seg = segments.next())
        if (seg->sigma_maj > 0) tau += double(seg->sigma_maj) * double(seg->t1 - seg->t0);
    return float(std::exp(-tau));
}

float majorant_at(const Medium& m, const Ray& ray, float t, float tmax) {
    MajorantIterator segments = m.majorants(ray, tmax);
    float last = 0;
    while (const std::optional<MajorantSegment> seg = segments.next()) {
        if (seg->t0 <= t && t <= seg->t1) return seg->sigma_maj;
        last = seg->sigma_maj;
    }
    return t >= tmax ? last : 0.f;
}

namespace {

// One light sample towards a scattering point `ctx.p` (moved by `offset` off its surface; zero
// in a medium), weighed by MIS against the point's own direction sampling: f_pdf(wi) gives the
// scattering function (times the cosine at a surface) and that sampling's density of wi, and
// medium_for(wi) the medium a ray towards wi starts in. Divided by the light's pmf.
// `light_weight(light, pmf)` multiplies the sample of that light (chosen with probability pmf):
// the MIS weight against equiangular sampling.
template <class FPdf, class MediumFor, class LightWeight>
RGB sample_direct(const Scene& scene, const LightSampleContext& ctx, const Vec3& offset, float time,
                  const LightSampler& light_sampler, Sampler& sampler, const FPdf& f_pdf,
                  const MediumFor& medium_for, const LightWeight& light_weight) {
    const float u_select = sampler.get_1d();
    const Vec2 u_light = sampler.get_2d();
    const auto sl = light_sampler.sample(ctx, u_select);
    if (!sl) return RGB();
    LightSampleContext incomplete = ctx;
    incomplete.allow_incomplete_pdf = true;
    const auto ls = sl->light->sample_li(incomplete, u_light);
    if (!ls || ls->L.is_black() || !(ls->pdf_solid_angle > 0)) return RGB();
    const auto [f, pdf_dir] = f_pdf(ls->wi);
    if (f.is_black()) return RGB();
    const RGB tr = transmittance(scene, ctx.p, offset, ls->p_light, ls->offset(),
                                 medium_for(ls->wi), time, sampler);
    if (tr.is_black()) return RGB();
    const float light_pdf = sl->pmf * ls->pdf_solid_angle;
    float w = !sl->light->met_by_rays() ? 1.f : power_heuristic(light_pdf, pdf_dir);
    w *= light_weight(*sl->light, sl->pmf);
    return f * ls->L * tr * (w / light_pdf);
}

float mis_square(float a, float b) { return a * a / (a * a + b * b); }

}  // namespace

namespace {

// A point light chosen by power, a distance along the unit ray drawn equiangularly towards it,
// and that point's light scattered back along the ray: transmittance from the ray's origin,
// sigma_s, the phase function, the light and the shadow ray's transmittance, weighed by MIS
// against delta tracking (GreyTracking) finding the point and choosing the light there.
RGB equiangular_single_scattering(const Scene& scene, const Medium& medium, const Ray& ray,
                                  float tmax, const GreyTracking& grey,
                                  const LightSampler& light_sampler, Sampler& sampler) {
    const float u_select = sampler.get_1d(), u_t = sampler.get_1d();
    const Vec2 u_light = sampler.get_2d();
    const auto sl = light_sampler.sample(u_select);
    if (!sl || sl->light->type() != LightType::DeltaPosition) return RGB();
    const auto c = light_position(*sl->light);
    if (!c) return RGB();
    const Equiangular eq(ray, tmax, *c);
    if (!eq.valid) return RGB();
    const float t = eq.sample(u_t);
    if (!(t >= 0 && t < tmax)) return RGB();
    const Vec3 p = ray.at(t);
    const LightSampleContext ctx{p, Vec3(), Vec3()};
    const auto ls = sl->light->sample_li(ctx, u_light);
    if (!ls || ls->L.is_black()) return RGB();
    const MediumProperties mp = medium.at(p);
    const float phase = hg_phase(-ray.d, ls->wi, medium.g());
    const RGB tr =
        transmittance(scene, p, Vec3(), ls->p_light, ls->offset(), &medium, ray.time, sampler);
    if (tr.is_black()) return RGB();
    const float p_equi = sl->pmf * eq.pdf_length(t);
    const float p_track = light_sampler.pmf(ctx, sl->light) * grey.pdf_length(t);
    const float w = mis_square(p_equi, p_track);
    return mp.sigma_s * ls->L * tr * (phase * std::exp(-grey.sigma_t * t) * w / p_equi);
}

}  // namespace

// The position of a light at a point (point, spot, goniometric and projection lights): where
// its emitted rays start, the same for every sample.
std::optional<Vec3> light_position(const Light& light) {
    const auto le = light.sample_le(Vec2(0.5f, 0.5f), Vec2(0.5f, 0.5f));
    if (le) return le->ray.o;
    if (const auto b = light.bounds()) return (b->box.lo + b->box.hi) * 0.5f;
    return std::nullopt;
}

UnitRay unit_ray(const Ray& r, float tmax) {
    const float len = length(r.d);
    return {Ray{r.o, r.d / len, kInfinity, r.time}, tmax * len};
}

MediumCollision track_medium(const Medium& m, const Ray& ray, float tmax, Sampler& sampler,
                             RGB* beta, RGB* L, bool emission) {
    // Absorbed, scattered or null by their shares at each collision (for_each_collision).
    MediumCollision out;
    for_each_collision(m, ray, tmax, sampler, [&](float t, float sigma_maj) {
        const MediumProperties mp = m.at(ray.at(t));
        if (emission && m.emits()) *L += *beta * mp.sigma_a * mp.Le / sigma_maj;
        const RGB sigma_n = clamp_zero(RGB(sigma_maj) - mp.sigma_a - mp.sigma_s);
        const float pa = channel_mean(*beta * mp.sigma_a), ps = channel_mean(*beta * mp.sigma_s),
                    pn = channel_mean(*beta * sigma_n);
        const float c = pa + ps + pn;
        const float u = c > 0 ? sampler.get_1d() * c : 0.f;
        if (!(c > 0) || u < pa) {
            out = {MediumEvent::Absorb, t};
            return false;
        }
        if (u < pa + ps) {
            *beta *= mp.sigma_s * (c / (ps * sigma_maj));
            out = {MediumEvent::Scatter, t};
            return false;
        }
        *beta *= sigma_n * (c / (pn * sigma_maj));
        if (!beta->is_black()) return true;
        out = {MediumEvent::Absorb, t};
        return false;
    });
    return out;
}

const Medium* medium_after(const SurfaceInteraction& si, const Vec3& w, const Medium* current) {
    if (!si.mesh || !si.mesh->medium_interface) return current;
    return dot(w, si.ng) > 0 ? si.mesh->medium_outside : si.mesh->medium_inside;
}

bool is_interface(const SurfaceInteraction& si) {
    return si.material && si.material->type() == "interface";
}

RGB transmittance(const Scene& scene, const Vec3& from, const Vec3& from_offset, const Vec3& to,
                  const Vec3& to_offset, const Medium* medium, float time, Sampler& sampler) {
    RGB tr(1.f);
    const bool reached = walk_segment(scene, from, from_offset, to, to_offset, medium, time,
                                      [&](const Medium& m, const UnitRay& u, bool, bool) {
                                          tr *= medium_transmittance(m, u.ray, u.tmax, sampler);
                                          return !tr.is_black();
                                      });
    return reached ? tr : RGB();
}

RGB transmittance_to_surface(const Scene& scene, Ray ray, const Medium* medium, Sampler& sampler,
                             SurfaceInteraction* hit, bool* found) {
    RGB tr(1.f);
    for (int crossing = 0; crossing < 256; ++crossing) {
        *found = scene.intersect(ray, hit);
        if (medium) {
            const UnitRay u = unit_ray(ray, *found ? hit->t : kInfinity);
            tr *= medium_transmittance(*medium, u.ray, u.tmax, sampler);
            if (tr.is_black()) return RGB();
        }
        if (!*found || !is_interface(*hit)) return tr;
        medium = medium_after(*hit, ray.d, medium);
        ray = Ray{hit->offset_origin(ray.d), ray.d, kInfinity, ray.time};
    }
    *found = false;
    return RGB();
}

namespace {

// The path tracer's state between vertices in a scene with media: trace_volumetric walks it
// from the camera, continue_volumetric from a vertex another estimator reached.
class VolumeWalk {
public:
    VolumeWalk(const Scene& scene, Sampler& sampler, ScratchBuffer& scratch,
               const LightSampler& light_sampler, const PathTraceOptions& options)
        : m_scene(scene),
          m_sampler(sampler),
          m_scratch(scratch),
          m_lights(light_sampler),
          m_options(options) {}

    RGB L;
    RGB beta{1.f};
    const Medium* medium = nullptr;
    Ray ray;
    int depth = 0;                  // scattering vertices so far, surface and medium alike
    bool specular_bounce = true;    // the camera ray, or a delta lobe: emission counts whole
    float prev_pdf = 0;             // the density of the last scattering direction
    LightSampleContext prev_ctx{};  // the point it left from
    float eta_scale = 1;
    // The first vertex's weight by the direction it leaves in (FirstBounceWeight), kept out of
    // beta as continue_path keeps it: Russian roulette looks at the throughput alone.
    float path_weight = 1;
    // Whether the media's emission counts whole whatever path_weight is (and the path goes on
    // for it where path_weight is 0): FirstBounceWeight::weighs_media_emission.
    bool whole_emission = false;

    // The vertices from `ray` on, until the path ends.
    void run() {
        for (int crossings = 0; crossings < 4096; ++crossings)
            if (!step()) return;
    }

    // Scattering at p in `medium`, reached along -wo: a light sample and the phase function's
    // direction (weighted by `first` where given). `grey` and the unit segment u are the
    // equiangular strategy's, for MIS (grey invalid: none). False when the path ends.
    bool scatter_in_medium(const Vec3& p, const Vec3& wo, float time, const GreyTracking& grey,
                           const UnitRay* u, float t_event, const FirstBounceWeight* first) {
        const float g = medium->g();
        const LightSampleContext ctx{p, Vec3(), Vec3()};
        const Medium* here = medium;
        const Bsdf phase = first ? phase_bsdf(wo, g, m_scratch) : Bsdf();
        const bool weighted_out = first && first->vanishes(phase, wo);
        if (weighted_out && !whole_emission) return false;
        auto weight_of = [&](const Vec3& wi, const RGB* f) {
            return first ? first->weight(phase, wo, wi, false, f) : 1.f;
        };
        // (A path that goes on only for the media's emission takes no light samples.)
        if (!weighted_out && path_weight != 0.f)
            add(beta * sample_direct(
                           m_scene, ctx, Vec3(), time, m_lights, m_sampler,
                           [&](const Vec3& wi) {
                               const float ph = hg_phase(wo, wi, g);
                               float w = 1.f;
                               if (first) {
                                   const RGB f = phase.eval(wo, wi);
                                   w = weight_of(wi, &f);
                               }
                               return std::pair<RGB, float>(RGB(ph * w), ph);
                           },
                           [&](const Vec3&) { return here; },
                           [&](const Light& light, float pmf) {
                               // Against the segment's equiangular sample of this light.
                               if (!grey.valid || !u || light.type() != LightType::DeltaPosition)
                                   return 1.f;
                               const auto c = light_position(light);
                               if (!c) return 1.f;
                               const Equiangular eq(u->ray, u->tmax, *c);
                               if (!eq.valid) return 1.f;
                               return mis_square(pmf * grey.pdf_length(t_event),
                                                 m_lights.pmf(&light) * eq.pdf_length(t_event));
                           }));
        const Vec3 wi = sample_hg_phase(wo, g, m_sampler.get_2d());
        if (first) path_weight = weight_of(wi, nullptr);
        // The phase function is its own density: the throughput keeps its value.
        prev_pdf = hg_phase(wo, wi, g);
        prev_ctx = ctx;
        specular_bounce = false;
        ray = Ray{p, wi, kInfinity, time};
        return (path_weight != 0.f || whole_emission) && survive();
    }

    // Scattering at surface si (not an interface), the path having arrived in `medium`.
    bool scatter_at_surface(SurfaceInteraction& si, const FirstBounceWeight* first) {
        Bsdf bsdf = hit_bsdf(si, m_scratch);
        if (!bsdf) return false;
        const bool weighted_out = first && first->vanishes(bsdf, si.wo);
        if (weighted_out && !whole_emission) return false;
        // Next-event estimation through the media, then the BSDF's direction.
        if (bsdf.has_nonspecular() && !weighted_out && path_weight != 0.f) {
            const Medium* arrived = medium;
            add(beta * sample_direct(
                           m_scene, light_context(si), si.offset(), si.time, m_lights, m_sampler,
                           [&](const Vec3& wi) {
                               const RGB f = bsdf.eval(si.wo, wi);
                               const float w =
                                   first ? first->weight(bsdf, si.wo, wi, false, &f) : 1.f;
                               return std::pair<RGB, float>(f * (abs_dot(wi, si.ns) * w),
                                                            bsdf.pdf_solid_angle(si.wo, wi));
                           },
                           [&](const Vec3& wi) { return medium_after(si, wi, arrived); },
                           [](const Light&, float) { return 1.f; }));
        }
        const float uc = m_sampler.get_1d();
        const Vec2 u = m_sampler.get_2d();
        const auto bs = bsdf.sample(si.wo, uc, u);
        if (!bs) return false;
        if (first && bs->is_specular() && !first->takes_delta_lobes()) return false;
        beta *= bs->f * (abs_dot(bs->wi, si.ns) / bs->pdf_solid_angle);
        if (first) path_weight = first->weight(bsdf, si.wo, bs->wi, bs->is_specular(), nullptr);
        specular_bounce = bs->is_specular();
        prev_pdf = bs->pdf_solid_angle;
        prev_ctx = light_context(si);
        if (bs->is_transmission()) eta_scale *= sqr(bs->eta);
        medium = medium_after(si, bs->wi, medium);
        ray = spawn_ray(si, bs->wi);
        return (path_weight != 0.f || whole_emission) && survive();
    }

private:
    void add(const RGB& c) { L += c * path_weight; }

    // Russian roulette after a vertex's scattering sample; false: the path ends.
    bool survive() {
        const float rr = (beta * eta_scale).max_component();
        const float u = m_sampler.get_1d();
        if (rr < 1.f && depth >= m_options.rr_depth) {
            const float q = std::max(0.f, 1.f - rr);
            if (u < q) return false;
            beta = beta / (1.f - q);
        }
        return !beta.is_black() && beta.is_finite();
    }

    // The medium along `ray` and what ends it; false when the path ends.
    bool step() {
        SurfaceInteraction si;
        const bool hit = m_scene.intersect(ray, &si);

        // 1. The medium between the ray's origin and the surface (or infinity).
        if (medium) {
            const UnitRay u = unit_ray(ray, hit ? si.t : kInfinity);
            // 1a. Single scattering towards one point light, at a distance drawn equiangularly,
            // weighed by MIS against the tracking below finding the same point.
            const GreyTracking grey =
                m_options.equiangular ? GreyTracking(*medium, beta) : GreyTracking();
            if (grey.valid && depth < m_options.max_depth && path_weight != 0.f)
                add(beta * equiangular_single_scattering(m_scene, *medium, u.ray, u.tmax, grey,
                                                         m_lights, m_sampler));
            RGB emitted;
            const MediumCollision ev = track_medium(*medium, u.ray, u.tmax, m_sampler, &beta,
                                                    &emitted, depth < m_options.max_depth);
            L += emitted * (whole_emission ? 1.f : path_weight);
            if (ev.event == MediumEvent::Absorb) return false;
            if (ev.event == MediumEvent::Scatter) {
                if (depth++ >= m_options.max_depth) return false;
                return scatter_in_medium(u.ray.at(ev.t), -u.ray.d, ray.time, grey, &u, ev.t,
                                         nullptr);
            }
        }

        // 2. The surface (or the sky): its emission, weighed against the last light sample.
        add(beta * emission_along(m_scene, ray, hit ? &si : nullptr, specular_bounce, prev_pdf,
                                  prev_ctx, &m_lights));
        if (!hit) return false;
        if (is_interface(si)) {
            // A medium boundary only: the ray goes on, in the medium beyond.
            medium = medium_after(si, ray.d, medium);
            ray = Ray{si.offset_origin(ray.d), ray.d, kInfinity, ray.time};
            return true;
        }
        if (depth >= m_options.max_depth) return false;
        ++depth;
        return scatter_at_surface(si, nullptr);
    }

    const Scene& m_scene;
    Sampler& m_sampler;
    ScratchBuffer& m_scratch;
    const LightSampler& m_lights;
    const PathTraceOptions& m_options;
};

}  // namespace

RGB trace_volumetric(const Scene& scene, const Ray& camera_ray, Sampler& sampler,
                     ScratchBuffer& scratch, const LightSampler& light_sampler,
                     const PathTraceOptions& options) {
    VolumeWalk walk(scene, sampler, scratch, light_sampler, options);
    walk.medium = scene.camera_medium();
    walk.ray = camera_ray;
    walk.run();
    return walk.L;
}

RGB continue_volumetric(const Scene& scene, const VolumeVertex& v, int depth, RGB beta,
                        Sampler& sampler, ScratchBuffer& scratch, const LightSampler& light_sampler,
                        const PathTraceOptions& options, const FirstBounceWeight* first) {
    if (depth >= options.max_depth) return RGB();
    VolumeWalk walk(scene, sampler, scratch, light_sampler, options);
    walk.medium = v.medium;
    walk.beta = beta;
    walk.depth = depth + 1;  // v itself
    walk.whole_emission = first && !first->weighs_media_emission() && scene.has_emitting_media();
    SurfaceInteraction si = v.si;
    const bool goes_on = v.in_medium ? walk.scatter_in_medium(si.p, si.wo, si.time, GreyTracking(),
                                                              nullptr, 0, first)
                                     : walk.scatter_at_surface(si, first);
    if (goes_on) walk.run();
    return walk.L;
}

}  // namespace ml
