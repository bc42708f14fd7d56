#include "integrators/mlt/path_space.h"

#include "integrators/mlt/path_media.h"
#include "lights/light_sampler.h"
#include "sampling/sampler.h"

namespace ml {

namespace {

Vec3 dir(const PathVertex& from, const PathVertex& to) { return normalize(to.p() - from.p()); }

// The delta-lobe sample of `v` from `wo` whose direction is `wi`, if any.
std::optional<BsdfSample> matching_specular(const PathVertex& v, const Vec3& wo, const Vec3& wi,
                                            TransportMode mode = TransportMode::Radiance) {
    if (v.kind != VertexKind::Surface || !v.bsdf) return std::nullopt;
    for (float uc : {0.f, kOneMinusEpsilon}) {
        auto bs = v.bsdf.sample(wo, uc, Vec2(0.5f, 0.5f), mode);
        if (bs && bs->is_specular() && dot(bs->wi, wi) > 1 - 1e-3f) return bs;
    }
    return std::nullopt;
}

// The BSDF's value (no cosine) at a surface vertex, the phase function's at a medium vertex.
RGB vertex_value(const PathVertex& v, const Vec3& wo, const Vec3& wi,
                 TransportMode mode = TransportMode::Radiance) {
    if (v.kind == VertexKind::Medium) return RGB(hg_phase(wo, wi, v.medium->g()));
    return v.bsdf ? v.bsdf.eval(wo, wi, mode) : RGB();
}

// Scattering value (no cosine) at vertex k of the path, light arriving from k + 1 and leaving
// towards k - 1; the delta-lobe weight f |cos| for specular vertices.
RGB scattering(const MltPath& x, int k) {
    const PathVertex& v = x.v[size_t(k)];
    Vec3 wo = dir(v, x.v[size_t(k - 1)]), wi = dir(v, x.v[size_t(k + 1)]);
    if (is_specular_vertex(x, k)) return specular_weight(v, wo, wi);
    return vertex_value(v, wo, wi);
}

// Radiance (area lights) or intensity (point and spot lights) the path's light sends towards
// vertex `to`.
RGB emission(const BdptScene& ctx, const PathVertex& light, const PathVertex& to) {
    if (!light.light) return RGB();
    if (light.light->type() == LightType::Area) return light.Le(ctx, to);
    if (light.light->type() != LightType::DeltaPosition) return RGB();
    auto ls =
        light.light->sample_li(LightSampleContext{to.p(), to.ng(), to.ns()}, Vec2(0.5f, 0.5f));
    if (!ls) return RGB();
    return ls->L * distance_squared(to.p(), light.p());
}

// Cosine at vertex v towards w (1 for points and medium vertices).
float cosine(const PathVertex& v, const Vec3& w) {
    return v.on_surface() ? abs_dot(v.ns(), w) : 1.f;
}

// Every factor of f(x) beyond vertex k (exclusive) towards the light that depends on colour:
// scattering at k + 1 .. n - 2 and the emission. Scalar geometry terms are left out.
RGB light_side_colour(const BdptScene& ctx, const MltPath& x, int k) {
    int n = int(x.v.size());
    RGB c(1.f);
    for (int i = k + 1; i <= n - 2; ++i) c *= scattering(x, i);
    return c * emission(ctx, x.v.back(), x.v[size_t(n - 2)]);
}

}  // namespace

RGB specular_weight(const PathVertex& v, const Vec3& wo, const Vec3& wi) {
    auto bs = matching_specular(v, wo, wi);
    return bs ? bs->f * abs_dot(bs->wi, v.ns()) : RGB();
}

std::optional<Vec3> specular_direction(const PathVertex& v, const Vec3& wo, bool transmission) {
    if (v.kind != VertexKind::Surface || !v.bsdf || !v.bsdf.is_specular_only()) return std::nullopt;
    for (float uc : {0.f, kOneMinusEpsilon}) {
        auto bs = v.bsdf.sample(wo, uc, Vec2(0.5f, 0.5f));
        if (bs && bs->is_specular() && bs->is_transmission() == transmission) return bs->wi;
    }
    return std::nullopt;
}

std::optional<PathVertex> sample_light_point_by_area(const BdptScene& ctx, Sampler& sampler) {
    float u_select = sampler.get_1d();
    Vec2 u = sampler.get_2d();
    auto sl = ctx.light_sampler.sample(u_select);
    if (!sl || sl->pmf == 0) return std::nullopt;
    // Only the point is kept; the direction's numbers must still give it a density, or
    // sample_le fails: (0.5, 0.5) is the horizon of a two-sided light's back side (pdf 0, so
    // strategy s = 1 never sampled a two-sided light), (0.25, 0.5) the front side's normal.
    auto les = sl->light->sample_le(u, Vec2(0.25f, 0.5f));
    if (!les || les->L.is_black() || les->pdf_pos == 0) return std::nullopt;
    PathVertex v = PathVertex::light_endpoint(sl->light, les->ray.o, les->n_light, RGB(1.f), 0,
                                              les->p_error, les->prim);
    v.si.uv = les->uv;
    return v;
}

RGB path_over_bdpt_density(const BdptScene& ctx, const MltPath& x, int* s_lo, int* s_hi, int s_min,
                           int s_max) {
    const int n = int(x.v.size());
    if (n < 2 || !x.v.back().light) return RGB();
    const PathVertex& lv = x.v.back();
    const Light* light = lv.light;
    const bool area = light->type() == LightType::Area;
    const bool point = light->type() == LightType::DeltaPosition;
    if (!area && !point) return RGB();

    // 1. Densities from the vertices' positions: pdf_fwd[k] of x_k sampled from the camera side,
    //    pdf_rev[k] from the light side (the light's choice and position for the light itself).
    std::vector<float> fwd(size_t(n), 0.f), rev(size_t(n), 0.f);
    for (int k = 1; k < n; ++k)
        fwd[size_t(k)] = x.v[size_t(k - 1)].pdf_area(ctx, k >= 2 ? &x.v[size_t(k - 2)] : nullptr,
                                                     x.v[size_t(k)]);
    for (int k = 0; k + 2 < n; ++k)
        rev[size_t(k)] = x.v[size_t(k + 1)].pdf_area(ctx, &x.v[size_t(k + 2)], x.v[size_t(k)]);
    rev[size_t(n - 2)] = lv.pdf_light(ctx, x.v[size_t(n - 2)]);
    rev[size_t(n - 1)] = lv.pdf_light_origin(ctx, x.v[size_t(n - 2)]);
    // Camera rays are drawn over the film and its margin (PerspectiveCamera::raster_point), so
    // that splats reach the border pixels from past the edge as camera samples do: their
    // direction's density is pdf_we (which counts the film alone) over that area's ratio.
    const float film_ratio = ctx.camera.raster_area_ratio();
    fwd[1] /= film_ratio;
    // In media, each sampled edge's distance density (path_media.h).
    for (int k = 1; k < n; ++k) fwd[size_t(k)] *= media_density(x, k - 1, k);
    for (int k = 0; k + 1 < n; ++k) rev[size_t(k)] *= media_density(x, k, k);

    // 2. The strategies that make this path: s light vertices joined to t = n - s camera
    //    vertices where both ends can connect. Strategies on either side of a specular vertex
    //    sample it through different delta distributions, whose ratio is no density: only the
    //    run of consecutive strategies with the most light vertices counts (the proposals of
    //    the others are refused), so q is a true density of this path.
    auto connectible = [&](int k) {
        if (k == 0) return true;
        if (k == n - 1) return true;  // area, point or spot light
        return !is_specular_vertex(x, k) && x.v[size_t(k)].is_connectible();
    };
    auto valid = [&](int s) {
        if (s < s_min || s > s_max) return false;
        int t = n - s;
        if (t < 1 || (s == 1 && t == 1)) return false;
        if (s == 0) return area && light->met_by_rays();  // (no path meets an invisible light)
        if (t == 1 && n - 1 < 2) return false;
        return connectible(t - 1) && connectible(t);
    };
    int hi = n - 1;
    while (hi >= 0 && !valid(hi)) --hi;
    if (hi < 0) return RGB();
    int lo = hi;
    while (lo > 0 && valid(lo - 1)) --lo;
    if (n == 2) lo = hi = 0;  // depth 0: the camera path alone
    if (s_lo) *s_lo = lo;
    if (s_hi) *s_hi = hi;

    // 3. Sum of p_s / p_hi over the run, from the ratios of neighbouring strategies:
    //    p_{s-1} / p_s = fwd[n - s] / rev[n - s].
    double sum = 1, ratio = 1;
    for (int s = hi; s > lo; --s) {
        float f = fwd[size_t(n - s)], r = rev[size_t(n - s)];
        if (!(f > 0 && r > 0)) return RGB();
        ratio *= double(f) / double(r);
        sum += ratio;
    }

    // 4. f / p_hi: the strategy's own estimate, subpath throughputs from the positions.
    const int s = hi, t = n - s;
    auto scatter = [&](int k, const PathVertex& toward_light, const PathVertex& toward_eye,
                       TransportMode mode) {
        // f |cos| / pdf at x_k, sampled from the side `mode` comes from.
        const PathVertex& v = x.v[size_t(k)];
        if (v.kind == VertexKind::Medium) return RGB(1.f);  // the phase function samples itself
        bool radiance = mode == TransportMode::Radiance;
        Vec3 wo = dir(v, radiance ? toward_eye : toward_light);
        Vec3 wi = dir(v, radiance ? toward_light : toward_eye);
        if (is_specular_vertex(x, k)) {
            auto bs = matching_specular(v, wo, wi, mode);
            return bs ? bs->f * (abs_dot(bs->wi, v.ns()) / bs->pdf_solid_angle) : RGB();
        }
        float pdf = v.bsdf.pdf_solid_angle(wo, wi, mode);
        return pdf > 0 ? v.bsdf.eval(wo, wi, mode) * (abs_dot(wi, v.ns()) / pdf) : RGB();
    };
    auto camera_beta = [&](int k) {  // the camera subpath's throughput at x_k
        RGB beta(1.f);
        for (int i = 1; i < k; ++i)
            beta *= scatter(i, x.v[size_t(i + 1)], x.v[size_t(i - 1)], TransportMode::Radiance);
        return beta;
    };
    auto light_beta = [&](int k) {  // the light subpath's throughput at x_k (k < n - 1)
        const PathVertex& next = x.v[size_t(n - 2)];
        Vec3 w = dir(lv, next);
        float pdf_pos = 1, pdf_dir = 0;
        if (area)
            lv.light->pdf_le(Ray{lv.p(), w}, lv.ng(), &pdf_pos, &pdf_dir);
        else
            lv.light->pdf_le(Ray{lv.p(), w}, Vec3(), &pdf_pos, &pdf_dir);
        if (point) pdf_pos = 1;
        float pmf = ctx.light_sampler.pmf(light);
        if (!(pdf_pos > 0 && pdf_dir > 0 && pmf > 0)) return RGB();
        RGB beta = emission(ctx, lv, next) * (cosine(lv, w) / (pmf * pdf_pos * pdf_dir));
        for (int i = n - 2; i > k; --i)
            beta *= scatter(i, x.v[size_t(i + 1)], x.v[size_t(i - 1)], TransportMode::Importance);
        return beta;
    };
    RGB C;
    if (s == 0) {
        C = camera_beta(n - 1) * lv.Le(ctx, x.v[size_t(n - 2)]);
    } else if (s == 1) {
        const PathVertex& pt = x.v[size_t(n - 2)];
        Vec3 wo = dir(pt, x.v[size_t(n - 3)]), wi = dir(pt, lv);
        RGB Le;
        float pdf = 1;
        LightSampleContext lc{pt.p(), pt.ng(), pt.ns()};
        if (area) {
            Le = light->radiance(lv.p(), lv.ng(), lv.si.uv, -wi);
            // The light point's area density (bidir_mutation samples it so), over solid angle.
            float pos = 0, pdf_dir = 0;
            light->pdf_le(Ray{lv.p(), -wi}, lv.ng(), &pos, &pdf_dir);
            float cos_l = abs_dot(lv.ng(), wi);
            pdf = cos_l > 0 ? pos * distance_squared(pt.p(), lv.p()) / cos_l : 0.f;
        } else if (auto ls = light->sample_li(lc, Vec2(0.5f, 0.5f))) {
            Le = ls->L;
        }
        float pmf = ctx.light_sampler.pmf(light);
        if (!(pdf > 0 && pmf > 0)) return RGB();
        C = camera_beta(n - 2) * vertex_value(pt, wo, wi) * (cosine(pt, wi) / (pdf * pmf)) * Le;
    } else if (t == 1) {
        const PathVertex &e = x.v[0], &q = x.v[1];
        Vec3 wi = dir(q, e), wo = dir(q, x.v[2]);
        float d2 = distance_squared(e.p(), q.p());
        float We = ctx.camera.importance(Ray{e.p(), -wi, kInfinity, e.si.time});
        float pdf_wi = d2 / (abs_dot(ctx.camera.forward(e.si.time), wi) * ctx.camera.lens_area());
        C = light_beta(1) * vertex_value(q, wo, wi, TransportMode::Importance) *
            (cosine(q, wi) * We / pdf_wi);
    } else {
        const PathVertex &q = x.v[size_t(t)], &p = x.v[size_t(t - 1)];
        Vec3 d = q.p() - p.p();
        float d2 = length_squared(d);
        d = d / std::sqrt(d2);
        float g = cosine(p, d) * cosine(q, d) / d2;
        C = light_beta(t) *
            vertex_value(q, dir(q, x.v[size_t(t + 1)]), -d, TransportMode::Importance) *
            vertex_value(p, dir(p, x.v[size_t(t - 2)]), d) * camera_beta(t - 1) * g;
    }
    if (!x.edges.empty()) {
        // The media's colour over the distance densities of the edges this strategy sampled
        // (all but the connection (t - 1, t)): camera edges towards the light, light edges back.
        float density = 1;
        for (int k = 1; k <= t - 1; ++k) density *= media_density(x, k - 1, k);
        for (int k = t; k <= n - 2; ++k) density *= media_density(x, k, k);
        if (!(density > 0)) return RGB();
        C *= media_colour(x) / density;
    }
    if (t >= 2) C *= film_ratio;  // the camera ray's We cos / density
    if (C.is_black() || !C.is_finite()) return RGB();
    float n_strategies = n == 2 ? 1.f : float(n);
    return C * float(n_strategies / sum);
}

RGB lens_target(const BdptScene& ctx, const MltPath& x, int j) {
    RGB T(1.f);
    for (int k = 1; k < j; ++k) T *= scattering(x, k);
    const PathVertex &a = x.v[size_t(j)], &b = x.v[size_t(j + 1)];
    Vec3 d = b.p() - a.p();
    float d2 = length_squared(d);
    if (d2 == 0) return RGB();
    d = d / std::sqrt(d2);
    T *= scattering(x, j) * (cosine(a, d) * cosine(b, d) / d2);
    return T * light_side_colour(ctx, x, j) * media_colour(x);
}

RGB caustic_target(const BdptScene& ctx, const MltPath& x, int m) {
    const int n = int(x.v.size());
    const PathVertex& vm = x.v[size_t(m)];
    Vec3 w = dir(vm, x.v[size_t(m - 1)]);
    // From the light to vertex m: fixed colours, then m's scattering into w and its cosine.
    RGB T = m == n - 1 ? emission(ctx, vm, x.v[size_t(m - 1)])
                       : scattering(x, m) * light_side_colour(ctx, x, m);
    T *= cosine(vm, w);
    // The specular chain, then the first vertex seen from the lens.
    for (int k = 2; k < m; ++k) T *= scattering(x, k);
    const PathVertex &e = x.v[0], &d1 = x.v[1];
    Vec3 to_lens = e.p() - d1.p();
    float d2 = length_squared(to_lens);
    if (d2 == 0) return RGB();
    to_lens = to_lens / std::sqrt(d2);
    float We = ctx.camera.importance(Ray{e.p(), -to_lens, kInfinity, e.si.time});
    T *= scattering(x, 1) *
         (cosine(d1, to_lens) * We * abs_dot(ctx.camera.forward(e.si.time), to_lens) / d2);
    return T * media_colour(x);
}

}  // namespace ml
