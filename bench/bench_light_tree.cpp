// Light tree build time (PLOC, manylight/light_tree.h) for 1k .. 1M random lights of each kind.
// Goal: 1M lights in under 2 s on 2 cores.
//   ./manylight_bench --benchmark_filter=LightTree
// And the cut loop's cost per refined node (BM_LightcutRefine), what issue 13 item 7 measures.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/rng.h"
#include "manylight/bounds.h"
#include "manylight/gather.h"
#include "manylight/light_tree.h"
#include "manylight/pilot.h"
#include "manylight/representative.h"
#include "materials/bxdfs.h"

using namespace ml;

namespace {

std::vector<PointLight> bench_lights(size_t n, int kind) {
    Rng rng(n);
    std::vector<PointLight> lights(n);
    for (PointLight& pl : lights) {
        pl.p = Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 10;
        float z = 1 - 2 * rng.next_float(), phi = 2 * kPi * rng.next_float();
        float r = std::sqrt(std::max(0.f, 1 - z * z));
        pl.n = Vec3(r * std::cos(phi), r * std::sin(phi), z);
        pl.intensity = RGB(rng.next_float(), rng.next_float(), rng.next_float());
        pl.kind = kind < 3 ? PointLightKind(kind) : PointLightKind(rng.next_u32() % 3);
    }
    return lights;
}

// range(0): light count; range(1): 0 omni, 1 oriented, 2 directional, 3 mixed.
void BM_LightTreeBuild(benchmark::State& state) {
    std::vector<PointLight> lights = bench_lights(size_t(state.range(0)), int(state.range(1)));
    for (auto _ : state) {
        LightTree tree(lights);
        benchmark::DoNotOptimize(tree.node_count());
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
}

// The lightcuts cut loop (LightcutsIntegrator::shade's steps, without shadow rays: every light
// counts as visible) at gather points drawn uniformly in the lights' box, each with a random
// normal, a grey Lambertian BSDF and wo along the normal: Walter's max criterion at 2%, lazy
// tight bounds, a child whose representative is its parent's reusing its value. What it costs
// is the nodes' and representatives' memory traffic plus the bounds' arithmetic, per refined
// (split) node: the "ns_per_refined" counter. range(0): light count (oriented, as VPLs are).
void BM_LightcutRefine(benchmark::State& state) {
    PointLightSet set;
    set.lights = bench_lights(size_t(state.range(0)), 1);
    LightTree tree(set.lights);
    DiffuseBxdf bxdf(RGB(0.5f));
    Rng rng(7);
    struct Entry {
        int32_t node, rep;
        float bound;
        RGB estimate, rep_value;
        bool tight;
        bool operator<(const Entry& o) const { return bound < o.bound; }
    };
    std::vector<Entry> heap;
    int64_t refined = 0, cut_nodes = 0;
    for (auto _ : state) {
        GatherPoint g;
        g.si.p = Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 10;
        float z = 1 - 2 * rng.next_float(), phi = 2 * kPi * rng.next_float();
        float r = std::sqrt(std::max(0.f, 1 - z * z));
        g.si.ng = g.si.ns = g.si.wo = Vec3(r * std::cos(phi), r * std::sin(phi), z);
        g.bsdf = Bsdf(Frame::from_z(g.si.ns), g.si.ng, &bxdf);
        g.beta = RGB(1.f);
        int k = int(rng.next_u32() % kLightTreeReps);
        const RGB m_all = g.bsdf.max_value_bound(g.si.wo, DirectionCone::entire_sphere());
        auto value = [&](int32_t light) {
            RGB v;
            Ray shadow;
            point_light_contribution(set, set.lights[size_t(light)], g, &v, &shadow);
            return v;
        };
        auto make_entry = [&](int32_t index, int32_t rep, const RGB& rep_value) {
            Entry e{index, rep, 0.f, rep_value, rep_value, true};
            if (tree.node(index).is_leaf()) return e;
            e.estimate = rep_value *
                         representative_scale(tree.weight(index),
                                              selection_weight(set.lights[size_t(rep)].intensity));
            RGB b = loose_node_bound(tree.ref(index), g.si.p, m_all);
            for (int c = 0; c < 3; ++c) b[c] = std::max(b[c], e.estimate[c]);
            e.bound = std::isnan(b.luminance()) ? kInfinity : b.luminance();
            e.tight = e.bound == 0;
            return e;
        };
        heap.clear();
        RGB total;
        int32_t root = tree.root(PointLightKind::Oriented);
        heap.push_back(make_entry(root, tree.rep(root, k), value(tree.rep(root, k))));
        total += heap.back().estimate;
        while (int(heap.size()) < 1000 && heap.front().bound > cut_tolerance(0.02f, total, 0)) {
            std::pop_heap(heap.begin(), heap.end());
            Entry e = heap.back();
            heap.pop_back();
            if (!e.tight) {
                RGB b = node_error_bound(tree.ref(e.node), g.si.p, g.bsdf, g.si.wo);
                for (int c = 0; c < 3; ++c) b[c] = std::max(b[c], e.estimate[c]);
                float l = std::isnan(b.luminance()) ? kInfinity : b.luminance();
                e.bound = std::min(e.bound, l);
                e.tight = true;
                heap.push_back(e);
                std::push_heap(heap.begin(), heap.end());
                continue;
            }
            total = total - e.estimate;
            ++refined;
            for (int32_t child : tree.node(e.node).children()) {
                int32_t rep = tree.rep(child, k);
                Entry c = make_entry(child, rep, rep == e.rep ? e.rep_value : value(rep));
                total += c.estimate;
                heap.push_back(c);
                std::push_heap(heap.begin(), heap.end());
            }
        }
        cut_nodes += int64_t(heap.size());
        benchmark::DoNotOptimize(total);
    }
    state.counters["ns_per_refined"] = benchmark::Counter(
        double(refined) * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["cut"] = double(cut_nodes) / double(state.iterations());
}

}  // namespace

BENCHMARK(BM_LightTreeBuild)
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_LightcutRefine)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMicrosecond);
