#include "integrators/mlt/mutations.h"

#include <thread>

#include "integrators/bdpt/connect.h"
#include "integrators/bdpt/subpaths.h"
#include "integrators/common.h"
#include "materials/material.h"
#include "sampling/warps.h"

namespace ml {

namespace {

Vec3 dir(const PathVertex& from, const PathVertex& to) { return normalize(to.p() - from.p()); }

// True if vertex k of x refracts (its two neighbours lie on opposite sides of its surface).
bool transmits(const MltPath& x, int k) {
    const PathVertex& v = x.v[size_t(k)];
    return dot(dir(v, x.v[size_t(k - 1)]), v.ng()) * dot(dir(v, x.v[size_t(k + 1)]), v.ng()) < 0;
}

// A surface vertex at the hit of `ray`, with its BSDF.
std::optional<PathVertex> surface_hit(const BdptScene& ctx, const Ray& ray,
                                      ScratchBuffer& scratch) {
    PathVertex v;
    if (!ctx.scene.intersect(ray, &v.si)) return std::nullopt;
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

bool mlt_supported(const MltPath& x) {
    if (x.v.size() < 2) return false;
    const PathVertex& l = x.v.back();
    if (l.kind != VertexKind::Light || !l.light) return false;
    LightType t = l.light->type();
    if (t != LightType::Area && t != LightType::DeltaPosition) return false;
    for (size_t k = 1; k + 1 < x.v.size(); ++k) {
        const PathVertex& v = x.v[k];
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
    CameraSample cs{Vec2(u.x * float(cam.width()), u.y * float(cam.height())), sampler.get_2d(), 0};
    std::vector<PathVertex> cv(static_cast<size_t>(t)), lv(static_cast<size_t>(std::max(s, 1)));
    if (generate_camera_subpath(ctx, cam.generate_ray(cs), sampler, scratch, t, cv.data()) != t)
        return std::nullopt;
    if (generate_light_subpath(ctx, sampler, scratch, s, lv.data()) != s) return std::nullopt;
    PathVertex sampled;
    Connection c = connect_bdpt(ctx, lv.data(), cv.data(), s, t, sampler, &sampled);
    if (c.L.is_black()) return std::nullopt;

    // The whole path, lens first.
    MltPath x;
    x.p_raster = c.splat ? c.p_raster : cs.p_film;
    x.u_lens = cs.p_lens;
    if (t == 1) {
        x.v.push_back(sampled);
        if (cam.lens_radius() > 0) {
            Vec3 pl = cam.camera_to_world().inverse().point(sampled.p());
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
    if (!mlt_supported(x)) return std::nullopt;
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
    Proposal p = make_proposal(std::move(*y), Wy, *Wx);
    p.W = Wy;
    return p;
}

namespace {

int lens_vertex(const MltPath& x) {
    // The form E S* D (D|L): j is the first vertex that is not specular.
    const int n = int(x.v.size());
    int j = 1;
    while (j < n - 1 && is_specular_vertex(x, j)) ++j;
    if (j >= n - 1 || !x.v[size_t(j)].is_connectible()) return -1;
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

float lens_offset_density(const PerspectiveCamera& cam, const Vec2& a, const Vec2& b) {
    float r = std::sqrt(sqr(a.x - b.x) + sqr(a.y - b.y)), r_max = lens_offset_max(cam);
    if (!(r >= 0.1f && r <= r_max)) return 0;
    // Radial density 1 / (r log(r_max / r_min)), spread over the circle of radius r.
    return 1 / (r * std::log(r_max / 0.1f) * 2 * kPi * r);
}

std::optional<MltPath> lens_candidate(const BdptScene& ctx, const MltPath& x, int j, const Vec2& p,
                                      const SurfaceInteraction* first_hit, ScratchBuffer& scratch) {
    const PerspectiveCamera& cam = ctx.camera;
    if (!(p.x >= 0 && p.y >= 0 && p.x < float(cam.width()) && p.y < float(cam.height())))
        return std::nullopt;
    // Through the same specular chain to a new vertex j, joined to the old j + 1.
    MltPath y = x;
    y.p_raster = p;
    Ray ray = cam.generate_ray({p, x.u_lens, 0});
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
            v = surface_hit(ctx, ray, scratch);
        }
        if (!v) return std::nullopt;
        bool specular = v->bsdf.is_specular_only();
        if (specular != (k < j)) return std::nullopt;
        y.v[size_t(k)] = *v;
        if (k == j) break;
        auto wi = specular_direction(*v, -ray.d, transmits(x, k));
        if (!wi) return std::nullopt;
        ray = spawn_ray(v->si, *wi);
    }
    if (!y.v[size_t(j)].is_connectible() ||
        !mutually_visible(ctx.scene, y.v[size_t(j)], y.v[size_t(j + 1)]))
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
    if (!y) return std::nullopt;
    RGB ty = lens_target(ctx, *y, j);
    if (importance_of(ty) == 0) return std::nullopt;
    return make_proposal(std::move(*y), ty, lens_target(ctx, x, j));
}

std::optional<Proposal> mutate_lens_multiple_try(const BdptScene& ctx, const MltPath& x,
                                                 Sampler& sampler, ScratchBuffer& scratch) {
    constexpr int kTries = 4;
    Vec2 u[2 * kTries];
    for (Vec2& v : u) v = sampler.get_2d();
    float u_pick = sampler.get_1d();
    int j = lens_vertex(x);
    if (j < 0) return std::nullopt;
    const PerspectiveCamera& cam = ctx.camera;

    // Up to four perturbations of `from`, their first hits traced as one packet, and their
    // weights.
    struct Try {
        std::optional<MltPath> y;
        RGB target;
        double weight = 0;
    };
    auto tries = [&](const MltPath& from, const Vec2* us, int count, const MltPath& to, Try* out) {
        Ray rays[4];
        bool active[4] = {false, false, false, false}, hit[4];
        Vec2 p[4];
        SurfaceInteraction si[4];
        for (int i = 0; i < count; ++i) {
            p[i] = from.p_raster + lens_offset(cam, us[i].x, us[i].y);
            active[i] = p[i].x >= 0 && p[i].y >= 0 && p[i].x < float(cam.width()) &&
                        p[i].y < float(cam.height());
            rays[i] = cam.generate_ray({p[i], from.u_lens, 0});
        }
        ctx.scene.intersect4(rays, active, si, hit);
        for (int i = 0; i < count; ++i) {
            out[i] = Try();
            if (!active[i] || !hit[i]) continue;
            out[i].y = lens_candidate(ctx, from, j, p[i], &si[i], scratch);
            if (!out[i].y) continue;
            out[i].target = lens_target(ctx, *out[i].y, j);
            // w(y) = pi(y) T(y -> to) lambda(y, to) with the symmetric lambda = 1 / T: the
            // offsets' density is symmetric, so the weight is pi(y) wherever T > 0.
            out[i].weight = lens_offset_density(cam, out[i].y->p_raster, to.p_raster) > 0
                                ? double(importance_of(out[i].target))
                                : 0.0;
        }
    };

    // 1. Four tries from x; one of them, y, picked in proportion to its weight.
    Try ys[kTries];
    tries(x, u, kTries, x, ys);
    double sum_y = 0;
    for (const Try& t : ys) sum_y += t.weight;
    if (!(sum_y > 0)) return std::nullopt;
    int pick = 0;
    for (double acc = 0; pick < kTries - 1; ++pick) {
        acc += ys[pick].weight;
        if (u_pick * sum_y < acc) break;
    }
    while (ys[pick].weight == 0) --pick;

    // 2. Reference points: three tries from y, and x itself.
    Try xs[kTries];
    tries(*ys[pick].y, u + kTries, kTries - 1, *ys[pick].y, xs);
    double sum_x = double(importance_of(lens_target(ctx, x, j)));
    for (int i = 0; i < kTries - 1; ++i) sum_x += xs[i].weight;

    // 3. Accept with min(1, sum of the tries' weights / sum of the reference points').
    Proposal prop;
    float iy = importance_of(ys[pick].target);
    prop.accept = sum_x > 0 ? float(std::min(1.0, sum_y / sum_x)) : 1.f;
    prop.colour = ys[pick].target / iy;
    prop.y = std::move(*ys[pick].y);
    return prop;
}

std::optional<Proposal> mutate_caustic(const BdptScene& ctx, const MltPath& x, Sampler& sampler,
                                       ScratchBuffer& scratch) {
    float u_size = sampler.get_1d(), u_angle = sampler.get_1d();
    // The form E D S+ (D|L): m is the first vertex after 1 that is not specular.
    const int n = int(x.v.size());
    if (n < 4 || is_specular_vertex(x, 1) || !x.v[1].is_connectible()) return std::nullopt;
    int m = 2;
    while (m < n - 1 && is_specular_vertex(x, m)) ++m;
    if (m < 3) return std::nullopt;
    const PathVertex& vm = x.v[size_t(m)];
    if (m < n - 1 && !vm.is_connectible()) return std::nullopt;

    // The direction leaving m, turned by a small angle.
    Vec3 w = dir(vm, x.v[size_t(m - 1)]);
    float theta = exponential_size(u_size, 1e-4f, 0.1f);
    float phi = 2 * kPi * u_angle;
    Vec3 w2 = Frame::from_z(w).to_world(spherical_direction(std::sin(theta), std::cos(theta), phi));
    Ray ray{vm.on_surface() ? vm.si.offset_origin(w2) : vm.p(), w2};

    // Back through the specular chain to a new vertex 1, seen from the same lens point.
    MltPath y = x;
    for (int k = m - 1; k >= 1; --k) {
        auto v = surface_hit(ctx, ray, scratch);
        if (!v) return std::nullopt;
        bool specular = v->bsdf.is_specular_only();
        if (specular != (k >= 2)) return std::nullopt;
        y.v[size_t(k)] = *v;
        if (k == 1) break;
        auto wi = specular_direction(*v, -ray.d, transmits(x, k));
        if (!wi) return std::nullopt;
        ray = spawn_ray(v->si, *wi);
    }
    const PathVertex &e = y.v[0], &d1 = y.v[1];
    if (!d1.is_connectible()) return std::nullopt;
    Vec2 raster;
    if (ctx.camera.importance(Ray{e.p(), normalize(d1.p() - e.p())}, &raster) == 0)
        return std::nullopt;
    if (!mutually_visible(ctx.scene, d1, e)) return std::nullopt;
    y.p_raster = raster;
    rebind_bsdfs(y, scratch);
    RGB ty = caustic_target(ctx, y, m);
    if (importance_of(ty) == 0) return std::nullopt;
    return make_proposal(std::move(y), ty, caustic_target(ctx, x, m));
}

}  // namespace ml
