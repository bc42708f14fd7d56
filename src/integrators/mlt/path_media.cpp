#include "integrators/mlt/path_media.h"

#include "transport/volume_path.h"

namespace ml {

namespace {

// The edge from a to b: through interfaces, each stretch in its medium.
std::optional<MediaEdge> trace_edge(const BdptScene& ctx, const PathVertex& a, const PathVertex& b,
                                    Sampler& sampler) {
    const Vec3 d = b.p() - a.p();
    if (length_squared(d) == 0) return std::nullopt;
    MediaEdge e;
    const bool reached = walk_segment(
        ctx.scene, a.p(), a.offset(), b.p(), b.offset(), a.medium_towards(ctx, normalize(d)),
        a.si.time, [&](const Medium& m, const UnitRay& u, bool first, bool last) {
            e.tr *= medium_transmittance(m, u.ray, u.tmax, sampler);
            e.tmaj *= majorant_transmittance(m, u.ray, u.tmax);
            if (first) e.maj_a = majorant_at(m, u.ray, 0, u.tmax);
            if (last) e.maj_b = majorant_at(m, u.ray, u.tmax, u.tmax);
            return true;
        });
    if (!reached) return std::nullopt;
    return e;
}

}  // namespace

bool trace_media_edges(const BdptScene& ctx, MltPath& y, const MltPath* reuse, Sampler& sampler) {
    y.edges.clear();
    if (!ctx.scene.has_media()) return true;
    const size_t n = y.v.size();
    y.edges.resize(n - 1);
    if (reuse && reuse->edges.size() + 1 != reuse->v.size()) reuse = nullptr;
    for (size_t k = 0; k + 1 < n; ++k) {
        const Vec3 &a = y.v[k].p(), &b = y.v[k + 1].p();
        bool kept = false;
        if (reuse) {
            for (size_t j = 0; j + 1 < reuse->v.size() && !kept; ++j) {
                if (reuse->v[j].p() == a && reuse->v[j + 1].p() == b) {
                    y.edges[k] = reuse->edges[j];
                    kept = true;
                }
            }
        }
        if (kept) continue;
        const std::optional<MediaEdge> e = trace_edge(ctx, y.v[k], y.v[k + 1], sampler);
        if (!e) return false;
        y.edges[k] = *e;
    }
    return true;
}

RGB media_colour(const MltPath& x) {
    RGB c(1.f);
    for (const MediaEdge& e : x.edges) c *= e.tr;
    if (x.edges.empty()) return c;
    for (const PathVertex& v : x.v)
        if (v.kind == VertexKind::Medium) c *= v.medium->at(v.p()).sigma_s;
    return c;
}

float media_density(const MltPath& x, int e, int to) {
    if (x.edges.empty()) return 1;
    const MediaEdge& edge = x.edges[size_t(e)];
    float p = edge.tmaj;
    if (x.v[size_t(to)].kind == VertexKind::Medium) p *= to == e ? edge.maj_a : edge.maj_b;
    return p;
}

}  // namespace ml
