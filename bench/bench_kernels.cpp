// Micro-benchmarks of the kernels the integrators stand on: ray queries against a tessellated
// sphere-in-a-box scene, BSDF sampling, sampler throughput.
#include <benchmark/benchmark.h>

#include "core/rng.h"
#include "geometry/embree_scene.h"
#include "sampling/sampler.h"

using namespace ml;

namespace {

TriangleMesh make_sphere(int n_theta, int n_phi, float r) {
    TriangleMesh m;
    for (int i = 0; i <= n_theta; ++i)
        for (int j = 0; j <= n_phi; ++j) {
            float th = kPi * i / n_theta, ph = 2 * kPi * j / n_phi;
            m.p.push_back(Vec3(r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph),
                               r * std::cos(th)));
        }
    for (int i = 0; i < n_theta; ++i)
        for (int j = 0; j < n_phi; ++j) {
            uint32_t a = i * (n_phi + 1) + j, b = a + 1, c = a + n_phi + 1, d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    return m;
}

void BM_RayIntersect(benchmark::State& state) {
    TriangleMesh mesh = make_sphere(int(state.range(0)), 2 * int(state.range(0)), 1.f);
    EmbreeScene scene({&mesh});
    Rng rng(1);
    SurfaceInteraction si;
    for (auto _ : state) {
        Vec3 d = normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 1.f));
        benchmark::DoNotOptimize(scene.intersect(Ray{Vec3(0, 0, -3), d}, &si));
    }
    state.SetItemsProcessed(state.iterations());
    state.counters["triangles"] = double(mesh.triangle_count());
}
BENCHMARK(BM_RayIntersect)->Arg(16)->Arg(256)->Arg(1024);

void BM_RayOccluded(benchmark::State& state) {
    TriangleMesh mesh = make_sphere(256, 512, 1.f);
    EmbreeScene scene({&mesh});
    Rng rng(1);
    for (auto _ : state) {
        Vec3 d = normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 1.f));
        benchmark::DoNotOptimize(scene.occluded(Ray{Vec3(0, 0, -3), d, 10.f}));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RayOccluded);

void BM_Sampler(benchmark::State& state, const char* name) {
    auto sampler = create_sampler(name, 64, 0);
    int i = 0;
    float acc = 0;
    for (auto _ : state) {
        sampler->start_pixel_sample({i & 255, (i >> 8) & 255}, i % 64);
        for (int d = 0; d < 8; ++d) acc += sampler->get_2d().x;
        ++i;
    }
    benchmark::DoNotOptimize(acc);
    state.SetItemsProcessed(state.iterations() * 8);
}
BENCHMARK_CAPTURE(BM_Sampler, independent, "independent");
BENCHMARK_CAPTURE(BM_Sampler, sobol, "sobol");

}  // namespace

BENCHMARK_MAIN();
