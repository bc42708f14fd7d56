#include "integrators/mlt/coherent.h"

#include "materials/material.h"
#include "transport/direct_lighting.h"

namespace ml {

namespace {

constexpr int kTries = kCoherentTries;
static_assert(kTries == 4 || kTries == 8, "tries are traced as packets of four or eight rays");

float importance_of(const RGB& c) {
    float y = c.luminance();
    return std::isfinite(y) && y > 0 ? y : 0.f;
}

void intersect_packet(const Scene& scene, const Ray* rays, const bool* active,
                      SurfaceInteraction* si, bool* hit) {
    if constexpr (kTries == 4)
        scene.intersect4(rays, active, si, hit);
    else
        scene.intersect8(rays, active, si, hit);
}

void occluded_packet(const Scene& scene, const Ray* rays, const bool* active, bool* occluded) {
    if constexpr (kTries == 4)
        scene.occluded4(rays, active, occluded);
    else
        scene.occluded8(rays, active, occluded);
}

bool any(const bool* active) {
    for (int i = 0; i < kTries; ++i)
        if (active[i]) return true;
    return false;
}

// The tries' paths: per thread, so that their vectors keep their capacity from step to step.
struct Tries {
    MltPath y[kTries];
    RGB target[kTries];  // lens_target, black for tries that failed
};

Tries& thread_tries(int set) {
    thread_local Tries tries[2];
    return tries[set];
}

// `count` perturbations of `from` (offsets from the numbers `u`), traced as packets: the camera
// rays, then each bounce of the specular chains to vertex j, then the rays joining the new
// vertices j to the kept vertex j + 1. Fills out.y[i] and out.target[i] for i < count.
void trace_tries(const BdptScene& ctx, const MltPath& from, int j, const Vec2* u, int count,
                 Tries& out, ScratchBuffer& scratch) {
    const PerspectiveCamera& cam = ctx.camera;
    Ray rays[kTries];
    bool active[kTries] = {}, hit[kTries] = {}, blocked[kTries] = {};
    SurfaceInteraction si[kTries];

    // 1. Camera rays through the offset film positions, from the same lens point.
    for (int i = 0; i < count; ++i) {
        MltPath& y = out.y[i];
        out.target[i] = RGB();
        y.v.assign(from.v.begin(), from.v.end());
        y.u_lens = from.u_lens;
        y.p_raster = from.p_raster + lens_offset(cam, u[i].x, u[i].y);
        const Vec2& p = y.p_raster;
        active[i] = cam.in_raster(p);
        if (active[i]) rays[i] = cam.generate_ray({p, from.u_lens, from.u_time});
    }

    // 2. The specular chains with the lobes of `from`, one packet per bounce, to vertex j.
    for (int k = 1; k <= j && any(active); ++k) {
        intersect_packet(ctx.scene, rays, active, si, hit);
        for (int i = 0; i < count; ++i) {
            if (!active[i]) continue;
            active[i] = false;
            if (!hit[i]) continue;
            PathVertex& v = out.y[i].v[size_t(k)];
            v = PathVertex();
            v.kind = VertexKind::Surface;
            v.si = si[i];
            v.ns_hit = v.si.ns;
            v.bsdf = hit_bsdf(v.si, scratch);
            if (!v.bsdf || v.bsdf.is_specular_only() != (k < j)) continue;
            if (k < j) {
                auto wi = specular_direction(v, -rays[i].d, transmits(from, k));
                if (!wi) continue;
                rays[i] = spawn_ray(v.si, *wi);
            }
            active[i] = true;
        }
    }

    // 3. The new vertices j joined to the kept j + 1 (as mutually_visible does it).
    for (int i = 0; i < count; ++i) {
        if (!active[i]) continue;
        const PathVertex &a = out.y[i].v[size_t(j)], &b = out.y[i].v[size_t(j + 1)];
        if (!a.is_connectible()) {
            active[i] = false;
            continue;
        }
        rays[i] = segment_ray(a.p(), a.offset(), b.p(), b.offset(), a.si.time);
    }
    if (any(active)) occluded_packet(ctx.scene, rays, active, blocked);

    // 4. The targets of the tries that got through.
    for (int i = 0; i < count; ++i)
        if (active[i] && !blocked[i]) out.target[i] = lens_target(ctx, out.y[i], j);
}

}  // namespace

std::optional<Proposal> mutate_lens_multiple_try(const BdptScene& ctx, const MltPath& x,
                                                 Sampler& sampler, ScratchBuffer& scratch) {
    Vec2 u[2 * kTries - 1];
    for (Vec2& v : u) v = sampler.get_2d();
    float u_pick = sampler.get_1d();
    int j = lens_vertex(x);
    if (j < 0) return std::nullopt;

    // 1. The tries from x and their weights pi(y_i) (T(y_i -> x) > 0: the offsets are
    //    symmetric).
    Tries& ys = thread_tries(0);
    trace_tries(ctx, x, j, u, kTries, ys, scratch);
    double w[kTries], sum_y = 0;
    for (int i = 0; i < kTries; ++i) sum_y += w[i] = importance_of(ys.target[i]);
    if (!(sum_y > 0)) return std::nullopt;

    // 2. Expected values: try i as a Metropolis proposal from x, accepted with
    //    a_i = min(1, pi(y_i) / pi(x)), splatted with a_i / k; x keeps the rest.
    Proposal prop;
    const float pi_x = importance_of(lens_target(ctx, x, j));
    for (int i = 0; i < kTries; ++i) {
        if (w[i] == 0) continue;
        float pi_y = float(w[i]);
        // colour(y_i) a_i / k = target / (pi_y k) * min(1, pi_y / pi_x)
        prop.tries[size_t(prop.n_tries++)] =
            TrySplat{ys.y[i].p_raster, ys.target[i] / (float(kTries) * std::max(pi_x, pi_y))};
        prop.tries_share += (pi_x > 0 ? std::min(1.f, pi_y / pi_x) : 1.f) / float(kTries);
    }

    // 3. y picked in proportion to the weights; reference tries from y, and x itself.
    int pick = 0;
    for (double acc = 0; pick < kTries - 1; ++pick) {
        acc += w[pick];
        if (u_pick * sum_y < acc) break;
    }
    while (w[pick] == 0) --pick;
    Tries& xs = thread_tries(1);
    trace_tries(ctx, ys.y[pick], j, u + kTries, kTries - 1, xs, scratch);
    double sum_x = pi_x;
    for (int i = 0; i < kTries - 1; ++i) sum_x += importance_of(xs.target[i]);

    // 4. The chain moves to y with min(1, sum of the tries' weights / sum of the references').
    prop.accept = sum_x > 0 ? float(std::min(1.0, sum_y / sum_x)) : 1.f;
    prop.colour = ys.target[pick] / float(w[pick]);
    prop.y = ys.y[pick];
    rebind_bsdfs(prop.y, scratch);
    return prop;
}

}  // namespace ml
