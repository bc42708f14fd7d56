// Light tree build time (PLOC, manylight/light_tree.h) for 1k .. 1M random lights of each kind.
// Goal: 1M lights in under 2 s on 2 cores.
//   ./manylight_bench --benchmark_filter=LightTree
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "manylight/light_tree.h"

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

}  // namespace

BENCHMARK(BM_LightTreeBuild)
    ->ArgsProduct({{1000, 10000, 100000, 1000000}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
