#include "bidir/subpaths.h"

#include <algorithm>

#include "materials/material.h"
#include "transport/direct_lighting.h"
#include "transport/spawn.h"
#include "transport/volume_path.h"

namespace ml {

namespace {

// Extends `path` (whose vertex -1 exists) by at most `max_vertices` vertices along `ray`, which
// starts in participating medium `medium` (null: none); `pdf_fwd` is the solid-angle density
// with which the previous vertex chose ray.d. In a medium, delta tracking (as `path`'s) decides
// where the ray scatters: a medium vertex whose density, as pbrt-v3's BDPT has it, leaves out
// the distance's (the throughput carries it; every strategy's weight uses the same densities,
// so the weights still sum to one).
//
// `sampling`: how distances in media are drawn (subpaths.h).
//
// `medium_emission` (camera subpaths only; null: not wanted): max_vertices entries, entry n the
// light the media emit along the stretch after the walk's n-th vertex (n = 0: from the start),
// times the throughput, as `path` adds it.
int random_walk(const BdptScene& ctx, Ray ray, Sampler& sampler, ScratchBuffer& scratch, RGB beta,
                float pdf_fwd, int max_vertices, TransportMode mode, PathVertex* path,
                const Medium* medium, RGB* medium_emission, DistanceSampling sampling) {
    if (max_vertices <= 0) return 0;
    if (medium_emission) std::fill(medium_emission, medium_emission + max_vertices, RGB());
    int n = 0;
    RGB unused_emission;
    for (int crossings = 0; crossings < 4096; ++crossings) {
        if (beta.is_black() || !beta.is_finite()) break;
        PathVertex& vertex = path[n];
        PathVertex& prev = path[n - 1];
        // Intersect straight into the vertex (no zeroed temporary: this is the hot loop).
        const bool hit = ctx.scene.intersect(ray, &vertex.si);
        if (medium) {
            const UnitRay u = unit_ray(ray, hit ? vertex.si.t : kInfinity);
            MediumCollision ev;
            if (sampling == DistanceSampling::Majorant) {
                if (const std::optional<float> t =
                        first_majorant_collision(*medium, u.ray, u.tmax, sampler))
                    ev = MediumCollision{MediumEvent::Scatter, *t};
            } else {
                ev = track_medium(*medium, u.ray, u.tmax, sampler, &beta,
                                  medium_emission ? &medium_emission[n] : &unused_emission,
                                  medium_emission != nullptr);
            }
            if (ev.event == MediumEvent::Absorb) break;
            if (ev.event == MediumEvent::Scatter) {
                const Vec3 p = u.ray.at(ev.t), wo = -u.ray.d;
                vertex = PathVertex::in_medium(p, wo, medium, ray.time, beta);
                vertex.pdf_fwd = prev.convert_density(pdf_fwd, vertex);
                if (++n >= max_vertices) break;
                const Vec3 wi = sample_hg_phase(wo, medium->g(), sampler.get_2d());
                // The phase function is its own density, the same both ways.
                pdf_fwd = hg_phase(wo, wi, medium->g());
                prev.pdf_rev = vertex.convert_density(pdf_fwd, prev);
                ray = Ray{p, wi, kInfinity, ray.time};
                continue;
            }
        }
        if (!hit) {
            // Camera rays that escape end on the infinite lights (one vertex for all of them).
            if (mode == TransportMode::Radiance && !ctx.scene.infinite_lights().empty()) {
                vertex = PathVertex::light_endpoint(nullptr, ray.o + ray.d, -ray.d, beta, pdf_fwd);
                ++n;
            }
            break;
        }
        if (medium || (vertex.si.mesh && vertex.si.mesh->medium_interface)) {
            if (is_interface(vertex.si)) {
                // A medium boundary only: the ray goes on, in the medium beyond.
                medium = medium_after(vertex.si, ray.d, medium);
                ray = Ray{vertex.si.offset_origin(ray.d), ray.d, kInfinity, ray.time};
                continue;
            }
        }
        vertex.medium = medium;
        vertex.kind = VertexKind::Surface;
        vertex.delta = false;
        vertex.light = nullptr;
        vertex.pdf_rev = 0;
        vertex.beta = beta;
        vertex.ns_hit = vertex.si.ns;
        vertex.bsdf = hit_bsdf(vertex.si, scratch);
        vertex.pdf_fwd = prev.convert_density(pdf_fwd, vertex);
        if (++n >= max_vertices || !vertex.bsdf) break;

        // Sample the BSDF for the next direction; record the reverse density at prev.
        float uc = sampler.get_1d();
        Vec2 u = sampler.get_2d();
        auto bs = vertex.bsdf.sample(vertex.si.wo, uc, u, mode);
        if (!bs) break;
        pdf_fwd = bs->pdf_solid_angle;
        beta *= bs->f * (abs_dot(bs->wi, vertex.si.ns) / bs->pdf_solid_angle);
        TransportMode other =
            mode == TransportMode::Radiance ? TransportMode::Importance : TransportMode::Radiance;
        float pdf_rev = vertex.bsdf.pdf_solid_angle(bs->wi, vertex.si.wo, other);
        if (bs->is_specular()) {
            vertex.delta = true;
            pdf_fwd = pdf_rev = 0;
        }
        prev.pdf_rev = vertex.convert_density(pdf_rev, prev);
        ray = spawn_ray(vertex.si, bs->wi);
        medium = medium_after(vertex.si, bs->wi, medium);
    }
    return n;
}

}  // namespace

int generate_camera_subpath(const BdptScene& ctx, const Ray& ray, Sampler& sampler,
                            ScratchBuffer& scratch, int max_vertices, PathVertex* path,
                            RGB* medium_emission, DistanceSampling sampling) {
    if (max_vertices <= 0) return 0;
    // A pinhole is a point (no normal); a thin lens is a surface facing forwards, but the
    // camera vertex is never the far end of a density conversion, so the normal is moot.
    path[0] = PathVertex::camera(ray.o, Vec3(), RGB(1.f));
    path[0].si.time = ray.time;
    float pdf_pos, pdf_dir;
    ctx.camera.pdf_we(ray, &pdf_pos, &pdf_dir);
    if (medium_emission) medium_emission[max_vertices - 1] = RGB();
    return 1 + random_walk(ctx, ray, sampler, scratch, RGB(1.f), pdf_dir, max_vertices - 1,
                           TransportMode::Radiance, path + 1, ctx.scene.camera_medium(),
                           medium_emission, sampling);
}

int continue_subpath(const BdptScene& ctx, const Ray& ray, float pdf_dir, Sampler& sampler,
                     ScratchBuffer& scratch, int max_vertices, TransportMode mode, PathVertex* path,
                     const Medium* medium, DistanceSampling sampling) {
    return random_walk(ctx, ray, sampler, scratch, RGB(1.f), pdf_dir, max_vertices, mode, path,
                       medium, nullptr, sampling);
}

int generate_light_subpath(const BdptScene& ctx, Sampler& sampler, ScratchBuffer& scratch,
                           int max_vertices, float time, PathVertex* path,
                           DistanceSampling sampling) {
    if (max_vertices <= 0) return 0;
    float u_select = sampler.get_1d();
    Vec2 u_pos = sampler.get_2d();
    Vec2 u_dir = sampler.get_2d();
    auto sl = ctx.light_sampler.sample(u_select);
    if (!sl || sl->pmf == 0) return 0;
    auto les = sl->light->sample_le(u_pos, u_dir);
    if (!les || les->pdf_pos == 0 || les->pdf_dir == 0 || les->L.is_black()) return 0;

    // The light vertex: its density is the light choice times the position's.
    float pdf_origin = sl->pmf * les->pdf_pos;
    path[0] = PathVertex::light_endpoint(sl->light, les->ray.o, les->n_light, les->L, pdf_origin,
                                         les->p_error, les->prim);
    path[0].si.time = time;
    path[0].si.uv = les->uv;
    float cos_light = les->n_light == Vec3() ? 1.f : abs_dot(les->n_light, les->ray.d);
    RGB beta = les->L * (cos_light / (pdf_origin * les->pdf_dir));
    // Off the light's surface, to the side the ray leaves by (points stay where they are).
    Ray ray = les->ray;
    ray.time = time;
    if (path[0].on_surface()) ray.o = path[0].si.offset_origin(ray.d);
    int n = random_walk(ctx, ray, sampler, scratch, beta, les->pdf_dir, max_vertices - 1,
                        TransportMode::Importance, path + 1,
                        sl->light->medium_towards(les->ray.d, les->n_light), nullptr, sampling);

    // Infinite lights: the first hit's density is the disk's (planar, times its cosine), and
    // the light vertex's is the direction's.
    if (path[0].is_infinite_light()) {
        if (n > 0) {
            path[1].pdf_fwd = les->pdf_pos;
            if (path[1].on_surface()) path[1].pdf_fwd *= abs_dot(ray.d, path[1].ng());
        }
        path[0].pdf_fwd = ctx.infinite_light_density(ray.d);
    }
    return n + 1;
}

}  // namespace ml
