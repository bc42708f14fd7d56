// Metropolis instant radiosity (MIR, Segovia, Iehl and Péroche 2007; Segovia's thesis), with
// multiple-try Metropolis (MTMH).
//   1. A Metropolis-Hastings chain over complete paths x0 x1 xv xs in primary sample space: the
//      camera's part (x0 x1: a film position and the delta chain to the first non-delta hit)
//      and the light's part (a standard light path xs and the choice of one of its VPLs, xv).
//      The target is f = the luminance that VPL xv gives x1 (visibility included) times the
//      number of VPLs on the light path (the choice's probability), so the chain visits paths in
//      proportion to what they bring the camera.
//   2. Mutations: a large step (every coordinate afresh), or a small step of the camera's part
//      alone or of the light's part alone (a normal perturbation of each coordinate). With K
//      tries, K proposals are made and one kept in proportion to f, then accepted against K - 1
//      proposals made back from it and the current state (Liu, Liang and Wong 2000); the
//      proposals are symmetric, so the weights are f.
//   3. Every step's state is a path VPL (xv, xs). A step that keeps the light's part (a rejection
//      or an accepted camera mutation) adds to the current geometric VPL's multiplicity k_i;
//      others start a new geometric VPL.
//   4. Normalisation: P_c, the power the VPLs bring to the camera (here the image mean of f's
//      light), is estimated by the mean of f over independent paths (the chain's bootstrap: the
//      same integral the chain samples); geometric VPL i must bring P_i = k_i P_c / n (n: the
//      steps). Its power at the light path's flux, P'_i, is measured on vpl.metropolis.pilot
//      (4096) camera points stratified over the film (a unit-power render over a sample of the
//      image, where the seed renders the whole image: 256 points left a VPL that lights a small
//      part of the image with a noisy, sometimes tiny P'_i and so a huge scale); its flux is
//      scaled by P_i / P'_i.
//   5. Several chains (vpl.metropolis.chains, 16): the n steps are shared by independent chains,
//      each started from a bootstrap path drawn in proportion to f, each on its own random
//      stream (so they run in parallel, the same VPLs at any thread count); every chain's
//      geometric VPLs are normalised as one chain's, by k_i P_c / n with n all the steps. One
//      chain kept its light side for long runs on scenes lit through a gap (veach-ajar: about
//      95% of independent paths bring nothing, so large steps are almost never accepted).
//   6. A bounded target (vpl.metropolis.cap, 1): f's VPL luminance at x1 is bounded by cap P_c,
//      so the chain does not stay on the 1/r^2 spikes of VPLs next to x1 (half of veach-ajar's
//      P_c lies above that bound). Any target that is positive where f is gives a consistent
//      image as long as P_c and P'_i measure the same target: both are bounded alike.

#include <algorithm>
#include <cmath>
#include <limits>

#include "camera/camera.h"
#include "core/assert.h"
#include "core/parallel.h"
#include "core/rng.h"
#include "manylight/gather.h"
#include "manylight/point_light_set.h"
#include "manylight/vpl_sampler.h"
#include "sampling/distributions.h"
#include "sampling/mlt_sampler.h"
#include "scene/scene.h"

namespace ml {
namespace {

constexpr int kCameraDims = 32;     // film 2, lens 2, time 1, the delta chain's samples
constexpr float kSigma = 1.f / 32;  // small steps: normal perturbation of each coordinate

// Reads a fixed vector of primary samples in order (past its end: 0.5).
class VectorSampler final : public Sampler {
public:
    VectorSampler(const std::vector<float>& u, size_t begin, size_t end)
        : m_u(&u), m_begin(begin), m_end(end), m_i(begin) {}
    int samples_per_pixel() const override { return 1; }
    void start_pixel_sample(Point2i, int, int dimension) override { m_i = m_begin + dimension; }
    float get_1d() override { return m_i < m_end ? (*m_u)[m_i++] : 0.5f; }
    Vec2 get_2d() override {
        float a = get_1d();
        return {a, get_1d()};
    }
    std::unique_ptr<Sampler> clone() const override {
        return std::make_unique<VectorSampler>(*this);
    }
    std::string name() const override { return "vector"; }

private:
    const std::vector<float>* m_u;
    size_t m_begin, m_end, m_i;
};

enum class Mutation { Large, Camera, Light };

class MirChain {
public:
    MirChain(const Scene& scene, const PerspectiveCamera& camera, const VplOptions& options)
        : m_scene(scene),
          m_camera(camera),
          m_options(options),
          m_tracer(scene, clean(options)),
          m_dims(size_t(kCameraDims) + 1 + 5 + 4 * size_t(4 * options.max_depth + 16)) {}

