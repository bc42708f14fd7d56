// Bidirectional instant radiosity (Segovia, Iehl, Mitanchey and Péroche 2006; Segovia's thesis):
// VPLs where the camera looks.
//   1. Pilot: points x1 the camera sees (first non-delta hit).
//   2. Candidates: from a pilot point chosen uniformly, a cosine-distributed direction gives the
//      VPL position x2 (camera sub-path x0 x1 x2). Its density over area is the mixture over all
//      pilot points, p(x2) = 1/P sum_j cos_j / pi |cos x2| / d_j^2 V(x1_j, x2): exact given the
//      pilot, so the estimator is unbiased wherever some pilot point sees x2 (and consistent: a
//      point seen from a fraction f of the image is missed with probability (1 - f)^P). In a
//      scene that moves, each candidate draws its time uniformly over the shutter, and its ray,
//      its density (the pilot points taken as fixed origins) and its connection are all traced
//      at that time, so that, as standard's light paths, each VPL is light at one time.
//   3. Connection back to the lights, one per candidate: a point on a light (light sampling,
//      probability kDirectShare), or a vertex of a standard light path (a VPL of a pool traced
//      with the whole BSDF at every vertex, one bounce shorter; in a scene that moves, a light
//      path of the candidate's own, traced at its time, and one of its vertices chosen
//      uniformly). The flux arriving at x2 divided by p(x2) is the candidate's flux; its depth
//      (vertices from the light) is one more than the vertex's.
//      How many candidates: enough that vpl.candidates of them per VPL bring light, on average
//      (a connection that fails costs two rays; the density, the costly part, is only computed
//      for those that succeed), from the share a first, dropped wave of them finds.
//   4. Resampling: `count` VPLs from the candidates in proportion to the square root of their
//      flux's luminance (systematic resampling; a kept candidate's flux is divided by its
//      expected number of draws, so any positive weight keeps the estimate unbiased). The
//      square root, not the flux, because the flux is heavy-tailed (a candidate seen from few
//      pilot points, or next to a pool vertex): in proportion to flux such candidates are drawn
//      many times and the kept set has few distinct VPLs.
//   5. The light that reaches a VPL position through a delta bounce (caustics on it), which no
//      connection finds: standard light paths that deposit only after a delta bounce. The
//      connections and these paths split the light paths' space, so nothing counts twice.
#include <algorithm>
#include <cmath>

#include "core/parallel.h"
#include "core/rng.h"
#include "lights/light_sampler.h"
#include "manylight/point_light_set.h"
#include "manylight/vpl_sampler.h"
#include "materials/material.h"
#include "sampling/warps.h"
#include "scene/scene.h"
#include "transport/direct_lighting.h"
#include "transport/spawn.h"

namespace ml {
namespace {

constexpr float kDirectShare = 0.5f;  // connections to a point on a light (else a pool vertex)
constexpr size_t kChunk = 256;        // candidates per task
// Most candidates traced per VPL kept, where few bring light (step 2a).
constexpr double kMaxCandidatesPerVpl = 256;

struct Candidate {
    SurfaceInteraction si;  // wo: towards where the light arrives from
    RGB flux;               // one-sample estimate (not yet divided by the candidate count)
    float weight = 0;       // resampling weight (step 4)
    uint8_t depth = 0;      // vertices from the light, x2 included (0: unknown)
};

// Resampling weight of a candidate of flux luminance y (step 4).
float resample_weight(float y) { return y > 0 ? std::sqrt(y) : 0.f; }

// A task's working memory: the BSDFs of a candidate, and in a scene that moves its own light
// path (with a set that holds the path's glossy surfaces, for point_light_intensity).
struct CandidateScratch {
    ScratchBuffer bsdfs, light;
    VplChunk path;
    PointLightSet view;
};

class BidirectionalSampler {
public:
    BidirectionalSampler(const Scene& scene, const PerspectiveCamera& camera,
                         const VplOptions& options)
        : m_scene(scene),
          m_options(options),
          m_light_sampler("power", scene.lights()),
          m_path_options(pool_options(options)),
          m_tracer(scene, m_path_options) {
        m_pilot = camera_pilot_points(scene, camera, options.sampler.pilot, 8,
                                      hash_ints(options.seed, 0x6269646972ULL));
        for (GatherPoint& g : m_pilot.points) {
            // The hemisphere the candidates leave into: the camera's side.
            if (dot(g.si.ns, g.si.wo) < 0) g.si.ns = -g.si.ns;
        }
        // The pool (a static scene): light paths one bounce shorter.
        if (options.max_depth >= 2 && !scene.moves()) generate_vpls(scene, m_path_options, m_pool);
    }

    size_t pool_paths() const { return m_pool.light_paths; }

