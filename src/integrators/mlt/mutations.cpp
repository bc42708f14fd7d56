#include "integrators/mlt/mutations.h"

#include <thread>

#include "bidir/connect.h"
#include "bidir/subpaths.h"
#include "integrators/mlt/path_media.h"
#include "materials/material.h"
#include "sampling/warps.h"
#include "transport/direct_lighting.h"
#include "transport/volume_path.h"

namespace ml {

namespace {

Vec3 dir(const PathVertex& from, const PathVertex& to) { return normalize(to.p() - from.p()); }

// A surface vertex at the hit of `ray`, with its BSDF. In a scene with media, the ray passes
// through interfaces; `medium` is the one it starts in, and becomes the one it arrived in (the
// vertex's).
std::optional<PathVertex> surface_hit(const BdptScene& ctx, Ray ray, ScratchBuffer& scratch,
                                      const Medium*& medium) {
    PathVertex v;
    for (int crossing = 0;; ++crossing) {
        if (!ctx.scene.intersect(ray, &v.si)) return std::nullopt;
        if (!ctx.scene.has_media() || !is_interface(v.si)) break;
        if (crossing >= 256) return std::nullopt;
        medium = medium_after(v.si, ray.d, medium);
        ray = Ray{v.si.offset_origin(ray.d), ray.d, kInfinity, ray.time};
    }
    v.medium = medium;
    v.kind = VertexKind::Surface;
    v.ns_hit = v.si.ns;
    v.bsdf = hit_bsdf(v.si, scratch);
    if (!v.bsdf) return std::nullopt;
    return v;
}

float importance_of(const RGB& c) {
    float y = c.luminance();
    return std::isfinite(y) && y > 0 ? y : 0.f;
}

// The caustic perturbation turns the direction leaving the first non-specular vertex by an angle
// between these (radians), as Veach suggests (thesis, section 11.4.3).
constexpr float kCausticAngleMin = 1e-4f, kCausticAngleMax = 0.1f;

// An exponentially distributed size between lo and hi (density proportional to 1 / size).
float exponential_size(float u, float lo, float hi) {
    return hi * std::exp(-std::log(hi / lo) * u);
}

Proposal make_proposal(MltPath y, const RGB& target_y, const RGB& target_x) {
    Proposal p;
    float iy = importance_of(target_y), ix = importance_of(target_x);
    p.accept = ix > 0 ? std::min(1.f, iy / ix) : 1.f;
    p.colour = iy > 0 ? target_y / iy : RGB();
    p.y = std::move(y);
    return p;
}

}  // namespace

bool transmits(const MltPath& x, int k) {
    const PathVertex& v = x.v[size_t(k)];
    return dot(dir(v, x.v[size_t(k - 1)]), v.ng()) * dot(dir(v, x.v[size_t(k + 1)]), v.ng()) < 0;
}

bool mlt_supported(const MltPath& x) {
    if (x.v.size() < 2) return false;
    const PathVertex& l = x.v.back();
    if (l.kind != VertexKind::Light || !l.light) return false;
    LightType t = l.light->type();
    if (t != LightType::Area && t != LightType::DeltaPosition) return false;
    for (size_t k = 1; k + 1 < x.v.size(); ++k) {
        const PathVertex& v = x.v[k];
        if (v.kind == VertexKind::Medium && v.medium) continue;
        if (v.kind != VertexKind::Surface || !v.bsdf) return false;
        if (v.delta && !v.bsdf.is_specular_only()) return false;
    }
    return true;
}

void rebind_bsdfs(MltPath& y, ScratchBuffer& scratch) {
    for (PathVertex& v : y.v) {
        if (v.kind != VertexKind::Surface) continue;
        SurfaceInteraction si = v.si;
        si.ns = v.ns_hit;
        v.bsdf = hit_bsdf(si, scratch);
        v.si.ns = si.ns;
    }
}

RGB proposal_weight(const BdptScene& ctx, const MltPath& y, int strategy) {
    int lo = -1, hi = -1;
    RGB W = path_over_bdpt_density(ctx, y, &lo, &hi);
    return strategy >= lo && strategy <= hi ? W : RGB();
}

std::optional<MltPath> sample_bdpt_path(const BdptScene& ctx, Sampler& sampler, int depth,
                                        ScratchBuffer& scratch, int* strategy) {
    // The strategy, uniformly; then the subpaths and their connection, as BdptEstimator does.
    int n = depth == 0 ? 1 : depth + 2;
    int s = depth == 0 ? 0 : std::min(int(sampler.get_1d() * float(n)), n - 1);
    int t = (depth == 0 ? 2 : n) - s;
    if (strategy) *strategy = s;
    const PerspectiveCamera& cam = ctx.camera;
    Vec2 u = sampler.get_2d();
    Vec2 u_lens = sampler.get_2d();
    float u_time = sampler.get_1d();
    CameraSample cs{cam.raster_point(u), u_lens, u_time};
    std::vector<PathVertex> cv(static_cast<size_t>(t)), lv(static_cast<size_t>(std::max(s, 1)));
    const bool media = ctx.scene.has_media();
    const DistanceSampling sampling = mlt_distance_sampling(ctx);
    if (generate_camera_subpath(ctx, cam.generate_ray(cs), sampler, scratch, t, cv.data(), nullptr,
                                sampling) != t)
        return std::nullopt;
    if (generate_light_subpath(ctx, sampler, scratch, s, cam.sample_time(u_time), lv.data(),
                               sampling) != s)
        return std::nullopt;
    PathVertex sampled;
    Connection c;
    if (media && s >= 2) {
        // The connection's ends only: trace_media_edges traces it (through interfaces) and f / q
        // weighs it (connect_bdpt's estimate would draw the transmittance again).
        const PathVertex& q = lv[size_t(s - 1)];
        if (!q.is_connectible()) return std::nullopt;
        if (t == 1) {
            auto ws = cam.sample_wi(q.p(), sampler.get_2d(), q.si.time);
            if (!ws) return std::nullopt;
            sampled = PathVertex::camera(ws->p_lens, ws->n_lens, RGB(1.f));
            sampled.si.time = q.si.time;
            c.splat = true;
            c.p_raster = ws->p_raster;
        } else if (!cv[size_t(t - 1)].is_connectible()) {
            return std::nullopt;
        }
    } else if (s == 1) {
        // The light point by area density, the density path_over_bdpt_density counts for s = 1
        // (connect_bdpt's light sample draws by solid angle: with it the bootstrap's mean, and so
        // the image, was 5.5% bright on tests/scenes/light_invisible, where no path meets the
        // light and s = 1 carries its direct light).
        const PathVertex& pt = cv[size_t(t - 1)];
        if (!pt.is_connectible()) return std::nullopt;
        auto light_point = sample_light_point_by_area(ctx, sampler);
        if (!light_point) return std::nullopt;
        sampled = *light_point;
        sampled.si.time = pt.si.time;
        if (!media && !mutually_visible(ctx.scene, pt, sampled)) return std::nullopt;
    } else {
        c = connect_bdpt(ctx, lv.data(), cv.data(), s, t, sampler, &sampled);
        if (c.L.is_black()) return std::nullopt;
    }

    // The whole path, lens first.
    MltPath x;
    x.p_raster = c.splat ? c.p_raster : cs.p_film;
    x.u_lens = cs.p_lens;
    x.u_time = u_time;
    if (t == 1) {
        x.v.push_back(sampled);
        if (cam.lens_radius() > 0) {
            Vec3 pl = cam.camera_to_world(sampled.si.time).inverse().point(sampled.p());
            x.u_lens = invert_uniform_disk_concentric(
                Vec2(pl.x / cam.lens_radius(), pl.y / cam.lens_radius()));
        }
    } else {
        for (int i = 0; i < t; ++i) x.v.push_back(cv[size_t(i)]);
    }
    if (s == 1) {
        x.v.push_back(sampled);
    } else {
        for (int i = s - 1; i >= 0; --i) x.v.push_back(lv[size_t(i)]);
    }
    if (s == 0) {
        // The camera subpath ended on an area light: that vertex is the light endpoint.
        PathVertex& e = x.v.back();
        e.kind = VertexKind::Light;
        e.light = e.si.area_light;
        e.si.ns = e.si.ng;
        e.bsdf = Bsdf();
    }
    if (!mlt_supported(x) || !trace_media_edges(ctx, x, nullptr, sampler)) return std::nullopt;
    return x;
}

std::optional<Proposal> mutate_bidirectional(const BdptScene& ctx, const MltPath& x, RGB* Wx,
                                             Sampler& sampler, ScratchBuffer& scratch) {
    int strategy = -1;
    auto y = sample_bdpt_path(ctx, sampler, x.depth(), scratch, &strategy);
    if (!y) return std::nullopt;
    RGB Wy = proposal_weight(ctx, *y, strategy);
    if (importance_of(Wy) == 0) return std::nullopt;
    if (Wx->is_black()) *Wx = path_over_bdpt_density(ctx, x);
    // A current path that BDPT cannot make (q(x) = 0, reached by a perturbation) cannot be
    // proposed back: T(y -> x) = 0, so the move is refused, not accepted.
    if (importance_of(*Wx) == 0) return std::nullopt;
    Proposal p = make_proposal(std::move(*y), Wy, *Wx);
    p.W = Wy;
    return p;
}

int lens_vertex(const MltPath& x) {
    // The form E S* D (D|L): j is the first vertex that is not specular.
    const int n = int(x.v.size());
    int j = 1;
    while (j < n - 1 && is_specular_vertex(x, j)) ++j;
    if (j >= n - 1 || x.v[size_t(j)].kind != VertexKind::Surface ||
        !x.v[size_t(j)].is_connectible())
        return -1;
    if (j + 1 < n - 1 && is_specular_vertex(x, j + 1)) return -1;
    return j;
}

float lens_offset_max(const PerspectiveCamera& cam) {
    return std::max(0.05f * 0.5f * float(cam.width() + cam.height()), 0.2f);
}

Vec2 lens_offset(const PerspectiveCamera& cam, float u_size, float u_angle) {
    float r = exponential_size(u_size, 0.1f, lens_offset_max(cam));
    float phi = 2 * kPi * u_angle;
    return Vec2(r * std::cos(phi), r * std::sin(phi));
}

namespace {

std::optional<MltPath> lens_candidate(const BdptScene& ctx, const MltPath& x, int j, const Vec2& p,
                                      const SurfaceInteraction* first_hit, ScratchBuffer& scratch) {
    const PerspectiveCamera& cam = ctx.camera;
    if (!cam.in_raster(p)) return std::nullopt;
    // Through the same specular chain to a new vertex j, joined to the old j + 1.
    MltPath y = x;
    y.p_raster = p;
    Ray ray = cam.generate_ray({p, x.u_lens, x.u_time});
    const Medium* medium = ctx.scene.camera_medium();
    for (int k = 1; k <= j; ++k) {
        std::optional<PathVertex> v;
        if (k == 1 && first_hit) {
            PathVertex h;
            h.kind = VertexKind::Surface;
            h.si = *first_hit;
            h.ns_hit = h.si.ns;
            h.bsdf = hit_bsdf(h.si, scratch);
            if (h.bsdf) v = h;
        } else if (k > 1 || !first_hit) {
            v = surface_hit(ctx, ray, scratch, medium);
        }
        if (!v) return std::nullopt;
        bool specular = v->bsdf.is_specular_only();
        if (specular != (k < j)) return std::nullopt;
        y.v[size_t(k)] = *v;
        if (k == j) break;
        auto wi = specular_direction(*v, -ray.d, transmits(x, k));
        if (!wi) return std::nullopt;
        ray = spawn_ray(v->si, *wi);
        medium = medium_after(v->si, *wi, medium);
    }
    if (!y.v[size_t(j)].is_connectible() ||
        (!ctx.scene.has_media() &&
         !mutually_visible(ctx.scene, y.v[size_t(j)], y.v[size_t(j + 1)])))
        return std::nullopt;
    rebind_bsdfs(y, scratch);
    return y;
}

}  // namespace

std::optional<Proposal> mutate_lens(const BdptScene& ctx, const MltPath& x, Sampler& sampler,
                                    ScratchBuffer& scratch) {
    float u_size = sampler.get_1d(), u_angle = sampler.get_1d();
    int j = lens_vertex(x);
    if (j < 0) return std::nullopt;
    Vec2 p = x.p_raster + lens_offset(ctx.camera, u_size, u_angle);
    auto y = lens_candidate(ctx, x, j, p, nullptr, scratch);
    if (!y || !trace_media_edges(ctx, *y, &x, sampler)) return std::nullopt;
    RGB ty = lens_target(ctx, *y, j);
    if (importance_of(ty) == 0) return std::nullopt;
    return make_proposal(std::move(*y), ty, lens_target(ctx, x, j));
}

std::optional<Proposal> mutate_caustic(const BdptScene& ctx, const MltPath& x, Sampler& sampler,
                                       ScratchBuffer& scratch) {
    float u_size = sampler.get_1d(), u_angle = sampler.get_1d();
    // The form E D S+ (D|L): m is the first vertex after 1 that is not specular.
    const int n = int(x.v.size());
    if (n < 4 || x.v[1].kind != VertexKind::Surface || is_specular_vertex(x, 1) ||
        !x.v[1].is_connectible())
        return std::nullopt;
    int m = 2;
    while (m < n - 1 && is_specular_vertex(x, m)) ++m;
    if (m < 3) return std::nullopt;
    const PathVertex& vm = x.v[size_t(m)];
    if (m < n - 1 && !vm.is_connectible()) return std::nullopt;

    // The direction leaving m, turned by a small angle.
    Vec3 w = dir(vm, x.v[size_t(m - 1)]);
    float theta = exponential_size(u_size, kCausticAngleMin, kCausticAngleMax);
    float phi = 2 * kPi * u_angle;
    Vec3 w2 = Frame::from_z(w).to_world(spherical_direction(std::sin(theta), std::cos(theta), phi));
    Ray ray{vm.on_surface() ? vm.si.offset_origin(w2) : vm.p(), w2, kInfinity, vm.si.time};

    // Back through the specular chain to a new vertex 1, seen from the same lens point.
    MltPath y = x;
    const Medium* medium = vm.medium_towards(ctx, w2);
    for (int k = m - 1; k >= 1; --k) {
        auto v = surface_hit(ctx, ray, scratch, medium);
        if (!v) return std::nullopt;
        bool specular = v->bsdf.is_specular_only();
        if (specular != (k >= 2)) return std::nullopt;
        y.v[size_t(k)] = *v;
        if (k == 1) break;
        auto wi = specular_direction(*v, -ray.d, transmits(x, k));
        if (!wi) return std::nullopt;
        ray = spawn_ray(v->si, *wi);
        medium = medium_after(v->si, *wi, medium);
    }
    const PathVertex &e = y.v[0], &d1 = y.v[1];
    if (!d1.is_connectible()) return std::nullopt;
    Vec2 raster;
    if (ctx.camera.importance(Ray{e.p(), normalize(d1.p() - e.p()), kInfinity, e.si.time},
                              &raster) == 0)
        return std::nullopt;
    if (!ctx.scene.has_media() && !mutually_visible(ctx.scene, d1, e)) return std::nullopt;
    y.p_raster = raster;
    rebind_bsdfs(y, scratch);
    if (!trace_media_edges(ctx, y, &x, sampler)) return std::nullopt;
    RGB ty = caustic_target(ctx, y, m);
    if (importance_of(ty) == 0) return std::nullopt;
    return make_proposal(std::move(y), ty, caustic_target(ctx, x, m));
}

}  // namespace ml
