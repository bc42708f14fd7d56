#include "integrators/lightcuts/lightcuts.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "core/cone.h"
#include "core/parallel.h"
#include "core/stats.h"
#include "manylight/bounds.h"
#include "manylight/gather.h"
#include "manylight/pilot.h"
#include "manylight/representative.h"
#include "manylight/vpl_memory.h"
#include "render/render_loop.h"

namespace ml {

LightcutsIntegrator::LightcutsIntegrator(const Settings& settings)
    : m_settings(ManyLightSettings::read(settings)) {
    read_vpl_sets(settings, &m_settings);
    m_error = settings.get_float("error", m_error,
                                 {">= 0",
                                  "Relative error bound: a cut is refined until each node's bound "
                                  "is below this fraction of the estimate."});
    m_max_cut = settings.get_int("max_cut", m_max_cut,
                                 {">= 1",
                                  "Most nodes in one cut; a cut stopped there has no error bound "
                                  "(--stats: capped_fraction)."});
    m_verify = settings.get_bool("verify", false,
                                 {"",
                                  "Check every node of every cut against the exact sum over its "
                                  "lights and report bound violations in --stats (slow)."});
    m_floor = settings.get_float("floor", m_floor,
                                 {">= 0",
                                  "Error floor: a cut stops when every bound is below error times "
                                  "the larger of the estimate and floor times the image's mean "
                                  "luminance, from a pilot (0: purely relative)."});
    if (!(m_floor >= 0)) throw UsageError("lightcuts.floor must be >= 0");
    // Drawn from the tree's (tree.reps), all of them unless told fewer.
    m_reps = settings.get_int(
        "reps", m_settings.tree_reps,
        {"1 to tree.reps",
         "Representatives per node the samples shade with (1: Walter's single representative)."});
    if (m_reps < 1 || m_reps > m_settings.tree_reps)
        throw UsageError(
            fmt::format("lightcuts.reps must be 1 to tree.reps ({})", m_settings.tree_reps));
    m_reconstruct =
        settings.get_int("reconstruct", m_reconstruct,
                         {"0 to 64",
                          "Reconstruction cuts: full cuts only at every B-th pixel in x and y, the "
                          "others from their block's corners (0 or 1: off)."});
    if (m_reconstruct < 0 || m_reconstruct > 64)
        throw UsageError(
            "lightcuts.reconstruct must be 0 to 64 (the sparse grid's spacing in "
            "pixels; 0 or 1: off)");
    std::string criterion = settings.get_string(
        "criterion", "max",
        {"max, probable, sum",
         "When a cut stops: each node's bound below error (max), the whole cut's error below error "
         "with 99% probability (probable), or the sum of the bounds (sum)."});
    if (criterion == "max")
        m_criterion = Criterion::Max;
    else if (criterion == "sum")
        m_criterion = Criterion::Sum;
    else if (criterion == "probable")
        m_criterion = Criterion::Probable;
    else
        throw UsageError("lightcuts.criterion must be max, probable or sum, not " + criterion);
    if (!(m_error >= 0) || m_max_cut < 1)
        throw UsageError("lightcuts: error must be >= 0 and max_cut >= 1");
}

void LightcutsIntegrator::prepare(const Scene& scene) {
    // A pass's new set (vpl.sets=pass) replaces the last: that one goes first, so that two sets
    // and trees are never held at once (manylight/vpl_memory.h).
    m_tree = LightTree();
    m_set = PointLightSet();
    build_many_lights(scene, m_settings, &m_set, &m_direct);
    m_tree = build_light_tree(scene, m_settings, m_set, &m_tree_seconds);
}

RenderResult LightcutsIntegrator::render(const RenderContext& ctx) {
    // Reconstruction cuts take a light as seen where the nearby samples saw it, with no
    // transmittance.
    if (ctx.scene.has_media() && m_reconstruct > 1)
        throw UsageError("lightcuts.reconstruct does not handle participating media (use 0)");
    m_settings.use_render_seed(ctx.seed);
    m_settings.use_scene(ctx.scene);
    m_settings.lights.camera = &ctx.camera;
    m_settings.use_time_limit(ctx, true);
    check_vpl_memory(m_settings, true, name());
    m_width = ctx.film.width();
    m_pixel_cut.assign(size_t(ctx.film.width()) * ctx.film.height(), 0.f);
    m_pixel_samples.assign(m_pixel_cut.size(), 0);
    m_cut_sum = 0;
    m_gather_points = 0;
    m_cut_max = 0;
    m_capped = 0;
    m_reconstructed = 0;
    m_reconstructed_nodes = 0;
    m_refined = 0;
    RenderResult r = m_reconstruct > 1 ? render_reconstructed(ctx) : PixelIntegrator::render(ctx);
    r.point_lights = m_set.lights.size();
    r.vpls = m_set.vpls;
    if (std::string w = vpl_budget_warning(m_set); !w.empty()) r.warnings.push_back(w);
    uint64_t n = m_gather_points.load();
    double pixels = double(ctx.film.width()) * ctx.film.height() * std::max(1, r.spp);
    double shadow_per_pixel = double(stats::total().shadow) / pixels;
    double avg = n ? double(m_cut_sum.load()) / double(n) : 0.0;
    double capped = n ? double(m_capped.load()) / double(n) : 0.0;
    std::string warning =
        capped_cut_warning(name(), "gather points", capped, m_max_cut, m_set, m_pass_cap);
    if (!warning.empty()) r.warnings.push_back(warning);
    nlohmann::json& lc = r.stats["lightcuts"];
    lc = {{"error", m_error},
          {"floor", m_floor},
          {"floor_luminance", m_floor_luminance},
          {"criterion", criterion_name()},
          {"reps", m_reps},
          {"max_cut", m_max_cut},
          {"time_cap", cut_cap_json(m_cap_plan)},
          {"avg_cut_size", avg},
          {"max_cut_size", m_cut_max.load()},
          {"capped_fraction", capped},
          {"gather_points", n},
          {"shadow_rays_per_pixel", shadow_per_pixel},
          {"tree_build_seconds", m_tree_seconds},
          {"reconstruct", m_reconstruct}};
    if (m_reconstruct > 1) {
        uint64_t recon = m_reconstructed.load();
        lc["reconstruction"] = {
            {"reconstructed_fraction", n ? double(recon) / double(n) : 0.0},
            {"refined_fraction", n ? double(m_refined.load()) / double(n) : 0.0},
            {"avg_reconstruction_cut_size",
             recon ? double(m_reconstructed_nodes.load()) / double(recon) : 0.0}};
    }
    lc.update(many_light_figures(m_set, m_direct));
    if (m_verify) {
        uint64_t nodes = m_verified_nodes.load();
        double per_node = 1.0 / double(std::max<uint64_t>(1, nodes));
        lc["verify"] = {
            {"nodes", nodes},
            {"violations", m_violations.load()},
            {"mean_abs_node_error", m_verify_abs_error.load() * per_node},
            {"mean_node_bound", m_verify_bounds.load() * per_node},
            {"mean_rel_error", m_verify_total.load() / double(std::max<uint64_t>(1, n))}};
    }
    // The cut-size heat map: the mean cut size of each pixel's gather points.
    Image cut(ctx.film.width(), ctx.film.height());
    for (size_t i = 0; i < m_pixel_cut.size(); ++i)
        cut.pixels[i] = RGB(m_pixel_samples[i] ? m_pixel_cut[i] / m_pixel_samples[i] : 0.f);
    r.aovs["cutsize"] = std::move(cut);
    return r;
}

void LightcutsIntegrator::before_pixels(const RenderContext& ctx) {
    // Sample 0 of a pixel, shaded as li() does with cuts of at most `cap` nodes; *nodes receives
    // the cuts' summed size.
    struct State {
        std::unique_ptr<Sampler> sampler;
        ScratchBuffer scratch;
    };
    ThreadLocal<State> states([&] { return State{ctx.sampler.clone(), ScratchBuffer()}; });
    auto sample0 = [&](Point2i pixel, int cap, int* nodes) {
        State& st = states.local();
        Sampler& sampler = *st.sampler;
        sampler.start_pixel_sample(pixel, 0);
        float weight, camera_weight;
        Ray ray = pixel_sample_ray(ctx, pixel, sampler, &weight, &camera_weight);
        if (camera_weight == 0) return RGB();
        RGB L = gather_along(ctx.scene, ray, sampler, st.scratch, m_settings.gather(),
                             [&](const GatherPoint& g, float u) {
                                 int cut_size = 0;
                                 RGB direct = m_direct.estimate(ctx.scene, g, sampler);
                                 int k = rep_index(u, m_reps);
                                 RGB c = shade(ctx.scene, g, k, &cut_size, direct, cap);
                                 *nodes += cut_size;
                                 return direct + c;
                             });
        st.scratch.reset();
        return L * camera_weight;
    };
    // The error floor, from a pilot of small cuts.
    m_floor_luminance = 0;
    if (m_floor > 0)
        m_floor_luminance = float(
            m_floor * pilot_mean_luminance(ctx.film.width(), ctx.film.height(), [&](Point2i pixel) {
                int nodes = 0;
                return sample0(pixel, kPilotMaxCut, &nodes);
            }));
    // Under a time limit, the cap that lets the first pass (a sample per pixel) end in time.
    m_cap_plan = plan_pass_cut_cap(ctx, m_max_cut, 1, [&](Point2i pixel, int cap, int) {
        int nodes = 0;
        sample0(pixel, cap, &nodes);
        return nodes;
    });
    m_pass_cap = m_cap_plan.cap;
}

RGB LightcutsIntegrator::li(const Ray& ray, const Scene& scene, Sampler& sampler,
                            ScratchBuffer& scratch, Point2i pixel) const {
    return li_sample(ray, scene, sampler, scratch, pixel, nullptr, {}, -1);
}

RGB LightcutsIntegrator::li_sample(const Ray& ray, const Scene& scene, Sampler& sampler,
                                   ScratchBuffer& scratch, Point2i pixel, SparseCut* record,
                                   std::span<const SparseCut* const> corners, int first_k) const {
    size_t i = size_t(pixel.y) * m_width + pixel.x;
    bool first = true;
    return gather_along(
        scene, ray, sampler, scratch, m_settings.gather(), [&](const GatherPoint& g, float u) {
            int cut_size = 0;
            RGB direct = m_direct.estimate(scene, g, sampler);
            const bool at_first = first;
            const int k = at_first && first_k >= 0 ? first_k : rep_index(u, m_reps);
            first = false;
            RGB c;
            std::array<const SparseCut*, 4> agreeing;
            int n_agreeing =
                at_first && !corners.empty() ? agreeing_corners(g, corners, &agreeing) : 0;
            if (n_agreeing >= kReconstructMinCorners) {
                c = direct + reconstruction_cut(scene, m_set, m_settings, m_tree, g, k,
                                                std::span(agreeing.data(), size_t(n_agreeing)),
                                                &cut_size);
                m_reconstructed.fetch_add(1, std::memory_order_relaxed);
                m_reconstructed_nodes.fetch_add(uint64_t(cut_size), std::memory_order_relaxed);
            } else {
                SparseCut* out = at_first ? record : nullptr;
                if (at_first && !corners.empty()) m_refined.fetch_add(1, std::memory_order_relaxed);
                c = direct +
                    shade(scene, g, k, &cut_size, direct, m_pass_cap, out ? &out->cut : nullptr);
                if (out) {
                    out->valid = true;
                    out->material = g.si.material;
                    out->p = g.si.p;
                    out->n = g.si.ns;
                }
            }
            m_cut_sum.fetch_add(uint64_t(cut_size), std::memory_order_relaxed);
            m_gather_points.fetch_add(1, std::memory_order_relaxed);
            if (cut_size >= m_pass_cap) m_capped.fetch_add(1, std::memory_order_relaxed);
            int prev = m_cut_max.load(std::memory_order_relaxed);
            while (cut_size > prev && !m_cut_max.compare_exchange_weak(prev, cut_size)) {
            }
            if (i < m_pixel_cut.size()) {
                m_pixel_cut[i] += float(cut_size);
                ++m_pixel_samples[i];
            }
            return c;
        });
}

RenderResult LightcutsIntegrator::render_reconstructed(const RenderContext& ctx) {
    prepare(ctx.scene);
    before_pixels(ctx);
    // The sparse grid: columns 0, B, 2B, ... and the last one; rows alike.
    const int w = ctx.film.width(), h = ctx.film.height(), b = m_reconstruct;
    auto grid_count = [&](int size) { return size > 0 ? (size - 1 + b - 1) / b + 1 : 0; };
    auto grid_pos = [&](int i, int size) { return std::min(i * b, size - 1); };
    const int gw = grid_count(w), gh = grid_count(h);
    const size_t sparse = size_t(gw) * size_t(gh);
    std::vector<SparseCut> cuts(sparse);
    std::vector<RGB> values(sparse);
    std::vector<float> weights(sparse);
    std::vector<uint8_t> done(sparse);
    struct State {
        std::unique_ptr<Sampler> sampler;
        ScratchBuffer scratch;
    };
    ThreadLocal<State> states([&] { return State{ctx.sampler.clone(), ScratchBuffer()}; });
    // One camera sample of `pixel`, as PixelIntegrator::render takes it. At its first gather
    // point every pixel's sample s shades with representative s mod reps of each node, so that
    // the corners' shadow rays tested the very lights a sample between them stands for; over a
    // pixel's samples the representatives (each drawn at random when the tree was built) take
    // turns, which keeps the estimate unbiased.
    auto sample = [&](Point2i pixel, int s, SparseCut* record,
                      std::span<const SparseCut* const> corners, float* weight) {
        State& st = states.local();
        st.sampler->start_pixel_sample(pixel, s);
        float camera_weight;
        Ray ray = pixel_sample_ray(ctx, pixel, *st.sampler, weight, &camera_weight);
        if (camera_weight == 0) return RGB();
        RGB L =
            li_sample(ray, ctx.scene, *st.sampler, st.scratch, pixel, record, corners, s % m_reps);
        st.scratch.reset();
        return L * camera_weight;
    };
    RenderContext pass_ctx = ctx;
    pass_ctx.progress = nullptr;  // progress counts whole passes, below
    RenderResult result;
    for (int s = 0; s < ctx.spp; ++s) {
        // 1. The sparse samples' full cuts: sample s of the grid's pixels, each the same whatever
        // the thread that takes it, so the reconstruction is too.
        parallel_for(size_t(0), sparse, [&](size_t i) {
            cuts[i].valid = false;
            done[i] = 0;
            if (ctx.out_of_time()) return;
            Point2i pixel{grid_pos(int(i % size_t(gw)), w), grid_pos(int(i / size_t(gw)), h)};
            values[i] = sample(pixel, s, &cuts[i], {}, &weights[i]);
            done[i] = 1;
        });
        // 2. Every pixel's sample s: the grid's are those just taken; the others reconstruct
        // from their block's corners.
        int64_t ran = render_pixels(pass_ctx, 1, [&](Point2i pixel, int64_t, int64_t) {
            const bool on_x = pixel.x % b == 0 || pixel.x == w - 1;
            const bool on_y = pixel.y % b == 0 || pixel.y == h - 1;
            const int ix = pixel.x / b, iy = pixel.y / b;
            if (on_x && on_y) {
                size_t i = size_t(pixel.y == h - 1 ? gh - 1 : iy) * size_t(gw) +
                           size_t(pixel.x == w - 1 ? gw - 1 : ix);
                if (done[i]) ctx.film.add_sample(pixel, values[i], weights[i]);
                return;
            }
            const int ix1 = std::min(ix + 1, gw - 1), iy1 = std::min(iy + 1, gh - 1);
            const size_t corner_index[4] = {size_t(iy) * gw + ix, size_t(iy) * gw + ix1,
                                            size_t(iy1) * gw + ix, size_t(iy1) * gw + ix1};
            std::array<const SparseCut*, 4> corners;
            bool all_done = true;
            for (int c = 0; c < 4; ++c) {
                corners[size_t(c)] = &cuts[corner_index[c]];
                all_done = all_done && done[corner_index[c]];
            }
            float weight;
            RGB L = sample(pixel, s, nullptr,
                           all_done ? std::span<const SparseCut* const>(corners)
                                    : std::span<const SparseCut* const>(),
                           &weight);
            ctx.film.add_sample(pixel, L, weight);
        });
        if (ran == 0) break;
        result.spp = s + 1;
        report_progress(ctx, double(s + 1) / double(ctx.spp));
    }
    return result;
}

RGB LightcutsIntegrator::error_bound(const RGB& bound, const LightTreeNode& n,
                                     const RGB& estimate) const {
    // The error of two non-negative values is at most the larger. The bounds of bounds.h hold
    // the estimate too, whichever representative it is made of (bound_intensity, light_tree.h),
    // so the cut does not depend on the representatives drawn; the estimate only counts here
    // where clamping caps the bound, or float rounding puts it a hair above.
    RGB out;
    if (!(m_settings.clamp > 0) || n.clampable <= 0) {
        for (int c = 0; c < 3; ++c) out[c] = std::max(bound[c], estimate[c]);
        return out;
    }
    // Each of the node's VPLs gives at most the clamp (per channel), so the node at most
    // clampable times it: finite even where the 1/d^2 bound is not (x inside the node's box).
    float cap = float(n.clampable) * m_settings.clamp;
    for (int c = 0; c < 3; ++c) out[c] = std::max(std::min(bound[c], cap), estimate[c]);
    return out;
}

RGB LightcutsIntegrator::shade(const Scene& scene, const GatherPoint& g, int k, int* cut_size,
                               const RGB& known, int max_cut, std::vector<CutNode>* cut_out) const {
    const Vec3& x = g.si.p;
    const Vec3& wo = g.si.wo;
    // The representative's contribution: exact, with its shadow ray (and VPL clamping).
    auto light_value = [&](int32_t light, ShadowResult* shadow) {
        return visible_point_light(scene, m_set, m_settings, m_set.lights[size_t(light)], g,
                                   shadow);
    };
    // Bounds are made lazily: a new node first gets the BSDF's bound over every direction (one
    // per gather point) times its geometric bound, and its own, tighter material bound only if
    // it reaches the top of the heap still above the threshold. Most nodes of a cut never do.
    const RGB m_all = g.bsdf.max_value_bound(wo, DirectionCone::entire_sphere());
    auto loose_bound = [&](int32_t index, const RGB& estimate) {
        LightNodeRef n = m_tree.ref(index);
        float l = error_bound(g.beta * loose_node_bound(n, x, m_all), n.node, estimate).luminance();
        return std::isnan(l) ? kInfinity : l;
    };
    auto tight_bound = [&](int32_t index, const RGB& estimate) {
        LightNodeRef n = m_tree.ref(index);
        float l =
            error_bound(g.beta * node_error_bound(n, x, g.bsdf, wo), n.node, estimate).luminance();
        return std::isnan(l) ? kInfinity : l;
    };
    // A node stands for its cluster: the representative's value scaled by the cluster's weight
    // over its own, the same factor in every channel, which makes the expectation over the
    // representatives the exact sum whatever the lights' colours (representative.h).
    auto make_entry = [&](int32_t index, int32_t rep, const RGB& rep_value, ShadowResult shadow) {
        CutEntry e{index, rep, 0.f, RGB(), rep_value, true, shadow};
        if (m_tree.node(index).is_leaf()) {
            e.estimate = rep_value;  // exact
            return e;
        }
        const PointLight& pl = m_set.lights[size_t(rep)];
        e.estimate =
            rep_value * representative_scale(m_tree.weight(index), selection_weight(pl.intensity));
        e.bound = loose_bound(index, e.estimate);
        e.tight = e.bound == 0;
        return e;
    };

    thread_local std::vector<CutEntry> heap;
    heap.clear();
    RGB total = known;
    // Over the clustered (non-leaf) nodes of the cut: the sum of their bounds and of their
    // squares.
    float bound_sum = 0, bound_sq = 0;
    for (PointLightKind kind : kAllPointLightKinds) {
        int32_t root = m_tree.root(kind);
        if (root < 0) continue;
        int32_t rep = m_tree.rep(root, k);
        ShadowResult shadow;
        RGB value = light_value(rep, &shadow);
        CutEntry e = make_entry(root, rep, value, shadow);
        total += e.estimate;
        bound_sum += e.bound;
        bound_sq += e.bound * e.bound;
        heap.push_back(e);
        std::push_heap(heap.begin(), heap.end());
    }
    // Refine the worst node until every bound is within the error of the estimate.
    while (!heap.empty() && int(heap.size()) < max_cut) {
        const CutEntry& top = heap.front();
        float tolerance = cut_tolerance(m_error, total, m_floor_luminance);
        if (top.bound <= 0.f) break;
        if (m_criterion == Criterion::Max && top.bound <= tolerance) break;
        if (m_criterion == Criterion::Sum && bound_sum <= tolerance) break;
        // Hoeffding: independent zero-mean errors bounded by b_i exceed t with probability
        // at most 2 exp(-t^2 / (2 sum b_i^2)); 3.26 sqrt(sum b_i^2) makes that 1%.
        if (m_criterion == Criterion::Probable && 3.26f * std::sqrt(bound_sq) <= tolerance) break;
        std::pop_heap(heap.begin(), heap.end());
        CutEntry e = heap.back();
        heap.pop_back();
        if (!e.tight) {
            // Tighten the bound and look again: the node may no longer be the worst.
            float b = tight_bound(e.node, e.estimate);
            if (b < e.bound) {
                bound_sum += b - e.bound;
                bound_sq += b * b - e.bound * e.bound;
                e.bound = b;
            }
            e.tight = true;
            heap.push_back(e);
            std::push_heap(heap.begin(), heap.end());
            continue;
        }
        total = total - e.estimate;
        bound_sum -= e.bound;
        bound_sq -= e.bound * e.bound;
        for (int32_t child : m_tree.node(e.node).children()) {
            // A child whose representative is the parent's reuses its shadow ray.
            int32_t rep = m_tree.rep(child, k);
            ShadowResult shadow = e.shadow;
            RGB value = rep == e.rep ? e.rep_value : light_value(rep, &shadow);
            CutEntry c = make_entry(child, rep, value, shadow);
            total += c.estimate;
            bound_sum += c.bound;
            bound_sq += c.bound * c.bound;
            heap.push_back(c);
            std::push_heap(heap.begin(), heap.end());
        }
    }
    *cut_size = int(heap.size());
    // Sum the cut afresh: the running total drifts by float cancellation.
    RGB L;
    for (const CutEntry& e : heap) L += e.estimate;
    if (m_verify && max_cut == m_max_cut) verify_cut(scene, g, heap, L);  // not the pilot
    if (cut_out) {
        cut_out->clear();
        for (const CutEntry& e : heap) cut_out->push_back({e.node, e.shadow});
        std::sort(cut_out->begin(), cut_out->end());
    }
    return L;
}

void LightcutsIntegrator::verify_cut(const Scene& scene, const GatherPoint& g,
                                     const std::vector<CutEntry>& cut, const RGB& estimate) const {
    uint64_t nodes = 0, violations = 0;
    double abs_error = 0, bounds = 0;
    RGB exact_total;
    std::vector<int32_t> stack;
    for (const CutEntry& e : cut) {
        const LightTreeNode& n = m_tree.node(e.node);
        if (n.is_leaf()) {
            exact_total += e.estimate;
            continue;
        }
        RGB exact;
        stack.assign(1, e.node);
        while (!stack.empty()) {
            int32_t m = stack.back();
            stack.pop_back();
            if (!m_tree.node(m).is_leaf()) {
                stack.push_back(m_tree.node(m).children()[0]);
                stack.push_back(m_tree.node(m).children()[1]);
                continue;
            }
            exact += visible_point_light(scene, m_set, m_settings,
                                         m_set.lights[size_t(m_tree.light(m))], g);
        }
        exact_total += exact;
        RGB bound = error_bound(
            g.beta * node_error_bound(m_tree.ref(e.node), g.si.p, g.bsdf, g.si.wo), n, e.estimate);
        ++nodes;
        for (int c = 0; c < 3; ++c)
            if (std::abs(e.estimate[c] - exact[c]) > bound[c] * 1.0001f + 1e-12f) {
                ++violations;
                break;
            }
        abs_error += std::abs(e.estimate.luminance() - exact.luminance());
        bounds += bound.luminance();
    }
    m_verified_nodes += nodes;
    m_violations += violations;
    m_verify_abs_error.fetch_add(abs_error);
    m_verify_bounds.fetch_add(bounds);
    m_verify_total.fetch_add(std::abs(exact_total.luminance() - estimate.luminance()) /
                             std::max(1e-20f, exact_total.luminance()));
}

}  // namespace ml