    void candidate(size_t i, Sampler& sampler, CandidateScratch& cs, Candidate* c) const {
        c->weight = 0;
        c->depth = 0;
        sampler.start_pixel_sample({int(i & 0xfffff), int(i >> 20)}, 0);
        if (m_pilot.points.empty()) return;
        size_t P = m_pilot.points.size();
        size_t j = std::min(size_t(sampler.get_1d() * float(P)), P - 1);
        SurfaceInteraction origin = m_pilot.points[j].si;
        Vec3 d = Frame::from_z(origin.ns).to_world(sample_cosine_hemisphere(sampler.get_2d()));
        float us = sampler.get_1d(), ul = sampler.get_1d();
        Vec2 u2 = sampler.get_2d();
        // The candidate's time (step 2), drawn only where the scene moves.
        bool moves = m_scene.moves();
        float time = moves ? m_scene.time_at(sampler.get_1d()) : origin.time;
        origin.time = time;
        SurfaceInteraction& si = c->si;
        if (!m_scene.intersect(spawn_ray(origin, d), &si) || !si.material) return;
        si.time = time;
        Bsdf bsdf = si.material->get_bsdf(si, cs.bsdfs);
        if (!bsdf || !bsdf.has_nonspecular()) return;
        if (m_options.glossy == GlossyVpls::Skip && (bsdf.flags() & kBxdfGlossy)) return;

        bool paths = m_options.max_depth >= 2 && (moves || !m_pool.lights.empty());
        bool direct = !paths || us < kDirectShare;
        float p_strategy = !paths ? 1.f : direct ? kDirectShare : 1 - kDirectShare;
        RGB E;
        Vec3 wi;
        uint8_t depth = 1;
        if (direct) {
            auto sl = m_light_sampler.sample(ul);
            if (!sl || sl->pmf == 0) return;
            auto ls = sl->light->sample_li(light_context(si), u2);
            if (!ls || ls->L.is_black() || ls->pdf_solid_angle == 0) return;
            if (!m_scene.visible(si, ls->p_light, ls->offset())) return;
            wi = ls->wi;
            E = ls->L * (abs_dot(si.ng, wi) / (ls->pdf_solid_angle * sl->pmf));
        } else {
            // A vertex of the pool, or of a light path of the candidate's own (a moving scene),
            // chosen uniformly among V: its flux times V estimates the sum over all of them.
            const PointLightSet* set = &m_pool;
            const std::vector<PointLight>* lights = &m_pool.lights;
            if (moves) {
                clear(cs.path);
                m_tracer.trace_path(sampler, cs.light, cs.path, &time);
                cs.light.reset();
                cs.view.surfaces = cs.path.surfaces;
                set = &cs.view;
                lights = &cs.path.lights;
            }
            size_t V = lights->size();
            if (V == 0) return;
            const PointLight& pl = (*lights)[std::min(size_t(ul * float(V)), V - 1)];
            Vec3 dz = pl.p - si.p;
            float d2 = length_squared(dz);
            if (!(d2 > 0)) return;
            wi = dz / std::sqrt(d2);
            RGB I = point_light_intensity(*set, pl, -wi);
            if (I.is_black()) return;
            if (!m_scene.visible(si, pl.p, pl.offset)) return;
            // (The pool's fluxes are already divided by its paths; one's own path is one.)
            E = I * (abs_dot(si.ng, wi) * float(V) / d2);
            depth = pl.depth > 0 ? uint8_t(std::min(255, int(pl.depth) + 1)) : 0;
        }
        if (E.is_black()) return;
        // The density last: it costs a shadow ray per pilot point, and most connections of a
        // scene lit through a gap (veach-ajar) fail.
        float p_area = area_density(si);
        if (!(p_area > 0)) return;
        RGB flux = E / (p_area * p_strategy);
        if (!flux.is_finite() || flux.is_black()) return;
        si.wo = wi;
        c->flux = flux;
        c->weight = resample_weight(flux.luminance());
        c->depth = depth;
    }

private:
    static VplOptions pool_options(const VplOptions& options) {
        VplOptions po = options;
        po.glossy = GlossyVpls::Bsdf;
        po.max_depth = std::max(1, options.max_depth - 1);
        po.count = std::max(1, options.count);
        po.paths = 0;
        po.light_pmf.clear();
        po.after_specular_only = false;
        po.seed = hash_ints(options.seed, 0x706f6f6cULL);
        return po;
    }
    static void clear(VplChunk& c) {
        c.lights.clear();
        c.surfaces.clear();
        if (c.arena) c.arena->reset();
    }