    size_t dims() const { return m_dims; }
    // The target's bound on one VPL's luminance at x1 (infinite: f itself).
    void set_cap(float cap) { m_cap = cap; }
    size_t light_begin() const { return size_t(kCameraDims); }

    // f of the path u (and its chosen VPL's index on the light path, and the path's VPLs).
    float evaluate(const std::vector<float>& u, int* vpl_index = nullptr,
                   float* path_vpls = nullptr) {
        m_scratch.reset();
        VectorSampler cs(u, 0, kCameraDims);
        CameraSample c;
        Vec2 film = cs.get_2d();
        c.p_film = Vec2(film.x * float(m_camera.width()), film.y * float(m_camera.height()));
        c.p_lens = cs.get_2d();
        c.time = cs.get_1d();
        float camera_weight;
        Ray ray = m_camera.generate_ray(c, &camera_weight);
        if (camera_weight == 0) return 0;  // stopped by the realistic camera's lens
        RGB L, beta(camera_weight);
        GatherPoint g;
        bool found = false;
        for (int depth = 0; depth <= 8; ++depth) {
            if (!detail::next_gather_hit(m_scene, ray, m_scratch, beta, &L, &g)) break;
            g.beta = beta;
            if (g.bsdf.has_nonspecular()) {
                found = true;
                break;
            }
            if (!detail::continue_through_delta(g, cs, &beta, &ray)) break;
        }
        if (!found) return 0;
        clear(m_chunk);
        VectorSampler ls(u, light_begin() + 1, m_dims);
        m_tracer.trace_path(ls, m_light_scratch, m_chunk);
        m_light_scratch.reset();
        size_t n = m_chunk.lights.size();
        if (n == 0) return 0;
        size_t k = std::min(size_t(u[light_begin()] * float(n)), n - 1);
        if (vpl_index) *vpl_index = int(k);
        m_view.surfaces = m_chunk.surfaces;
        RGB value;
        Ray shadow;
        if (!point_light_contribution(m_view, m_chunk.lights[k], g, &value, &shadow)) return 0;
        if (path_vpls) *path_vpls = float(n);
        float y = std::min(value.luminance(), m_cap) * float(n);
        if (!(y > 0) || !std::isfinite(y) || m_scene.occluded(shadow)) return 0;
        return y;
    }

    // Appends the chosen VPL of path u to out (tracing its light path again).
    void keep_vpl(const std::vector<float>& u, VplChunk& out) {
        size_t before = out.lights.size();
        VectorSampler ls(u, light_begin() + 1, m_dims);
        m_tracer.trace_path(ls, m_light_scratch, out);
        m_light_scratch.reset();
        size_t n = out.lights.size() - before;
        ML_ASSERT(n > 0, "a kept MIR path has VPLs");
        size_t k = std::min(size_t(u[light_begin()] * float(n)), n - 1);
        PointLight pl = out.lights[before + k];
        out.lights.resize(before);
        out.lights.push_back(pl);
    }

private:
    static VplOptions clean(VplOptions o) {
        o.light_pmf.clear();
        o.after_specular_only = false;
        return o;
    }
    static void clear(VplChunk& c) {
        c.lights.clear();
        c.surfaces.clear();
        c.path_end.clear();
        c.path_light.clear();
        if (c.arena) c.arena->reset();
    }

