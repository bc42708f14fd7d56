#include "integrators/bdpt/bdpt.h"

#include <fmt/format.h>

#include "bidir/connect.h"
#include "bidir/subpaths.h"
#include "core/stats.h"

namespace ml {

BdptIntegrator::BdptIntegrator(const Settings& settings) {
    m_max_depth = settings.get_int("maxdepth", 5, {">= 0", "Longest path, in bounces."});
    m_strategy_images =
        settings.get_bool("strategy_images", false,
                          {"",
                           "Also write one image per (s, t) strategy, OUT.bdpt_s{S}_t{T}.exr, its "
                           "MIS-weighted contribution (maxdepth <= 16)."});
    // pbrt-v4's names for its per-strategy images (weighted or not): the same images here.
    if (settings.get_bool("visualizestrategies", false,
                          {"", "pbrt-v4's name: as strategy_images."}))
        m_strategy_images = true;
    if (settings.get_bool("visualizeweights", false, {"", "pbrt-v4's name: as strategy_images."}))
        m_strategy_images = true;
    m_light_sampler_name =
        settings.get_string("lightsampler", "power",
                            {"power, bvh, uniform",
                             "How a light subpath's light is chosen: by power (bvh, pbrt-v4's "
                             "default, means power) or uniformly."});
    if (m_light_sampler_name == "bvh") m_light_sampler_name = "power";
    settings.get_bool(
        "regularize", false,
        {"", "Accepted for pbrt-v4 scenes; no effect."});  // accepted for pbrt-v4 scenes; no effect
    if (m_max_depth < 0) throw UsageError("bdpt: maxdepth must be >= 0");
    if (m_light_sampler_name != "power" && m_light_sampler_name != "uniform")
        throw UsageError("bdpt: lightsampler must be power or uniform");
    if (m_strategy_images && m_max_depth > 16)
        throw UsageError("bdpt: strategy_images needs maxdepth <= 16 (one image per strategy)");
}

BdptIntegrator::~BdptIntegrator() = default;

int BdptIntegrator::strategy_index(int s, int t) {
    int depth = s + t - 2;
    return s + depth * (5 + depth) / 2;
}

std::vector<std::string> BdptIntegrator::extra_images() const {
    if (!m_strategy_images) return {};
    std::vector<std::string> names(size_t(strategy_count(m_max_depth)));
    for (int depth = 0; depth <= m_max_depth; ++depth)
        for (int s = 0; s <= depth + 2; ++s) {
            int t = depth + 2 - s;
            if (t == 0 || (s == 1 && t == 1)) continue;
            names[size_t(strategy_index(s, t))] = fmt::format("bdpt_s{}_t{}", s, t);
        }
    // Indices nobody uses ((1,1) and t = 0) get names too, so every image is written.
    for (size_t i = 0; i < names.size(); ++i)
        if (names[i].empty()) names[i] = fmt::format("bdpt_unused{}", i);
    return names;
}

void BdptIntegrator::prepare(const RenderContext& ctx) {
    m_light_sampler = std::make_unique<LightSampler>(m_light_sampler_name, ctx.scene.lights());
    m_ctx = std::make_unique<BdptScene>(ctx.scene, ctx.camera, *m_light_sampler);
}

void BdptIntegrator::render_sample(const RenderContext& ctx, Point2i pixel, int index,
                                   Sampler& sampler, ScratchBuffer& scratch,
                                   SplatList& splats) const {
    float weight;
    Ray ray = pixel_sample_ray(ctx, pixel, sampler, &weight);

    // Both subpaths, then every strategy of at most maxdepth bounces.
    thread_local std::vector<PathVertex> camera_vertices, light_vertices;
    thread_local std::vector<RGB> medium_emission;
    camera_vertices.resize(size_t(m_max_depth) + 2);
    light_vertices.resize(size_t(m_max_depth) + 1);
    medium_emission.resize(size_t(m_max_depth) + 2);
    const bool emitting_media = ctx.scene.has_emitting_media();
    int nc = generate_camera_subpath(*m_ctx, ray, sampler, scratch, m_max_depth + 2,
                                     camera_vertices.data(),
                                     emitting_media ? medium_emission.data() : nullptr);
    int nl = generate_light_subpath(*m_ctx, sampler, scratch, m_max_depth + 1, ray.time,
                                    light_vertices.data());
    RGB L;
    // Light emitted by media along the camera subpath: strategy s = 0 alone (subpaths.h), each
    // stretch after k scattering vertices a path of depth k + 1.
    if (emitting_media)
        for (int k = 0; k + 1 <= m_max_depth; ++k) {
            const RGB& e = medium_emission[size_t(k)];
            if (e.is_black()) continue;
            L += e;
            if (m_strategy_images) splats.add_to_pixel(pixel, e, strategy_index(0, k + 3));
        }
    for (int t = 1; t <= nc; ++t)
        for (int s = 0; s <= nl; ++s) {
            int depth = s + t - 2;
            if ((s == 1 && t == 1) || depth < 0 || depth > m_max_depth) continue;
            Connection c =
                connect_bdpt(*m_ctx, light_vertices.data(), camera_vertices.data(), s, t, sampler);
            if (c.L.is_black()) continue;
            if (c.splat)
                splats.add(c.p_raster, c.L);
            else
                L += c.L;
            // Strategy images average camera samples unweighted: the film's weighted mean is the
            // same for filters whose sampling weight is constant (every positive filter).
            if (m_strategy_images && c.splat)
                splats.add(c.p_raster, c.L, strategy_index(s, t));
            else if (m_strategy_images)
                splats.add_to_pixel(pixel, c.L, strategy_index(s, t));
        }
    ctx.film.add_sample(pixel, L, weight);
}

}  // namespace ml