    // Density over area of a candidate landing at si (step 2 above), at si's time.
    float area_density(const SurfaceInteraction& si) const {
        double sum = 0;
        for (const GatherPoint& g : m_pilot.points) {
            Vec3 d = si.p - g.si.p;
            float d2 = length_squared(d);
            if (!(d2 > 0)) continue;
            Vec3 w = d / std::sqrt(d2);
            float cos1 = dot(g.si.ns, w), cos2 = abs_dot(si.ng, w);
            if (cos1 <= 0 || cos2 <= 0) continue;
            SurfaceInteraction origin = g.si;
            origin.time = si.time;
            if (!m_scene.visible(origin, si.p, si.offset())) continue;
            sum += double(cos1 * kInvPi * cos2 / d2);
        }
        return float(sum / double(m_pilot.points.size()));
    }

    const Scene& m_scene;
    const VplOptions& m_options;
    LightSampler m_light_sampler;
    VplOptions m_path_options;
    VplTracer m_tracer;
    PilotPoints m_pilot;
    PointLightSet m_pool;
};

}  // namespace

void sample_bidirectional_vpls(const Scene& scene, const PerspectiveCamera& camera,
                               const VplOptions& options, PointLightSet& set) {
    if (options.count <= 0 || options.max_depth <= 0 || scene.lights().empty()) return;
    BidirectionalSampler bidir(scene, camera, options);
    const size_t N = size_t(options.count);
    auto trace = [&](std::vector<Candidate>& cands, uint64_t seed) {
        size_t M = cands.size();
        parallel_for_chunks(
            size_t(0), (M + kChunk - 1) / kChunk, size_t(1), [&](size_t b, size_t e) {
                auto sampler = create_sampler("independent", 1, seed);
                CandidateScratch scratch;
                for (size_t k = b; k < e; ++k)
                    for (size_t i = k * kChunk; i < std::min(M, (k + 1) * kChunk); ++i) {
                        bidir.candidate(i, *sampler, scratch, &cands[i]);
                        scratch.bsdfs.reset();
                    }
            });
    };

    // Step 2a: the share of candidates that bring light, from a first wave of N that is then
    // dropped (so that how many are traced does not depend on those kept: no bias), sets their
    // number: vpl.candidates that bring light per VPL, on average.
    std::vector<Candidate> cands(N);
    trace(cands, hash_ints(options.seed, 0x72617465ULL));
    size_t lit = size_t(
        std::count_if(cands.begin(), cands.end(), [](const Candidate& c) { return c.weight > 0; }));
    const double per_vpl = double(std::max(1, options.sampler.candidates));
    double share = std::max(double(lit) / double(N), per_vpl / kMaxCandidatesPerVpl);
    const size_t M = std::max(N, size_t(std::ceil(double(N) * per_vpl / share)));

    // Steps 2 and 3: the candidates, each from a sample stream of its own.
    cands.assign(M, Candidate());
    trace(cands, hash_ints(options.seed, 0x63616e64ULL));

    // Step 4: systematic resampling of N from the candidates by weight.
    double W = 0;
    for (const Candidate& c : cands) W += double(c.weight);
    VplChunk chunk;
    size_t kept = 0;
    if (W > 0) {
        auto sampler = create_sampler("independent", 1, hash_ints(options.seed, 0x726573ULL));
        sampler->start_pixel_sample({0, 0}, 0);
        double u0 = double(sampler->get_1d()), step = W / double(N), next = u0 * step, cdf = 0;
        ScratchBuffer scratch;
        for (const Candidate& c : cands) {
            if (c.weight <= 0) continue;
            cdf += double(c.weight);
            size_t k = 0;
            while (next < cdf && kept + k < N) {
                ++k;
                next += step;
            }
            if (k == 0) continue;
            kept += k;
            // Each draw estimates the candidates' mean as flux W / (M weight), over N draws.
            float scale = float(double(k) * W / (double(M) * double(N) * double(c.weight)));
            Bsdf bsdf = c.si.material->get_bsdf(c.si, scratch);
            size_t before = chunk.lights.size();
            deposit_vpl(c.si, bsdf, c.flux * scale, options.glossy, chunk);
            if (chunk.lights.size() > before) chunk.lights.back().depth = c.depth;
            scratch.reset();
        }
    }
    std::vector<VplChunk> chunks;
    chunks.push_back(std::move(chunk));
    size_t n = chunks[0].lights.size();
    append_vpls(chunks, n, 1.f, set);
    set.light_paths += bidir.pool_paths();

    // Step 5: what arrives through delta bounces, from standard light paths.
    VplOptions so = options;
    so.after_specular_only = true;
    so.paths = N;
    so.seed = hash_ints(options.seed, 0x73706563ULL);
    generate_vpls(scene, so, set);
}

}  // namespace ml