    const Scene& m_scene;
    const PerspectiveCamera& m_camera;
    const VplOptions& m_options;
    VplTracer m_tracer;
    size_t m_dims;
    float m_cap = std::numeric_limits<float>::infinity();
    ScratchBuffer m_scratch, m_light_scratch;
    VplChunk m_chunk;
    PointLightSet m_view;  // m_chunk's surfaces, for point_light_contribution
};

// Random numbers for the chain's own choices: an independent sampler, one pixel per step.
class ChainRandom {
public:
    explicit ChainRandom(uint64_t seed) : m_sampler(create_sampler("independent", 1, seed)) {}
    void start(int64_t step) {
        m_sampler->start_pixel_sample({int(step & 0xfffff), int(step >> 20)}, 0);
    }
    float uniform() { return m_sampler->get_1d(); }

private:
    std::unique_ptr<Sampler> m_sampler;
};

void mutate(const std::vector<float>& x, Mutation m, size_t light_begin, ChainRandom& rng,
            std::vector<float>* y) {
    *y = x;
    for (size_t i = 0; i < x.size(); ++i) {
        bool light = i >= light_begin;
        if (m == Mutation::Large) {
            (*y)[i] = rng.uniform();
        } else if ((m == Mutation::Light) == light) {
            float v = x[i] + kSigma * float(standard_normal_quantile(double(rng.uniform())));
            v -= std::floor(v);
            (*y)[i] = std::min(v, 0x1.fffffep-1f);
        }
    }
}

// One chain's run: `steps` steps from x, its path VPLs clustered into geometric VPLs (out, with
// their multiplicities), its acceptance counts in stats.
struct ChainRun {
    VplChunk out;
    std::vector<double> multiplicity;
    MirTrace stats;
};

void run_chain(MirChain& chain, std::vector<float> x, int64_t steps, const VplOptions& options,
               ChainRandom& rng, bool record, ChainRun* run) {
    const size_t LB = chain.light_begin();
    const int K = std::max(1, options.sampler.tries);
    const float large = options.sampler.mir_large_step;
    float fx = chain.evaluate(x);
    chain.keep_vpl(x, run->out);
    run->multiplicity.push_back(0);
    MirTrace& st = run->stats;
    std::vector<std::vector<float>> ys(static_cast<size_t>(K)), refs(static_cast<size_t>(K));
    std::vector<float> fy(static_cast<size_t>(K));
    for (int64_t step = 0; step < steps; ++step) {
        rng.start(step);
        float u = rng.uniform();
        Mutation m = u < large                     ? Mutation::Large
                     : u < large + (1 - large) / 2 ? Mutation::Camera
                                                   : Mutation::Light;
        double sum_y = 0;
        for (int j = 0; j < K; ++j) {
            mutate(x, m, LB, rng, &ys[size_t(j)]);
            fy[size_t(j)] = chain.evaluate(ys[size_t(j)]);
            sum_y += double(fy[size_t(j)]);
        }
        bool accepted = false;
        size_t s = 0;
        if (sum_y > 0) {
            double pick = double(rng.uniform()) * sum_y, cdf = 0;
            for (s = 0; s + 1 < size_t(K); ++s) {
                cdf += double(fy[s]);
                if (pick < cdf) break;
            }
            double sum_ref = double(fx);
            for (int j = 0; j + 1 < K; ++j) {
                mutate(ys[s], m, LB, rng, &refs[size_t(j)]);
                sum_ref += double(chain.evaluate(refs[size_t(j)]));
            }
            accepted = double(rng.uniform()) * sum_ref < sum_y;
        }
        st.proposed[int(m)] += 1;
        if (accepted) {
            st.accepted[int(m)] += 1;
            x = ys[s];
            fx = fy[s];
            if (m != Mutation::Camera) {
                chain.keep_vpl(x, run->out);
                run->multiplicity.push_back(0);
            }
        }
        run->multiplicity.back() += 1;
        if (record) {
            st.positions.push_back(run->out.lights.back().p);
            st.contributions.push_back(fx);
        }
    }
}

}  // namespace

void sample_metropolis_vpls(const Scene& scene, const PerspectiveCamera& camera,
                            const VplOptions& options, PointLightSet& set, MirTrace* trace) {
    if (options.count <= 0 || options.max_depth <= 0 || scene.lights().empty()) return;
    const int64_t n = options.count;
    const int C = int(std::min<int64_t>(std::max(1, options.sampler.mir_chains), n));
    MirChain boot(scene, camera, options);
    const size_t D = boot.dims();
    ChainRandom rng(hash_ints(options.seed, 0x6d6972ULL));

    // Bootstrap: P_c (the mean of f over independent paths) and each chain's start, drawn in
    // proportion to f among them.
    const int bootstrap = std::max(1024, options.count);
    std::vector<float> fs(static_cast<size_t>(bootstrap)), nv(fs.size(), 0.f);
    std::vector<float> x(D);
    for (int b = 0; b < bootstrap; ++b) {
        rng.start(-1 - int64_t(b));
        for (float& v : x) v = rng.uniform();
        fs[size_t(b)] = boot.evaluate(x, nullptr, &nv[size_t(b)]);
    }
    double Pc = 0;
    for (float f : fs) Pc += double(f);
    Pc /= double(bootstrap);
    const float cap_share = options.sampler.mir_cap;
    const float cap =
        cap_share > 0 ? float(cap_share * Pc) : std::numeric_limits<float>::infinity();
    if (cap_share > 0) {
        Pc = 0;
        for (size_t b = 0; b < fs.size(); ++b) {
            if (fs[b] > 0) fs[b] = std::min(fs[b] / nv[b], cap) * nv[b];
            Pc += double(fs[b]);
        }
        Pc /= double(bootstrap);
    }
    if (!(Pc > 0)) return;
    Distribution1D start_dist(fs);
    std::vector<size_t> starts(static_cast<size_t>(C));
    for (int c = 0; c < C; ++c) {
        rng.start(-1 - int64_t(bootstrap) - c);
        starts[size_t(c)] = start_dist.sample_discrete(rng.uniform());
    }

    // The chains, n steps in all (the first n mod C one longer), each on its own random stream:
    // the same VPLs at any thread count.
    std::vector<ChainRun> runs(static_cast<size_t>(C));
    parallel_for(0, C, [&](int c) {
        std::vector<float> start(D);
        ChainRandom start_rng(hash_ints(options.seed, 0x6d6972ULL));
        start_rng.start(-1 - int64_t(starts[size_t(c)]));
        for (float& v : start) v = start_rng.uniform();
        ChainRandom chain_rng(c == 0 ? hash_ints(options.seed, 0x6d6972ULL)
                                     : hash_ints(options.seed, 0x6d6972ULL, uint64_t(c)));
        MirChain chain(scene, camera, options);
        chain.set_cap(cap);
        int64_t steps = n / C + (c < n % C ? 1 : 0);
        run_chain(chain, std::move(start), steps, options, chain_rng, trace != nullptr,
                  &runs[size_t(c)]);
    });

    // Normalisation: P_i = k_i P_c / n against P'_i measured on the pilot points.
    PilotPoints pilot = camera_pilot_points(scene, camera, options.sampler.mir_pilot, 8,
                                            hash_ints(options.seed, 0x6d69722dULL));
    std::vector<std::pair<size_t, size_t>> index;  // (chain, geometric VPL)
    for (size_t c = 0; c < runs.size(); ++c)
        for (size_t i = 0; i < runs[c].out.lights.size(); ++i) index.emplace_back(c, i);
    std::vector<double> measured(index.size(), 0.0);
    std::vector<PointLightSet> views(runs.size());
    for (size_t c = 0; c < runs.size(); ++c) views[c].surfaces = runs[c].out.surfaces;
    parallel_for_chunks(size_t(0), index.size(), size_t(16), [&](size_t b, size_t e) {
        for (size_t j = b; j < e; ++j) {
            auto [c, i] = index[j];
            for (const GatherPoint& g : pilot.points) {
                RGB value;
                Ray shadow;
                if (!point_light_contribution(views[c], runs[c].out.lights[i], g, &value, &shadow))
                    continue;
                if (!scene.occluded(shadow))
                    measured[j] += double(std::min(value.luminance(), cap));
            }
        }
    });
    double pilot_count = double(std::max(1, options.sampler.mir_pilot));
    VplChunk kept;
    kept.arena = std::move(runs[0].out.arena);
    double total = 0;
    for (size_t j = 0; j < index.size(); ++j) {
        auto [c, i] = index[j];
        double P_measured = measured[j] / pilot_count;
        double P_target = runs[c].multiplicity[i] * Pc / double(n);
        if (!(P_measured > 0)) continue;  // the pilot sees none of its light: left out
        if (!(P_target > 0)) continue;    // a chain's start, left at its first step
        float scale = float(P_target / P_measured);
        append_scaled_vpl(runs[c].out.lights[i], runs[c].out.surfaces, scale, kept.lights,
                          kept.surfaces);
        total += P_target;
    }
    if (trace) {
        trace->Pc = Pc;
        trace->kept_power = total;
        trace->steps = size_t(n);
        trace->bootstrap_nonzero =
            size_t(std::count_if(fs.begin(), fs.end(), [](float f) { return f > 0; }));
        std::vector<size_t> distinct = starts;
        std::sort(distinct.begin(), distinct.end());
        trace->distinct_starts =
            size_t(std::unique(distinct.begin(), distinct.end()) - distinct.begin());
        for (ChainRun& r : runs) {
            trace->geometric += r.out.lights.size();
            trace->runs.insert(trace->runs.end(), r.multiplicity.begin(), r.multiplicity.end());
            for (int m = 0; m < 3; ++m) {
                trace->proposed[m] += r.stats.proposed[m];
                trace->accepted[m] += r.stats.accepted[m];
            }
            trace->positions.insert(trace->positions.end(), r.stats.positions.begin(),
                                    r.stats.positions.end());
            trace->contributions.insert(trace->contributions.end(), r.stats.contributions.begin(),
                                        r.stats.contributions.end());
        }
    }
    std::vector<VplChunk> chunks;
    chunks.push_back(std::move(kept));
    size_t count = chunks[0].lights.size();
    append_vpls(chunks, count, 1.f, set);
}

}  // namespace ml
