#include "bidir/connect.h"

#include <optional>
#include <type_traits>
#include <utility>

namespace ml {

namespace {

// Sets a value for the rest of the scope, then puts the old one back. A large old value (a
// vertex) is kept in an optional, so an unused Scoped<PathVertex> costs no zeroed vertex.
template <typename T>
class Scoped {
    static constexpr bool kSmall = std::is_trivially_copyable_v<T> && sizeof(T) <= 8;
    using Saved = std::conditional_t<kSmall, T, std::optional<T>>;

public:
    Scoped() = default;
    Scoped(T* target, T value) : m_target(target) {
        if (m_target) {
            m_saved = std::move(*target);
            *target = std::move(value);
        }
    }
    Scoped(const Scoped&) = delete;
    Scoped& operator=(Scoped&& o) noexcept {
        restore();
        m_target = std::exchange(o.m_target, nullptr);
        m_saved = std::move(o.m_saved);
        return *this;
    }
    ~Scoped() { restore(); }

private:
    void restore() {
        if (!m_target) return;
        if constexpr (kSmall)
            *m_target = m_saved;
        else
            *m_target = std::move(*m_saved);
        m_target = nullptr;
    }
    T* m_target = nullptr;
    Saved m_saved{};
};

// The geometry term between two vertices (shading cosines; none at medium vertices), times
// what passes between them (visibility, or the media's transmittance).
RGB geometry(const BdptScene& ctx, const PathVertex& a, const PathVertex& b, Sampler& sampler) {
    Vec3 d = a.p() - b.p();
    float d2 = length_squared(d);
    if (d2 == 0) return RGB();
    float g = 1 / d2;
    d = d * std::sqrt(g);
    if (a.on_surface()) g *= abs_dot(a.ns(), d);
    if (b.on_surface()) g *= abs_dot(b.ns(), d);
    if (g == 0) return RGB();
    return transmittance_between(ctx, a, b, sampler) * g;
}

}  // namespace

float mis_weight(const BdptScene& ctx, PathVertex* light_vertices, PathVertex* camera_vertices,
                 const PathVertex& sampled, int s, int t, bool balance) {
    if (s + t == 2) return 1;
    // Zero densities stand for delta distributions: they cancel between numerator and
    // denominator, so they count as one.
    auto remap0 = [](float f) { return f != 0 ? f : 1.f; };

    // The connection vertices and their predecessors, with the sampled vertex in place.
    PathVertex* qs = s > 0 ? &light_vertices[s - 1] : nullptr;
    PathVertex* pt = t > 0 ? &camera_vertices[t - 1] : nullptr;
    PathVertex* qs_minus = s > 1 ? &light_vertices[s - 2] : nullptr;
    PathVertex* pt_minus = t > 1 ? &camera_vertices[t - 2] : nullptr;
    Scoped<PathVertex> a1;
    if (s == 1) a1 = Scoped<PathVertex>(qs, sampled);
    if (t == 1) a1 = Scoped<PathVertex>(pt, sampled);

    // The connection vertices were connected, so they are not delta whatever sampled them.
    Scoped<bool> a2(pt ? &pt->delta : nullptr, false);
    Scoped<bool> a3(qs ? &qs->delta : nullptr, false);

    // Reverse densities across the connection: each end as the other subpath would have
    // sampled it, and the predecessors likewise.
    Scoped<float> a4, a5, a6, a7;
    if (pt)
        a4 = Scoped<float>(&pt->pdf_rev, s > 0 ? qs->pdf_area(ctx, qs_minus, *pt)
                                               : pt->pdf_light_origin(ctx, *pt_minus));
    if (pt_minus)
        a5 = Scoped<float>(&pt_minus->pdf_rev, s > 0 ? pt->pdf_area(ctx, qs, *pt_minus)
                                                     : pt->pdf_light(ctx, *pt_minus));
    if (qs) a6 = Scoped<float>(&qs->pdf_rev, pt->pdf_area(ctx, pt_minus, *qs));
    if (qs_minus) a7 = Scoped<float>(&qs_minus->pdf_rev, qs->pdf_area(ctx, pt, *qs_minus));

    // Ratios p_i / p_s of the other strategies' densities, walking away from the connection
    // along each subpath (squared for the power heuristic).
    float sum = 0;
    float ri = 1;
    for (int i = t - 1; i > 0; --i) {
        ri *= remap0(camera_vertices[i].pdf_rev) / remap0(camera_vertices[i].pdf_fwd);
        if (!camera_vertices[i].delta && !camera_vertices[i - 1].delta)
            sum += balance ? ri : ri * ri;
    }
    ri = 1;
    for (int i = s - 1; i >= 0; --i) {
        ri *= remap0(light_vertices[i].pdf_rev) / remap0(light_vertices[i].pdf_fwd);
        bool delta_before =
            i > 0 ? light_vertices[i - 1].delta : light_vertices[0].is_delta_light();
        if (!light_vertices[i].delta && !delta_before) sum += balance ? ri : ri * ri;
    }
    return 1 / (1 + sum);
}

Connection connect_bdpt(const BdptScene& ctx, PathVertex* light_vertices,
                        PathVertex* camera_vertices, int s, int t, Sampler& sampler,
                        PathVertex* sampled_out) {
    Connection c;
    // A camera subpath ending on an infinite light connects to nothing.
    if (t > 1 && s != 0 && camera_vertices[t - 1].kind == VertexKind::Light) return c;

    RGB L;
    // The vertex sampled anew for s = 1 and t = 1, made only then (a vertex is large).
    std::optional<PathVertex> sampled;
    if (s == 0) {
        // The camera subpath alone, ending on an emitter.
        const PathVertex& pt = camera_vertices[t - 1];
        if (pt.is_light()) L = pt.Le(ctx, camera_vertices[t - 2]) * pt.beta;
    } else if (t == 1) {
        // The light subpath's end seen through a point sampled on the lens.
        const PathVertex& qs = light_vertices[s - 1];
        if (qs.is_connectible()) {
            Vec2 u = sampler.get_2d();
            auto cs = qs.kind == VertexKind::Surface || qs.kind == VertexKind::Medium
                          ? ctx.camera.sample_wi(qs.p(), u, qs.si.time)
                          : std::nullopt;
            if (cs) {
                c.splat = true;
                c.p_raster = cs->p_raster;
                sampled =
                    PathVertex::camera(cs->p_lens, cs->n_lens, RGB(cs->We / cs->pdf_solid_angle));
                sampled->si.time = qs.si.time;
                L = qs.beta * qs.f(*sampled, TransportMode::Importance) * sampled->beta *
                    qs.cos_towards(cs->wi);
                if (!L.is_black()) L *= transmittance_between(ctx, qs, *sampled, sampler);
            }
        }
    } else if (s == 1) {
        // A point sampled on a light, seen from the camera subpath's end.
        const PathVertex& pt = camera_vertices[t - 1];
        if (pt.is_connectible()) {
            float u_select = sampler.get_1d();
            Vec2 u = sampler.get_2d();
            auto sl = ctx.light_sampler.sample(u_select);
            if (sl && sl->pmf > 0) {
                auto ls = sl->light->sample_li(LightSampleContext{pt.p(), pt.ng(), pt.ns()}, u);
                if (ls && !ls->L.is_black() && ls->pdf_solid_angle > 0) {
                    sampled = PathVertex::light_endpoint(sl->light, ls->p_light, ls->n_light,
                                                         ls->L / (ls->pdf_solid_angle * sl->pmf), 0,
                                                         ls->p_error, ls->prim);
                    sampled->si.time = pt.si.time;
                    sampled->si.uv = ls->uv;
                    sampled->pdf_fwd = sampled->pdf_light_origin(ctx, pt);
                    L = pt.beta * pt.f(*sampled, TransportMode::Radiance) * sampled->beta *
                        pt.cos_towards(ls->wi);
                    if (!L.is_black()) L *= transmittance_between(ctx, pt, *sampled, sampler);
                }
            }
        }
    } else {
        // Both subpaths' ends joined by a deterministic segment.
        const PathVertex& qs = light_vertices[s - 1];
        const PathVertex& pt = camera_vertices[t - 1];
        if (qs.is_connectible() && pt.is_connectible()) {
            L = qs.beta * qs.f(pt, TransportMode::Importance) * pt.f(qs, TransportMode::Radiance) *
                pt.beta;
            if (!L.is_black()) L *= geometry(ctx, qs, pt, sampler);
        }
    }
    if (L.is_black() || !L.is_finite()) return c;
    if (sampled_out && sampled) *sampled_out = *sampled;
    c.mis_weight = mis_weight(ctx, light_vertices, camera_vertices,
                              sampled ? *sampled : camera_vertices[0], s, t);
    c.L = L * c.mis_weight;
    return c;
}

}  // namespace ml
