#include "manylight/gather.h"

#include <algorithm>
#include <cmath>

#include "lights/light.h"
#include "lights/light_sampler.h"
#include "materials/material.h"
#include "transport/direct_lighting.h"
#include "transport/phase_bxdf.h"
#include "transport/volume_path.h"

namespace ml {

const Medium* medium_towards(const GatherPoint& g, const Vec3& wi) {
    // A point in a medium has no mesh: medium_after keeps its medium.
    return medium_after(g.si, wi, g.medium);
}

RGB point_light_transmittance(const Scene& scene, const GatherPoint& g, const PointLight& pl) {
    const SurfaceInteraction& si = g.si;
    if (pl.kind != PointLightKind::Directional)
        return transmittance(scene, si.p, si.offset(), pl.p, pl.offset,
                             medium_towards(g, normalize(pl.p - si.p)), si.time, *g.sampler);
    // A point past the scene's bounds along the light's reverse direction.
    const Bounds3 b = scene.bounds();
    const Vec3 centre = (b.lo + b.hi) * 0.5f;
    const float radius = length(b.hi - b.lo) * 0.5f;
    const Vec3 wi = -pl.n;
    const Vec3 far = si.p + wi * (2 * std::max(radius, 1.f) + length(si.p - centre));
    return transmittance(scene, si.p, si.offset(), far, Vec3(), medium_towards(g, wi), si.time,
                         *g.sampler);
}

std::vector<EquiangularTarget> medium_gather_targets(const Scene& scene) {
    std::vector<EquiangularTarget> targets;
    if (!scene.has_media()) return targets;
    double total = 0;
    for (const auto& light : scene.lights()) {
        if (light->type() != LightType::DeltaPosition) continue;
        const std::optional<Vec3> p = light_position(*light);
        const float power = light->power().luminance();
        if (!p || !(power > 0)) continue;
        targets.push_back({*p, power});
        total += power;
        if (targets.size() > 64) return {};
    }
    for (EquiangularTarget& t : targets) t.pmf = float(t.pmf / total);
    return targets;
}

GatherPoint medium_gather_point(const Vec3& p, const Vec3& d, float time, const Medium* medium,
                                const RGB& beta, ScratchBuffer& scratch) {
    GatherPoint g;
    g.si.p = p;
    g.si.wo = -d;
    g.si.ng = g.si.ns = g.si.wo;
    g.si.time = time;
    g.bsdf = phase_bsdf(g.si.wo, medium->g(), scratch);
    g.beta = beta;
    g.medium = medium;
    g.in_medium = true;
    return g;
}

namespace detail {

namespace {

RGB exp_neg(const RGB& x, float t) {
    if (!std::isfinite(t)) return RGB();
    return RGB(std::exp(-x.r * t), std::exp(-x.g * t), std::exp(-x.b * t));
}

// `count` gather points on the unit ray's stretch [0, tmax) through homogeneous `m` (see
// next_gather_hit_media), appended to *points; *beta takes the stretch's transmittance. False
// where the medium's extinction is zero in some channel (delta tracking serves it instead).
bool stratified_medium_points(const Medium& m, const Medium* medium, const UnitRay& u, int count,
                              const std::vector<EquiangularTarget>* toward, float time,
                              Sampler& sampler, ScratchBuffer& scratch, RGB* beta,
                              std::vector<GatherPoint>* points) {
    const std::optional<MajorantSegment> seg = m.majorant(u.ray, u.tmax);
    if (!seg) return true;  // the ray misses the medium
    const MediumProperties mp = m.at(u.ray.at(seg->t0));
    const RGB sigma_t = mp.sigma_a + mp.sigma_s;
    // Distances drawn with density lambda exp(-lambda s) over the stretch, lambda the smallest
    // extinction, so that every channel's weight exp(-sigma_t s) / density stays bounded.
    const float lambda = std::min({sigma_t.r, sigma_t.g, sigma_t.b});
    if (!(lambda > 0)) return false;
    const float len = seg->t1 - seg->t0;
    const float mass = std::isfinite(len) ? -std::expm1(-lambda * len) : 1.f;
    // Equiangular sampling towards the targets, on stretches that start at the ray's origin.
    thread_local std::vector<Equiangular> eq;
    eq.clear();
    if (toward && !toward->empty() && seg->t0 == 0)
        for (const EquiangularTarget& t : *toward) eq.emplace_back(u.ray, len, t.p);
    // The density of the stretch's points at s: all strategies together (balance heuristic).
    auto density = [&](float s) {
        float d = float(count) * lambda * std::exp(-lambda * s) / mass;
        for (size_t j = 0; j < eq.size(); ++j)
            if (eq[j].valid) d += (*toward)[j].pmf * eq[j].pdf_length(s);
        return d;
    };
    auto add = [&](float s) {
        const float pdf = density(s);
        if (!(pdf > 0) || !(s < len) || mp.sigma_s.is_black()) return;
        const RGB w = exp_neg(sigma_t, s) * mp.sigma_s / pdf;
        points->push_back(
            medium_gather_point(u.ray.at(seg->t0 + s), u.ray.d, time, medium, *beta * w, scratch));
    };
    for (int k = 0; k < count; ++k) {
        const float uk = (float(k) + sampler.get_1d()) / float(count);
        add(std::min(-std::log1p(-uk * mass) / lambda, len));
    }
    if (!eq.empty()) {
        const float u_choose = sampler.get_1d(), u_distance = sampler.get_1d();
        float sum = 0;
        size_t j = 0;
        for (; j + 1 < eq.size(); ++j) {
            sum += (*toward)[j].pmf;
            if (u_choose < sum) break;
        }
        if (eq[j].valid) add(eq[j].sample(u_distance));
    }
    *beta *= exp_neg(sigma_t, len);
    return true;
}

}  // namespace

bool next_gather_hit_media(const Scene& scene, Ray ray, Sampler& sampler, ScratchBuffer& scratch,
                           const GatherOptions& options, const Medium** medium, RGB* beta, RGB* L,
                           GatherPoint* g, std::vector<GatherPoint>* points, bool media_emission) {
    // Interfaces crossed in a row; a scene of nested boundaries crosses a few.
    for (int crossing = 0; crossing < 256; ++crossing) {
        SurfaceInteraction si;
        const bool hit = scene.intersect(ray, &si);
        if (*medium) {
            const UnitRay u = unit_ray(ray, hit ? si.t : kInfinity);
            // (An emitting medium is tracked: its emission comes with the tracking.)
            const bool stratified =
                options.medium_points > 0 && (*medium)->homogeneous() && !(*medium)->emits() &&
                stratified_medium_points(**medium, *medium, u, options.medium_points,
                                         options.toward, ray.time, sampler, scratch, beta, points);
            if (!stratified) {
                const MediumCollision ev =
                    track_medium(**medium, u.ray, u.tmax, sampler, beta, L, media_emission);
                if (ev.event == MediumEvent::Absorb) return false;
                if (ev.event == MediumEvent::Scatter) {
                    if (beta->is_black() || !beta->is_finite()) return false;
                    points->push_back(medium_gather_point(u.ray.at(ev.t), u.ray.d, ray.time,
                                                          *medium, *beta, scratch));
                    return false;
                }
            }
            if (beta->is_black() || !beta->is_finite()) return false;
        }
        // Only the camera ray and delta chains get here: emission counts whole.
        *L += *beta * emission_along(scene, ray, hit ? &si : nullptr, true, 0.f, {}, nullptr);
        if (!hit) return false;
        if (is_interface(si)) {
            *medium = medium_after(si, ray.d, *medium);
            ray = Ray{si.offset_origin(ray.d), ray.d, kInfinity, ray.time};
            continue;
        }
        *g = GatherPoint();
        g->si = si;
        g->bsdf = hit_bsdf(g->si, scratch);
        g->medium = *medium;
        return bool(g->bsdf);
    }
    return false;
}

bool next_gather_hit(const Scene& scene, const Ray& ray, ScratchBuffer& scratch, const RGB& beta,
                     RGB* L, GatherPoint* g) {
    bool hit = scene.intersect(ray, &g->si);
    // Only the camera ray and delta chains get here, so emission counts whole: the point lights
    // stand for emitters seen through non-delta lobes only.
    *L += beta * emission_along(scene, ray, hit ? &g->si : nullptr, true, 0.f, {}, nullptr);
    if (!hit) return false;
    g->bsdf = hit_bsdf(g->si, scratch);
    return bool(g->bsdf);
}

RGB media_emission_after(const Scene& scene, const GatherPoint& g, int depth, int max_depth,
                         Sampler& sampler, ScratchBuffer& scratch) {
    static const MediaEmissionOnly only;
    static const LightSampler none("uniform", std::span<const Light* const>{});
    PathTraceOptions options;
    options.max_depth = max_depth;
    options.equiangular = false;
    return continue_volumetric(scene, VolumeVertex{g.si, g.medium, g.in_medium}, depth, g.beta,
                               sampler, scratch, none, options, &only);
}

bool continue_through_delta(const GatherPoint& g, Sampler& sampler, RGB* beta, Ray* ray) {
    float uc = sampler.get_1d();
    auto bs = g.bsdf.sample(g.si.wo, uc, sampler.get_2d());
    if (!bs || !bs->is_specular()) return false;
    *beta *= bs->f * (abs_dot(bs->wi, g.si.ns) / bs->pdf_solid_angle);
    if (beta->is_black() || !beta->is_finite()) return false;
    *ray = spawn_ray(g.si, bs->wi);
    return true;
}

}  // namespace detail

bool point_light_contribution(const PointLightSet& set, const PointLight& pl, const GatherPoint& g,
                              RGB* value, Ray* shadow, PointLightTerms* terms) {
    const SurfaceInteraction& si = g.si;
    Vec3 wi;
    RGB I;
    float inv_d2 = 1;
    if (pl.kind == PointLightKind::Directional) {
        wi = -pl.n;
        I = pl.intensity;
        *shadow = Ray{si.offset_origin(wi), wi, kInfinity, si.time};
    } else {
        Vec3 d = pl.p - si.p;
        float d2 = length_squared(d);
        if (!(d2 > 0)) return false;
        wi = d / std::sqrt(d2);
        I = point_light_intensity(set, pl, -wi);
        if (I.is_black()) return false;
        inv_d2 = 1 / d2;
        I = I / d2;
    }
    RGB f_bsdf = g.bsdf.eval(si.wo, wi);
    RGB f = f_bsdf * abs_dot(wi, si.ns);
    if (f.is_black()) return false;
    *value = g.beta * f * I;
    if (terms) *terms = {wi, inv_d2, f_bsdf};
    // The shadow ray last: the lights the BSDF turns away need none (a fifth of the pairs of an
    // igi frame of the kitchen).
    if (pl.kind != PointLightKind::Directional)
        *shadow = segment_ray(si.p, si.offset(), pl.p, pl.offset, si.time);
    return true;
}

}  // namespace ml
