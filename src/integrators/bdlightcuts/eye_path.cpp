#include "integrators/bdlightcuts/eye_path.h"

#include <algorithm>

#include "manylight/gather.h"
#include "transport/direct_lighting.h"

namespace ml {

RGB met_emission(const Scene& scene, const Ray& ray, const SurfaceInteraction* hit,
                 const EyeState& s, float t_prev, const SplitWeightOptions& o,
                 const LightSampler* nee) {
    RGB le = emission_along(scene, ray, hit, !s.prev_nee, s.prev_pdf, s.prev_ctx, nee);
    if (le.is_black()) return RGB();
    float pre = s.prefix, w_prev = 0;
    if (s.pending) {
        float dk = hit ? abs_dot(hit->ng, hit->wo) / kPi : 0.f;
        w_prev = split_weight(o, pre, s.pending_m * t_prev * dk, dk, s.pending_mu);
        pre += w_prev;
    }
    RGB L = s.beta * le * emission_weight(o, pre);
    if (s.prev_direct && w_prev > 0) {
        RGB le_mis =
            s.prev_nee ? le : emission_along(scene, ray, hit, false, s.prev_pdf, s.prev_ctx, nee);
        L += s.beta * le_mis * w_prev;
    }
    return L;
}

bool scatter(EyeState& s, const SurfaceInteraction& si, bool in_medium, const Bsdf& bsdf,
             const BsdfSample& bs, bool direct_mis, bool last_by_light, int bsdf_samples,
             float t_prev, const SplitWeightOptions& o, bool direct_sample, bool emission_mis) {
    const Vec3& n = bsdf.frame().n;
    s.prev_nee = !bs.is_specular() && (direct_sample ? last_by_light : emission_mis);
    s.prev_direct = direct_mis && !bs.is_specular();
    s.prev_pdf = bs.pdf_solid_angle * float(bsdf_samples);
    s.prev_ctx = vertex_context(si, in_medium);
    if (bs.is_specular()) {
        s.pending = false;  // neither a VSP nor a VPL here on this path: its splits weigh 0
    } else {
        float f = bsdf.eval(si.wo, bs.wi).max_component();
        if (s.pending) {
            float d = eye_lobe_density(f, si.wo, bs.wi, n, in_medium);
            s.prefix += split_weight(o, s.prefix, s.pending_m * t_prev * d, d, s.pending_mu);
        }
        s.pending = true;
        s.pending_m = f * abs_dot(bs.wi, si.ns);
        s.pending_mu = spread_mu(o, s.theta);
        s.pending_p = si.p;
        s.theta += lobe_spread(s.pending_m);
    }
    s.beta *= bs.f * (abs_dot(bs.wi, n) / bs.pdf_solid_angle);
    return !s.beta.is_black() && s.beta.is_finite();
}

EyeHit next_eye_hit(const Scene& scene, Ray* ray, Sampler& sampler, ScratchBuffer& scratch,
                    const Medium** medium, RGB* beta, SurfaceInteraction* si, Bsdf* phase,
                    const StretchFn& stretch, RGB* emitted) {
    for (int crossing = 0; crossing < 256; ++crossing) {
        const bool hit = scene.intersect(*ray, si);
        if (*medium) {
            const UnitRay u = unit_ray(*ray, hit ? si->t : kInfinity);
            if (stretch) stretch(**medium, u, *beta);
            RGB unused;
            const MediumCollision ev = track_medium(**medium, u.ray, u.tmax, sampler, beta,
                                                    emitted ? emitted : &unused, emitted);
            if (ev.event == MediumEvent::Absorb || beta->is_black() || !beta->is_finite())
                return EyeHit::Absorbed;
            if (ev.event == MediumEvent::Scatter) {
                GatherPoint g = medium_gather_point(u.ray.at(ev.t), u.ray.d, ray->time, *medium,
                                                    RGB(1.f), scratch);
                *si = g.si;
                *phase = g.bsdf;
                return EyeHit::Medium;
            }
        }
        if (!hit) return EyeHit::Escaped;
        if (!is_interface(*si)) return EyeHit::Surface;
        *medium = medium_after(*si, ray->d, *medium);
        *ray = Ray{si->offset_origin(ray->d), ray->d, kInfinity, ray->time};
    }
    return EyeHit::Absorbed;
}

}  // namespace ml
