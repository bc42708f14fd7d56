#include "manylight/vpl_generator.h"

#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "lights/light_sampler.h"
#include "manylight/point_light_set.h"
#include "materials/material.h"
#include "sampling/distributions.h"
#include "sampling/sampler.h"
#include "sampling/warps.h"
#include "scene/scene.h"
#include "transport/direct_lighting.h"
#include "transport/phase_bxdf.h"
#include "transport/volume_path.h"

namespace ml {
namespace {

// Paths per task: large enough to amortise a sampler and an arena, small enough to balance.
constexpr size_t kChunkPaths = 1024;

RGB max_rgb(const RGB& a, const RGB& b) {
    RGB r;
    for (int c = 0; c < 3; ++c) r[c] = std::max(a[c], b[c]);
    return r;
}

// A glossy reflector's VPL, bounded by the Bxdf's own bounds: what it sends towards w is
// flux f(w, wi) |cos(n, w)| = flux f(wi, w) |cos(n, w)| (reciprocity), which
// max_value_bound(wi, C) bounds over any cone C of w. Over every direction that gives the
// intensity; over the directions at least a bin's angle from the mirror direction (a cone
// about its reverse), the falloff. False where the Bxdf has no finite bound.
bool make_glossy(const Bsdf& bsdf, const Vec3& wi, const RGB& beta, PointLight* pl) {
    RGB peak = bsdf.max_value_bound(wi, DirectionCone::entire_sphere());
    if (!peak.is_finite() || peak.is_black()) return false;
    const Vec3& n = pl->n;  // on wi's side
    Vec3 axis = normalize(n * (2 * dot(wi, n)) - wi);
    pl->kind = PointLightKind::Glossy;
    pl->n = axis;
    pl->intensity = beta * peak;
    pl->falloff[0] = 0;
    for (int k = 1; k < kFalloffBins; ++k) {
        RGB b = bsdf.max_value_bound(wi, DirectionCone(-axis, -kFalloffCos[k]));
        float t = 0;
        for (int c = 0; c < 3; ++c)
            if (peak[c] > 0) t = std::max(t, b[c] / peak[c]);
        pl->falloff[k] = quantize_falloff(t);
    }
    return !pl->intensity.is_black();
}

// A VPL at si for flux `beta` arriving from si.wo.
void deposit_impl(const SurfaceInteraction& si, const Bsdf& bsdf, const RGB& beta,
                  GlossyVpls glossy, VplChunk& chunk) {
    PointLight pl;
    pl.p = si.p;
    pl.offset = si.offset();
    pl.is_vpl = true;
    Vec3 wi = si.wo;
    // The side the light arrived on.
    pl.n = bsdf.frame().n;
    if (dot(pl.n, wi) < 0) pl.n = -pl.n;
    uint8_t flags = bsdf.flags();
    bool transmits = flags & kBxdfTransmission;
    if (flags == kBxdfDiffuseReflection) {
        // Lambertian: f is constant, I(w) = flux f cos(n, w), a cosine lobe. (A diffuse base
        // under a smooth coat is not: Fresnel and the coat's absorption depend on w.)
        pl.kind = PointLightKind::Oriented;
        RGB f = bsdf.eval(pl.n, wi, TransportMode::Radiance);
        pl.intensity = beta * f;
        pl.diffuse_f = f.max_component();
        if (pl.intensity.is_black()) return;
        chunk.lights.push_back(pl);
        return;
    }
    // Glossy or transmitting: keep the BSDF for exact evaluation; the Bxdf is rebuilt in the
    // chunk's arena, which the set keeps (the tracing scratch is reset after every path).
    if (!chunk.arena) chunk.arena = std::make_unique<ScratchBuffer>(256 * 1024);
    Bsdf kept = si.material->get_bsdf(si, *chunk.arena);
    // Oriented lights are bounded by intensity * cos, so they need a bound of f alone;
    // omni lights (both sides) a bound of f |cos|.
    bool diffuse_only = glossy == GlossyVpls::Diffuse && (flags & kBxdfGlossy);
    if ((flags & kBxdfGlossy) && !transmits && !diffuse_only && make_glossy(kept, wi, beta, &pl)) {
        pl.surface = int32_t(chunk.surfaces.size());
        chunk.surfaces.push_back(VplSurface{kept, wi, beta, false});
        chunk.lights.push_back(pl);
        return;
    }
    pl.kind = transmits ? PointLightKind::Omni : PointLightKind::Oriented;
    std::optional<RGB> exact_max;
    if (diffuse_only && !transmits)
        exact_max = kept.bxdf()->max_diffuse_value(kept.frame().to_local(wi));
    pl.intensity = beta * (exact_max ? *exact_max
                                     : estimate_max_bsdf_value(kept, wi, transmits, diffuse_only));
    if (pl.intensity.is_black()) return;  // nothing diffuse to keep
    pl.surface = int32_t(chunk.surfaces.size());
    chunk.surfaces.push_back(VplSurface{kept, wi, beta, diffuse_only});
    chunk.lights.push_back(pl);
}

// Spherical Fibonacci point i of n (unit vector).
Vec3 fibonacci_direction(int i, int n) {
    constexpr float kGolden = 0.6180339887f;
    float z = 1 - (2 * float(i) + 1) / float(n);
    float phi = 2 * kPi * (float(i) * kGolden - std::floor(float(i) * kGolden));
    float r = safe_sqrt(1 - z * z);
    return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace

void VplTracer::focus_emission(const Vec3& center, float radius, bool on_focus, const Vec2& u_pos,
                               LightLeSample* le) const {
    // The disk lies in the plane through center - d radius, normal to the paths' direction d; the
    // focus sphere's shadow on it is the disk of its radius about its centre's projection.
    const Vec3 d = le->ray.d;
    const Vec3 disk = center - d * radius;
    const Vec3 focus = m_options.focus_center - d * dot(m_options.focus_center - disk, d);
    const float r = m_options.focus_radius, share = m_options.focus_share;
    if (on_focus) {
        const Frame f = Frame::from_z(d);
        const Vec2 q = sample_uniform_disk_concentric(u_pos) * r;
        le->ray.o = focus + f.s * q.x + f.t * q.y;
    }
    const bool in_focus = on_focus || length_squared(le->ray.o - focus) <= r * r;
    const bool in_disk = !on_focus || length_squared(le->ray.o - disk) <= radius * radius;
    le->pdf_pos = (in_focus ? share / (kPi * r * r) : 0.f) +
                  (in_disk ? (1 - share) / (kPi * radius * radius) : 0.f);
}

VplTracer::VplTracer(const Scene& scene, const VplOptions& options)
    : m_scene(scene), m_options(options), m_light_sampler("power", scene.lights()) {
    if (!options.light_pmf.empty()) m_light_pmf = Distribution1D(options.light_pmf);
}

void VplTracer::trace_chunk(size_t chunk_index, size_t chunk_paths, VplChunk& chunk) const {
    auto sampler = create_sampler("independent", 1, m_options.seed);
    ScratchBuffer scratch;
    size_t first = chunk_index * chunk_paths;
    chunk.path_end.reserve(chunk_paths);
    for (size_t k = first; k < first + chunk_paths; ++k) {
        sampler->start_pixel_sample({int(k & 0xfffff), int(k >> 20)}, 0);
        chunk.path_light.push_back(trace_path(*sampler, scratch, chunk));
        scratch.reset();
        chunk.path_end.push_back(uint32_t(chunk.lights.size()));
    }
}

// The path's VPLs into chunk; returns the index of the light it started from (-1: none).
int VplTracer::trace_path(Sampler& sampler, ScratchBuffer& scratch, VplChunk& chunk,
                          const float* given_time) const {
    // Step 0: in a scene that moves, the path's time, uniform over the shutter (drawn only
    // there, so that static scenes keep their VPLs) unless the caller gives it. Every ray of the
    // path is traced at it.
    float time = 0.f;
    if (m_scene.moves()) time = given_time ? *given_time : m_scene.time_at(sampler.get_1d());
    // Step 1: a light by power (or by options.light_pmf), a ray leaving it; beta is the flux
    // the path carries.
    float u_light = sampler.get_1d();
    Vec2 u_pos = sampler.get_2d(), u_dir = sampler.get_2d();
    const Light* light = nullptr;
    float pmf = 0;
    if (m_light_pmf.size() > 0) {
        size_t i = m_light_pmf.sample_discrete(u_light, &pmf);
        light = m_scene.lights()[i].get();
    } else if (auto sl = m_light_sampler.sample(u_light)) {
        light = sl->light;
        pmf = sl->pmf;
    }
    if (!light || pmf == 0) return -1;
    // Emission focus (VplOptions): u_pos.x picks the disk, then places the point on it.
    Vec3 disk_center;
    float disk_radius = 0;
    const bool focused = m_options.focus_share > 0 && m_options.focus_radius > 0 &&
                         light->emission_sphere(&disk_center, &disk_radius) &&
                         m_options.focus_radius < disk_radius;
    const float share = m_options.focus_share;
    const bool on_focus = focused && u_pos.x < share;
    if (focused)
        u_pos.x = on_focus ? u_pos.x / share
                           : std::min((u_pos.x - share) / (1 - share), kOneMinusEpsilon);
    auto le = light->sample_le(u_pos, u_dir);
    if (le && focused) focus_emission(disk_center, disk_radius, on_focus, u_pos, &*le);
    if (!le || le->L.is_black() || le->pdf_pos == 0 || le->pdf_dir == 0) return light->index;
    bool on_surface = length_squared(le->n_light) > 0;
    float cos_l = on_surface ? abs_dot(le->n_light, le->ray.d) : 1.f;
    RGB beta = le->L * (cos_l / (pmf * le->pdf_pos * le->pdf_dir));
    float beta0 = beta.max_component();
    if (!(beta0 > 0) || !beta.is_finite()) return light->index;

    // Step 2: follow it, leaving a VPL at every surface that is not delta (nor, when
    // skipping glossy surfaces, glossy), and carrying on by importance-mode BSDF sampling.
    // Off the emitter's surface (sample_le leaves the origin on it), as spawn_ray does.
    Ray ray = le->ray;
    ray.time = time;
    ray.o = offset_ray_origin(ray.o, surface_offset(le->n_light, le->p_error), ray.d);
    SurfaceInteraction si;
    int deposited = 0;
    bool after_specular = false;                     // the last bounce was a delta lobe
    int max_bounces = 4 * m_options.max_depth + 16;  // delta and skipped surfaces included
    // In a scene with media, the medium the ray travels in (the light's on the ray's side).
    const bool media = m_scene.has_media();
    const Medium* medium = media ? light->medium_towards(le->ray.d, le->n_light) : nullptr;
    // Russian roulette after the second bounce, on the throughput relative to the start.
    auto survives = [&](int bounce, float u_rr) {
        if (bounce < 1) return true;
        float q = std::max(0.f, 1.f - beta.max_component() / beta0);
        if (u_rr < q) return false;
        beta = beta / (1.f - q);
        return true;
    };
    for (int bounce = 0; bounce < max_bounces; ++bounce) {
        const bool hit = m_scene.intersect(ray, &si);
        if (medium) {
            // Delta tracking to a scattering, an absorption or the surface (volume_path.h).
            const UnitRay u = unit_ray(ray, hit ? si.t : kInfinity);
            RGB unused;
            const MediumCollision ev =
                track_medium(*medium, u.ray, u.tmax, sampler, &beta, &unused, false);
            if (ev.event == MediumEvent::Absorb || beta.is_black() || !beta.is_finite()) break;
            if (ev.event == MediumEvent::Scatter) {
                const Vec3 p = u.ray.at(ev.t), wo = -u.ray.d;
                if ((after_specular || !m_options.after_specular_only) &&
                    !m_options.region.excludes(p)) {
                    size_t before = chunk.lights.size();
                    deposit_medium_vpl(p, wo, medium->g(), beta, chunk);
                    if (chunk.lights.size() > before)
                        chunk.lights.back().depth = uint8_t(std::min(255, deposited + 1));
                }
                if (++deposited >= m_options.max_depth) break;
                const Vec2 u_dir = sampler.get_2d();
                const float u_rr = sampler.get_1d();
                // The phase function is its own density: beta keeps its value.
                ray = Ray{p, sample_hg_phase(wo, medium->g(), u_dir), kInfinity, time};
                after_specular = false;
                if (!survives(bounce, u_rr)) break;
                continue;
            }
        }
        if (!hit) break;
        if (media && is_interface(si)) {
            // A medium's boundary only: the ray goes on in the medium beyond.
            medium = medium_after(si, ray.d, medium);
            ray = Ray{si.offset_origin(ray.d), ray.d, kInfinity, time};
            continue;
        }
        // Not hit_bsdf: deposit() builds the BSDF again from si, which must keep its unbumped
        // normal; cosines use the BSDF's own normal instead.
        Bsdf bsdf = si.material ? si.material->get_bsdf(si, scratch) : Bsdf();
        if (!bsdf) break;
        uint8_t flags = bsdf.flags();
        bool glossy = flags & kBxdfGlossy;
        if (bsdf.has_nonspecular() && (m_options.glossy != GlossyVpls::Skip || !glossy)) {
            if ((after_specular || !m_options.after_specular_only) &&
                !m_options.region.excludes(si.p)) {
                size_t before = chunk.lights.size();
                deposit_vpl(si, bsdf, beta, m_options.glossy, chunk);
                if (chunk.lights.size() > before)
                    chunk.lights.back().depth = uint8_t(std::min(255, deposited + 1));
            }
            if (++deposited >= m_options.max_depth) break;
        }
        float uc = sampler.get_1d();
        Vec2 u = sampler.get_2d();
        float u_rr = sampler.get_1d();
        auto bs = bsdf.sample(si.wo, uc, u, TransportMode::Importance);
        if (!bs) break;
        after_specular = bs->is_specular();
        beta *= bs->f * (abs_dot(bs->wi, bsdf.frame().n) / bs->pdf_solid_angle);
        ray = spawn_ray(si, bs->wi);
        if (media) medium = medium_after(si, bs->wi, medium);
        if (!survives(bounce, u_rr)) break;
        if (beta.is_black() || !beta.is_finite()) break;
    }
    return light->index;
}

void deposit_vpl(const SurfaceInteraction& si, const Bsdf& bsdf, const RGB& beta, GlossyVpls glossy,
                 VplChunk& chunk) {
    deposit_impl(si, bsdf, beta, glossy, chunk);
}

void deposit_medium_vpl(const Vec3& p, const Vec3& wi, float g, const RGB& beta, VplChunk& chunk) {
    if (beta.is_black()) return;
    if (!chunk.arena) chunk.arena = std::make_unique<ScratchBuffer>(256 * 1024);
    PointLight pl;
    pl.p = p;  // on no surface: no offset
    pl.is_vpl = true;
    const Bsdf phase = phase_bsdf(wi, g, *chunk.arena);
    const RGB peak(hg_phase_max(g));
    pl.intensity = beta * peak;
    if (std::abs(g) < 1e-3f) {
        pl.kind = PointLightKind::Omni;  // isotropic: the same intensity every way
    } else {
        // A lobe about the direction the phase function favours: forward (-wi) for g > 0,
        // back (wi) for g < 0; each bin bounds it over the directions at least its angle away.
        pl.kind = PointLightKind::Glossy;
        pl.n = g > 0 ? -wi : wi;
        pl.falloff[0] = 0;
        for (int k = 1; k < kFalloffBins; ++k) {
            const RGB b = phase.max_value_bound(wi, DirectionCone(-pl.n, -kFalloffCos[k]));
            pl.falloff[k] = quantize_falloff(b.max_component() / peak.max_component());
        }
    }
    pl.surface = int32_t(chunk.surfaces.size());
    chunk.surfaces.push_back(VplSurface{phase, wi, beta, false});
    chunk.lights.push_back(pl);
}

RGB estimate_max_bsdf_value(const Bsdf& bsdf, const Vec3& wi, bool with_cos, bool diffuse_only) {
    // Probe directions: a spherical Fibonacci set, the normal, the mirror direction, and BSDF
    // samples from wi (which crowd where f(wi, .) = f(., wi) peaks, reciprocity); the largest
    // value seen, doubled for what falls between probes. An estimate, not a proof: it is
    // replaced by Bxdf bounds when those exist.
    const Vec3& n = bsdf.frame().n;
    RGB best;
    Vec3 peak = n;
    float peak_value = -1;
    auto probe = [&](const Vec3& w) {
        RGB f = diffuse_only ? bsdf.eval_diffuse(w, wi, TransportMode::Radiance)
                             : bsdf.eval(w, wi, TransportMode::Radiance);
        if (with_cos) f = f * abs_dot(w, n);
        if (!f.is_finite()) return false;
        best = max_rgb(best, f);
        if (f.max_component() <= peak_value) return false;
        peak_value = f.max_component();
        peak = w;
        return true;
    };
    constexpr int kGrid = 96, kSamples = 32;
    for (int i = 0; i < kGrid; ++i) probe(fibonacci_direction(i, kGrid));
    probe(n);
    probe(-n);
    probe(n * (2 * dot(wi, n)) - wi);
    // Rings near grazing on both sides, where layered and microfacet lobes grow.
    Frame f = Frame::from_z(n);
    for (float c : {0.002f, 0.02f, 0.06f, 0.15f})
        for (int j = 0; j < 24; ++j) {
            float phi = 2 * kPi * (float(j) + 0.5f) / 24, s = safe_sqrt(1 - c * c);
            probe(f.to_world({s * std::cos(phi), s * std::sin(phi), c}));
            probe(f.to_world({s * std::cos(phi), s * std::sin(phi), -c}));
        }
    for (int i = 0; i < kSamples; ++i) {
        Vec2 u = shifted_hammersley(uint32_t(i), kSamples, Vec2(0.5f / kSamples, 0.5f));
        auto s = bsdf.sample(wi, (float(i) + 0.5f) / kSamples, u, TransportMode::Radiance);
        if (s && !s->is_specular()) probe(s->wi);
    }
    // Pattern search about the largest value: narrow lobes near grazing peak between probes.
    for (float step : {0.1f, 0.03f, 0.01f, 0.003f, 0.001f})
        for (int round = 0; round < 3; ++round) {
            Frame pf = Frame::from_z(peak);
            bool moved = false;
            for (int j = 0; j < 8; ++j) {
                float phi = 2 * kPi * float(j) / 8;
                Vec3 d = pf.to_world({std::sin(step) * std::cos(phi),
                                      std::sin(step) * std::sin(phi), std::cos(step)});
                moved |= probe(d);
            }
            if (!moved) break;
        }
    return best * 2.f;
}

void append_scaled_vpl(const PointLight& pl, const std::vector<VplSurface>& surfaces, float scale,
                       std::vector<PointLight>& lights, std::vector<VplSurface>& out_surfaces) {
    PointLight scaled = pl;
    scaled.intensity = pl.intensity * scale;
    if (pl.surface >= 0) {
        VplSurface s = surfaces[size_t(pl.surface)];
        s.flux = s.flux * scale;
        scaled.surface = int32_t(out_surfaces.size());
        out_surfaces.push_back(s);
    }
    lights.push_back(scaled);
}

void append_vpls(std::vector<VplChunk>& chunks, size_t count, float scale, PointLightSet& set) {
    // Both vectors sized once: grown by doubling, the old and new buffers would be held together
    // at up to three times the surfaces' size, more than the memory check counts.
    size_t surfaces = 0;
    for (size_t left = count, c = 0; left > 0 && c < chunks.size(); ++c) {
        const size_t take = std::min(left, chunks[c].lights.size());
        for (size_t i = 0; i < take; ++i) surfaces += chunks[c].lights[i].surface >= 0;
        left -= take;
    }
    set.lights.reserve(set.lights.size() + count);
    set.surfaces.reserve(set.surfaces.size() + surfaces);
    size_t left = count;
    for (VplChunk& ch : chunks) {
        if (left == 0) break;
        size_t take = std::min(left, ch.lights.size());
        for (size_t i = 0; i < take; ++i)
            append_scaled_vpl(ch.lights[i], ch.surfaces, scale, set.lights, set.surfaces);
        if (ch.arena) set.arenas.push_back(std::move(ch.arena));
        // Copied: the chunk's lights and surfaces are released as the set's grow.
        std::vector<PointLight>().swap(ch.lights);
        std::vector<VplSurface>().swap(ch.surfaces);
        left -= take;
    }
    set.vpls += count;
}

void generate_vpls(const Scene& scene, const VplOptions& options, PointLightSet& set,
                   std::vector<int>* vpl_lights) {
    if ((options.count <= 0 && options.paths == 0) || options.max_depth <= 0 ||
        scene.lights().empty())
        return;
    VplTracer tracer(scene, options);
    auto trace = [&](std::vector<VplChunk>& chunks, size_t begin, size_t end) {
        parallel_for_chunks(begin, end, size_t(1), [&](size_t b, size_t e) {
            for (size_t c = b; c != e; ++c) tracer.trace_chunk(c, kChunkPaths, chunks[c]);
        });
    };
    std::vector<VplChunk> chunks;
    size_t kept_paths = 0, kept_vpls = 0;
    if (options.paths > 0) {
        // A fixed number of paths: whole chunks, the last one cut to size.
        chunks.resize((options.paths + kChunkPaths - 1) / kChunkPaths);
        trace(chunks, 0, chunks.size());
        kept_paths = options.paths;
        VplChunk& last = chunks.back();
        size_t in_last = options.paths - (chunks.size() - 1) * kChunkPaths;
        last.lights.resize(in_last > 0 ? last.path_end[in_last - 1] : 0);
        last.path_end.resize(in_last);
        last.path_light.resize(in_last);
        for (const VplChunk& ch : chunks) kept_vpls += ch.lights.size();
    } else {
        size_t target = size_t(options.count);
        // Give up on scenes where light paths find no surface (nothing to deposit on).
        size_t max_chunks = (64 * target + 65536) / kChunkPaths + 1;

        // Step 1: trace chunks of paths in waves until the target is met; each wave's size
        // comes from the VPLs per path seen so far. The waves only decide how much is traced,
        // never what a path holds, so the kept set below does not depend on them.
        size_t total = 0;
        while (total < target && chunks.size() < max_chunks) {
            size_t traced = chunks.size() * kChunkPaths;
            double per_path = traced > 0 && total > 0 ? double(total) / double(traced) : 1.0;
            double paths =
                traced > 0 ? double(target - total) / per_path * 1.05 : double(target) / 4;
            size_t wave = std::clamp(size_t(std::ceil(paths / double(kChunkPaths))), size_t(1),
                                     max_chunks - chunks.size());
            if (traced > 0 && total == 0)
                wave = std::min(chunks.size() * 2, max_chunks - chunks.size());
            size_t begin = chunks.size();
            chunks.resize(begin + wave);
            trace(chunks, begin, begin + wave);
            for (size_t c = begin; c < chunks.size(); ++c) total += chunks[c].lights.size();
        }

        // Step 2: keep paths in order up to the first at which the target is reached.
        for (const VplChunk& ch : chunks) {
            size_t before = kept_vpls;
            auto it = std::find_if(ch.path_end.begin(), ch.path_end.end(),
                                   [&](uint32_t e) { return before + e >= target; });
            if (it == ch.path_end.end()) {
                kept_paths += ch.path_end.size();
                kept_vpls += ch.lights.size();
                continue;
            }
            kept_paths += size_t(it - ch.path_end.begin()) + 1;
            kept_vpls += *it;
            break;
        }
    }
    if (kept_paths == 0) return;
    if (vpl_lights) {
        size_t left = kept_vpls;
        for (const VplChunk& ch : chunks) {
            uint32_t start = 0;
            for (size_t k = 0; k < ch.path_end.size() && left > 0; ++k) {
                uint32_t n = std::min<uint32_t>(ch.path_end[k] - start, uint32_t(left));
                vpl_lights->insert(vpl_lights->end(), n, ch.path_light[k]);
                left -= n;
                start = ch.path_end[k];
            }
        }
    }

    // Step 3: concatenate with fluxes divided by the number of paths kept.
    append_vpls(chunks, kept_vpls, 1.f / float(kept_paths), set);
    set.light_paths += kept_paths;
}

}  // namespace ml
