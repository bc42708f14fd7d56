#include "integrators/mlt/bidir_mutation.h"

#include <cmath>
#include <vector>

#include "bidir/subpaths.h"
#include "integrators/mlt/path_media.h"
#include "lights/light_sampler.h"
#include "sampling/warps.h"
#include "transport/direct_lighting.h"

namespace ml {

namespace {

Vec3 dir(const PathVertex& from, const PathVertex& to) { return normalize(to.p() - from.p()); }

float importance_of(const RGB& c) {
    float y = c.luminance();
    return std::isfinite(y) && y > 0 ? y : 0.f;
}

// Veach's unnormalised p_d over the deleted edges.
double deletion_weight(int k_d) { return k_d == 2 ? 0.5 : std::ldexp(1.0, -k_d); }

// Extends the kept surface or medium vertex path[-1], whose neighbour on its own side is `from`,
// by `count` vertices written from path[0]: its BSDF or phase function samples the first
// direction (the delta flag records a surface's lobe), BDPT's random walk the rest. False unless
// every vertex was made.
bool extend_from_surface(const BdptScene& ctx, PathVertex* path, const PathVertex& from, int count,
                         TransportMode mode, Sampler& sampler, ScratchBuffer& scratch) {
    float uc = sampler.get_1d();
    Vec2 u = sampler.get_2d();
    PathVertex& v = path[-1];
    if (v.kind == VertexKind::Medium) {
        v.si.wo = dir(v, from);
        const Vec3 wi = sample_hg_phase(v.si.wo, v.medium->g(), u);
        return continue_subpath(ctx, Ray{v.p(), wi, kInfinity, v.si.time},
                                hg_phase(v.si.wo, wi, v.medium->g()), sampler, scratch, count, mode,
                                path, v.medium, DistanceSampling::Majorant) == count;
    }
    if (v.kind != VertexKind::Surface || !v.bsdf) return false;
    v.si.wo = dir(v, from);
    auto bs = v.bsdf.sample(v.si.wo, uc, u, mode);
    if (!bs || bs->pdf_solid_angle == 0 || bs->f.is_black()) return false;
    v.delta = bs->is_specular();
    float pdf = v.delta ? 0.f : bs->pdf_solid_angle;
    return continue_subpath(ctx, spawn_ray(v.si, bs->wi), pdf, sampler, scratch, count, mode, path,
                            v.medium_towards(ctx, bs->wi), mlt_distance_sampling(ctx)) == count;
}

// Extends the kept light vertex path[-1] by `count` vertices from path[0], its direction drawn as
// sample_le draws directions: the lights' direction distributions depend on the origin only
// through its normal, so a direction sampled at another origin is carried over in the normal's
// frame (area lights; point and spot lights have one origin).
bool extend_from_light(const BdptScene& ctx, PathVertex* path, int count, Sampler& sampler,
                       ScratchBuffer& scratch) {
    Vec2 u_dir = sampler.get_2d();
    const PathVertex& l = path[-1];
    if (!l.light) return false;
    auto les = l.light->sample_le(Vec2(0.5f, 0.5f), u_dir);
    if (!les || les->pdf_dir == 0) return false;
    Vec3 d = les->ray.d;
    if (l.on_surface()) d = Frame::from_z(l.ng()).to_world(Frame::from_z(les->n_light).to_local(d));
    float pdf_pos = 0, pdf_dir = 0;
    l.light->pdf_le(Ray{l.p(), d}, l.ng(), &pdf_pos, &pdf_dir);
    if (!(pdf_dir > 0)) return false;
    Ray ray{l.on_surface() ? l.si.offset_origin(d) : l.p(), d, kInfinity, l.si.time};
    return continue_subpath(ctx, ray, pdf_dir, sampler, scratch, count, TransportMode::Importance,
                            path, l.light->medium_towards(d, l.ng()),
                            mlt_distance_sampling(ctx)) == count;
}

}  // namespace

double deletion_probability(int n, int k_d) {
    if (k_d < 2 || k_d > n + 1) return 0;
    double total = 0;
    for (int k = 2; k <= n + 1; ++k) total += deletion_weight(k);
    return deletion_weight(k_d) / total;
}

std::optional<Proposal> mutate_bidirectional_partial(const BdptScene& ctx, const MltPath& x,
                                                     Sampler& sampler, ScratchBuffer& scratch,
                                                     BidirChoice* choice) {
    const int n = int(x.v.size());
    const PerspectiveCamera& cam = ctx.camera;
    const bool media = ctx.scene.has_media();

    // 1. The deletion: k_d edges, x_{a+1} .. x_{b-1} with b = a + k_d, a in [-1, n - k_d].
    float u_length = sampler.get_1d(), u_position = sampler.get_1d(), u_split = sampler.get_1d();
    int k_d = n + 1;
    double acc = 0;
    for (int k = 2; k <= n; ++k) {
        acc += deletion_probability(n, k);
        if (u_length < acc) {
            k_d = k;
            break;
        }
    }
    const int positions = n + 2 - k_d;
    const int a = std::min(int(u_position * float(positions)), positions - 1) - 1;
    const int b = a + k_d, m = k_d - 1;

    // 2. The split: l_E eye vertices (at least the lens when it was deleted), l_L light ones;
    //    the strategy (s, t) joins the first t vertices to the last s.
    const int e_min = a < 0 ? 1 : 0;
    const int l_e = e_min + std::min(int(u_split * float(m + 1 - e_min)), m - e_min);
    const int l_l = m - l_e;
    const int t = a + 1 + l_e, s = n - t;
    if (choice) *choice = BidirChoice{a, b, l_e, 0};
    if (s == 1 && t == 1) return std::nullopt;

    thread_local std::vector<PathVertex> ev, lv;  // eye side in camera order, light side reversed
    ev.resize(size_t(n));
    lv.resize(size_t(n));
    MltPath y;
    y.p_raster = x.p_raster;
    y.u_lens = x.u_lens;
    y.u_time = x.u_time;

    // 3. The eye side: a new camera ray when the lens or its first vertex went (through the kept
    //    lens point if there is one), else the walk from x_a; a deleted lens with l_E = 1 is
    //    sampled by the connection.
    for (int k = 0; k <= a; ++k) ev[size_t(k)] = x.v[size_t(k)];
    if (l_e > 0 && a <= 0 && t >= 2) {
        Vec2 film = sampler.get_2d();
        CameraSample cs{cam.raster_point(film), x.u_lens, x.u_time};
        if (a < 0) cs.p_lens = sampler.get_2d();
        if (generate_camera_subpath(ctx, cam.generate_ray(cs), sampler, scratch, t, ev.data(),
                                    nullptr, mlt_distance_sampling(ctx)) != t)
            return std::nullopt;
        y.p_raster = cs.p_film;
        y.u_lens = cs.p_lens;
    } else if (l_e > 0 && a >= 1) {
        if (!extend_from_surface(ctx, &ev[size_t(a + 1)], ev[size_t(a - 1)], l_e,
                                 TransportMode::Radiance, sampler, scratch))
            return std::nullopt;
    }

    // 4. The light side likewise: a new light subpath when the light went, a new direction from
    //    the kept light, or the walk from x_b; a deleted light with l_L = 1 is sampled by the
    //    connection.
    const int kept_l = n - b;
    for (int k = b; k < n; ++k) lv[size_t(n - 1 - k)] = x.v[size_t(k)];
    if (l_l > 0 && kept_l == 0 && s >= 2) {
        if (generate_light_subpath(ctx, sampler, scratch, s, cam.sample_time(x.u_time), lv.data(),
                                   mlt_distance_sampling(ctx)) != s)
            return std::nullopt;
    } else if (l_l > 0 && kept_l == 1) {
        if (!extend_from_light(ctx, &lv[1], l_l, sampler, scratch)) return std::nullopt;
    } else if (l_l > 0 && kept_l >= 2) {
        if (!extend_from_surface(ctx, &lv[size_t(kept_l)], lv[size_t(kept_l - 2)], l_l,
                                 TransportMode::Importance, sampler, scratch))
            return std::nullopt;
    }

    // 5. The connection, its visibility traced.
    if (s == 0) {
        // The eye side ended on an emitter: that vertex is the light endpoint.
        PathVertex& e = ev[size_t(n - 1)];
        if (e.kind != VertexKind::Surface || !e.si.area_light) return std::nullopt;
        e.kind = VertexKind::Light;
        e.light = e.si.area_light;
        e.si.ns = e.si.ng;
        e.bsdf = Bsdf();
    } else if (t == 1) {
        PathVertex& q = lv[size_t(s - 1)];
        if (q.kind == VertexKind::Light || !q.is_connectible()) return std::nullopt;
        if (a < 0) {
            auto cs = cam.sample_wi(q.p(), sampler.get_2d(), q.si.time);
            if (!cs) return std::nullopt;
            ev[0] = PathVertex::camera(cs->p_lens, cs->n_lens, RGB(1.f));
            ev[0].si.time = q.si.time;
            y.p_raster = cs->p_raster;
            if (cam.lens_radius() > 0) {
                Vec3 pl = cam.camera_to_world(q.si.time).inverse().point(cs->p_lens);
                y.u_lens = invert_uniform_disk_concentric(
                    Vec2(pl.x / cam.lens_radius(), pl.y / cam.lens_radius()));
            }
        } else if (cam.importance(Ray{ev[0].p(), dir(ev[0], q), kInfinity, ev[0].si.time},
                                  &y.p_raster) == 0) {
            return std::nullopt;
        }
        if (!media && !mutually_visible(ctx.scene, q, ev[0])) return std::nullopt;
    } else {
        PathVertex& p = ev[size_t(t - 1)];
        if (p.kind == VertexKind::Camera || !p.is_connectible()) return std::nullopt;
        if (s == 1 && kept_l == 0) {
            auto light_point = sample_light_point_by_area(ctx, sampler);
            if (!light_point) return std::nullopt;
            lv[0] = *light_point;
        }
        PathVertex& q = lv[size_t(s - 1)];
        if (!q.is_connectible() || (!media && !mutually_visible(ctx.scene, p, q)))
            return std::nullopt;
    }

    // 6. The new path, lens first; the connection's ends were not sampled through a lobe.
    y.v.reserve(size_t(n));
    for (int k = 0; k < t; ++k) y.v.push_back(ev[size_t(k)]);
    for (int j = s - 1; j >= 0; --j) y.v.push_back(lv[size_t(j)]);
    if (s > 0) y.v[size_t(t - 1)].delta = y.v[size_t(t)].delta = false;
    if (!mlt_supported(y)) return std::nullopt;
    rebind_bsdfs(y, scratch);
    // In media: every edge traced through interfaces, the new ones' transmittances estimated.
    if (!trace_media_edges(ctx, y, &x, sampler)) return std::nullopt;

    // 7. f / sum p_s over the window of this deletion's strategies, for y and x: its ratio is
    //    f(y) T(y -> x) / (f(x) T(x -> y)). Proposals by splits outside y's counted run are
    //    refused, and so are all when x cannot be made by this deletion (T(y -> x) = 0).
    const int s_min = n - b, s_max = n - a - 1;
    int lo = -1, hi = -1;
    RGB gy = path_over_bdpt_density(ctx, y, &lo, &hi, s_min, s_max);
    float iy = importance_of(gy);
    if (iy == 0 || s < lo || s > hi) return std::nullopt;
    float ix = importance_of(path_over_bdpt_density(ctx, x, nullptr, nullptr, s_min, s_max));
    if (ix == 0) return std::nullopt;
    Proposal p;
    p.accept = std::min(1.f, iy / ix);
    p.colour = gy / iy;
    if (a < 0 && b == n) p.W = gy;  // the whole path: gy is its f / q
    p.y = std::move(y);
    if (choice) choice->ratio = double(iy) / double(ix);
    return p;
}

}  // namespace ml
