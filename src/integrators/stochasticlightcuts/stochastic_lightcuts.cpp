#include "integrators/stochasticlightcuts/stochastic_lightcuts.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/stats.h"
#include "manylight/bounds.h"
#include "manylight/cluster_sampling.h"

namespace ml {

StochasticLightcutsIntegrator::StochasticLightcutsIntegrator(const Settings& settings)
    : m_settings(ManyLightSettings::read(settings)) {
    read_vpl_sets(settings, &m_settings);
    m_cut = settings.get_int("cut", m_cut,
                             {">= 1",
                              "Clusters and single lights per cut; one light is drawn from each "
                              "cluster in proportion to its importance."});
    if (m_cut < 1) throw UsageError("stochasticlightcuts.cut must be >= 1");
}

void StochasticLightcutsIntegrator::prepare(const Scene& scene) {
    build_many_lights(scene, m_settings, &m_set, &m_direct);
    m_tree = build_light_tree(scene, m_settings, m_set, &m_tree_seconds);
    m_sampler = ClusterSampler(m_tree, m_set.lights);
}

RenderResult StochasticLightcutsIntegrator::render(const RenderContext& ctx) {
    m_settings.use_render_seed(ctx.seed);
    m_settings.use_scene(ctx.scene);
    m_settings.lights.camera = &ctx.camera;
    m_settings.use_time_limit(ctx, true);
    m_cut_sum = 0;
    m_gather_points = 0;
    RenderResult r = PixelIntegrator::render(ctx);
    r.point_lights = m_set.lights.size();
    r.vpls = m_set.vpls;
    if (std::string w = vpl_budget_warning(m_set); !w.empty()) r.warnings.push_back(w);
    uint64_t n = m_gather_points.load();
    double pixels = double(ctx.film.width()) * ctx.film.height() * std::max(1, r.spp);
    nlohmann::json& s = r.stats["stochasticlightcuts"];
    s = {{"cut", m_cut},
         {"avg_cut_size", n ? double(m_cut_sum.load()) / double(n) : 0.0},
         {"gather_points", n},
         {"shadow_rays_per_pixel", double(stats::total().shadow) / pixels},
         {"tree_build_seconds", m_tree_seconds}};
    s.update(many_light_figures(m_set, m_direct));
    return r;
}

RGB StochasticLightcutsIntegrator::li(const Ray& ray, const Scene& scene, Sampler& sampler,
                                      ScratchBuffer& scratch, Point2i) const {
    return gather_along(scene, ray, sampler, scratch, m_settings.gather(),
                        [&](const GatherPoint& g, float) {
                            int cut_size = 0;
                            RGB L = m_direct.estimate(scene, g, sampler);
                            L += shade(scene, g, sampler, &cut_size);
                            m_cut_sum.fetch_add(uint64_t(cut_size), std::memory_order_relaxed);
                            m_gather_points.fetch_add(1, std::memory_order_relaxed);
                            return L;
                        });
}

RGB StochasticLightcutsIntegrator::shade(const Scene& scene, const GatherPoint& g, Sampler& sampler,
                                         int* cut_size) const {
    const Vec3& x = g.si.p;
    const Vec3& wo = g.si.wo;
    struct Entry {
        int32_t node;
        float bound;  // luminance of the node's error bound at g (infinite: x in its box)
        bool operator<(const Entry& o) const { return bound < o.bound; }
    };
    thread_local std::vector<Entry> heap;
    thread_local std::vector<int32_t> singles;  // leaves of the cut: shaded exactly
    heap.clear();
    singles.clear();
    // Lightcuts' cheap bound (the BSDF's bound over every direction): only the order of the
    // splits depends on it, and whether a node can give light at all (zero: left out).
    const RGB m_all = g.bsdf.max_value_bound(wo, DirectionCone::entire_sphere());
    // A point in a medium scatters every way: no receiver cosine (a zero normal).
    const ClusterView view{x, g.in_medium ? Vec3() : face_forward(g.bsdf.frame().n, wo),
                           (g.bsdf.flags() & kBxdfTransmission) != 0};
    auto add = [&](int32_t index) {
        RGB b = g.beta * loose_node_bound(m_tree.ref(index), x, m_all);
        if (b.is_black()) return;  // none of its lights can reach x through this BSDF
        // Nor can they where the descent's importance is zero (spot lights aimed away: the
        // bound above counts them as emitting every way). Left out, they take no place in the
        // cut.
        if (!(m_sampler.importance(index, view) > 0)) return;
        if (m_tree.node(index).is_leaf()) {
            singles.push_back(m_tree.light(index));
            return;
        }
        float l = b.luminance();
        heap.push_back({index, std::isnan(l) || l == 0 ? kInfinity : l});
        std::push_heap(heap.begin(), heap.end());
    };
    for (PointLightKind kind : kAllPointLightKinds)
        if (m_tree.root(kind) >= 0) add(m_tree.root(kind));
    // Split the cluster of largest bound until the cut holds m_cut clusters and lights.
    while (!heap.empty() && int(heap.size() + singles.size()) < m_cut) {
        std::pop_heap(heap.begin(), heap.end());
        int32_t index = heap.back().node;
        heap.pop_back();
        const LightTreeNode& n = m_tree.node(index);
        add(n.children()[0]);
        add(n.children()[1]);
    }
    *cut_size = int(heap.size() + singles.size());
    auto value = [&](int32_t light) {
        return visible_point_light(scene, m_set, m_settings, m_set.lights[size_t(light)], g);
    };
    RGB L;
    for (int32_t light : singles) L += value(light);
    if (heap.empty()) return L;
    // One light per cluster, drawn by importance (the heap's order depends on g alone).
    for (const Entry& e : heap) {
        ClusterSample s = m_sampler.sample(e.node, view, sampler.get_1d());
        if (s.light >= 0 && s.pmf > 0) L += value(s.light) / s.pmf;
    }
    return L;
}

}  // namespace ml
