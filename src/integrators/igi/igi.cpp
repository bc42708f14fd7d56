#include "integrators/igi/igi.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "core/parallel.h"
#include "render/render_loop.h"

namespace ml {

namespace {

// The defaults: the best measured on the kitchen at 640x360 (bench/RESULTS.md, "Issue 16").
constexpr int kDefaultVpls = 256;
constexpr const char* kDefaultInterleave = "4x4";
constexpr int kDefaultFilter = 1;

double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Up to eight shadow rays traced as one Embree packet; each unoccluded ray adds its value to its
// target, in the order the rays were added. Full batches go at once; the caller flushes where
// its rays stop being coherent.
class ShadowPacket {
public:
    explicit ShadowPacket(const Scene& scene) : m_scene(scene) {}
    void add(const Ray& ray, const RGB& value, RGB* target) {
        m_rays[m_count] = ray;
        m_values[m_count] = value;
        m_targets[m_count] = target;
        if (++m_count == 8) flush();
    }
    void flush() {
        if (m_count == 0) return;
        bool active[8] = {}, occluded[8];
        for (int k = 0; k < m_count; ++k) active[k] = true;
        m_scene.occluded8(m_rays, active, occluded);
        for (int k = 0; k < m_count; ++k)
            if (!occluded[k]) *m_targets[k] += m_values[k];
        m_count = 0;
    }

private:
    const Scene& m_scene;
    Ray m_rays[8];
    RGB m_values[8];
    RGB* m_targets[8] = {};
    int m_count = 0;
};

}  // namespace

IgiSettings IgiSettings::read(const Settings& s) {
    IgiSettings r;
    std::string interleave = s.get_string(
        "interleave", kDefaultInterleave,
        {"NxM (N, M: 1 to 64)",
         "Pixel (x, y) is shaded by VPL subset (x mod N, y mod M), each scaled by N x M."});
    char extra = 0;
    if (std::sscanf(interleave.c_str(), "%dx%d%c", &r.n, &r.m, &extra) != 2 || r.n < 1 || r.m < 1 ||
        r.n > 64 || r.m > 64)
        throw UsageError("igi.interleave must be NxM with N and M from 1 to 64 (e.g. 4x4), not " +
                         interleave);
    r.filter = s.get_int("filter", kDefaultFilter,
                         {"0 to 8",
                          "Size of the box blur in interleave patterns (1: each pixel averages "
                          "every VPL subset once; 0: no blur)."});
    if (r.filter < 0 || r.filter > 8)
        throw UsageError(
            "igi.filter (the blur's size in interleave patterns; 0: none) must be from 0 to 8");
    r.thresholds.depth =
        s.get_float("depth_threshold", r.thresholds.depth,
                    {">= 0",
                     "Neighbours whose distance from the camera differs by more than this fraction "
                     "are across an edge and not blurred together."});
    r.thresholds.normal = s.get_float(
        "normal_threshold", r.thresholds.normal,
        {"0 to 180",
         "Degrees between shading normals beyond which neighbours are across an edge."});
    if (!(r.thresholds.depth >= 0) || !(r.thresholds.normal >= 0 && r.thresholds.normal <= 180))
        throw UsageError(
            "igi.depth_threshold must be >= 0 (relative depth) and igi.normal_threshold from 0 to "
            "180 (degrees)");
    r.packets = s.get_bool(
        "packets", r.packets,
        {"", "Trace each VPL's shadow rays to a row of 8 gather points as one Embree packet."});
    r.filter_direct = s.get_bool(
        "filter_direct", r.filter_direct,
        {"",
         "Blur the sampled direct light with the VPLs' light too (the viewer's moving frames)."});
    return r;
}

IgiIntegrator::IgiIntegrator(const Settings& settings)
    : m_many(ManyLightSettings::read(
          settings, {.glossy = "diffuse", .clamp = 0.2f, .tree_reps = 0, .focus = 0.5f})),
      m_igi(IgiSettings::read(settings)) {
    // igi.vpls, or the vpl.count the other many-light integrators read (under igi's default);
    // both only if they agree. vpl.count is read last, so that its default listed for igi
    // (integrator_settings) is igi's.
    int vpls = settings.get_int(
        "vpls", kDefaultVpls,
        {">= 0", "VPLs: vpl.count under igi's own name (give one, or both equal)."});
    int count = settings.get_int("vpl.count", vpls);
    if (settings.has("vpls") && settings.has("vpl.count") && vpls != count)
        throw UsageError("give igi.vpls or vpl.count, not both (they are the same count)");
    if (count < 0) throw UsageError("igi.vpls must be >= 0");
    m_many.lights.vpl_count = count;
    m_many.lights.vpls = m_many.lights.vpl_count > 0 && m_many.vpls_reach;
}

// Per pixel: the sums of its samples, the direct and the interleaved VPL parts apart.
struct IgiIntegrator::Pixel {
    RGB direct, indirect;
    float weight = 0;
};

RGB IgiIntegrator::shade(const Scene& scene, const GatherPoint& g,
                         const std::vector<uint32_t>& indices, float scale) const {
    RGB L;
    // In media (g.sampler set) each light's transmittance, which packets do not carry.
    if (!m_igi.packets || g.sampler) {
        for (uint32_t i : indices)
            L += visible_point_light(scene, m_set, m_many, m_set.lights[i], g);
        return L * scale;
    }
    // Eight shadow rays from one gather point at a time: coherent origins, one Embree packet.
    ShadowPacket packet(scene);
    for (uint32_t i : indices) {
        const PointLight& pl = m_set.lights[i];
        RGB c;
        Ray shadow;
        if (!point_light_contribution(m_set, pl, g, &c, &shadow)) continue;
        packet.add(shadow, m_many.clamped(c, pl.is_vpl), &L);
    }
    packet.flush();
    return L * scale;
}

void IgiIntegrator::gather_row(const RenderContext& ctx, const InterleavedLayout& layout, int y,
                               int x0, int x1, int s, RowState& rs,
                               std::vector<GBufferTexel>& gbuffer) const {
    const Scene& scene = ctx.scene;
    Sampler& sampler = *rs.sampler;
    const int w = ctx.film.width();
    rs.points.clear();
    rs.pixels.clear();
    for (int x = x0; x < x1; ++x) {
        const Point2i pixel = layout.to_image({x, y});
        const int sub = layout.sub_buffer(pixel);
        const size_t index = size_t(pixel.y) * w + pixel.x;
        sampler.start_pixel_sample(pixel, s);
        RowPixel rp;
        rp.index = index;
        rp.first = rs.points.size();
        Ray ray = pixel_sample_ray(ctx, pixel, sampler, &rp.weight, &rp.camera_weight);
        if (rp.camera_weight == 0) {  // vignetted: a sample of black
            rp.last = rp.first;
            rs.pixels.push_back(rp);
            continue;
        }
        bool first = s == 0;
        rp.direct = gather_along(
            scene, ray, sampler, rs.scratch, m_many.gather(), [&](const GatherPoint& g, float) {
                if (first) {
                    gbuffer[index] = {g.si.p, g.si.ns, length(g.si.p - ray.o), true};
                    first = false;
                }
                RowPoint pt{g, sub, RGB(), RGB()};
                RGB L = m_direct.estimate(scene, g, sampler);
                if (m_igi.filter_direct) {
                    pt.direct = L;
                    L = RGB();
                }
                L += shade(scene, g, m_emitters, 1.f);
                rs.points.push_back(pt);
                return L;
            });
        rp.last = rs.points.size();
        rs.pixels.push_back(rp);
    }
}

void IgiIntegrator::shade_row_vpls(const Scene& scene, RowState& rs) const {
    // The subsets the row's points belong to: one, or more at a seam of the split buffer.
    rs.subs.clear();
    for (const RowPoint& pt : rs.points)
        if (std::find(rs.subs.begin(), rs.subs.end(), pt.sub) == rs.subs.end())
            rs.subs.push_back(pt.sub);
    ShadowPacket packet(scene);
    for (int sub : rs.subs) {
        for (uint32_t i : m_subsets[sub]) {
            const PointLight& pl = m_set.lights[i];
            for (RowPoint& pt : rs.points) {
                if (pt.sub != sub) continue;
                if (!m_igi.packets || pt.g.sampler) {  // (in media: transmittance)
                    pt.vpls += visible_point_light(scene, m_set, m_many, pl, pt.g);
                    continue;
                }
                RGB c;
                Ray shadow;
                if (!point_light_contribution(m_set, pl, pt.g, &c, &shadow)) continue;
                packet.add(shadow, m_many.clamped(c, pl.is_vpl), &pt.vpls);
            }
            // One packet per VPL: the next VPL's rays end elsewhere.
            packet.flush();
        }
        for (RowPoint& pt : rs.points)
            if (pt.sub == sub) pt.vpls = pt.vpls * m_scales[sub];
    }
}

RenderResult IgiIntegrator::render(const RenderContext& ctx) {
    const Scene& scene = ctx.scene;
    m_many.use_render_seed(ctx.seed);
    m_many.use_time_limit(ctx, false);
    m_many.use_scene(scene);
    m_many.lights.camera = &ctx.camera;  // the VPLs' emission focus (vpl.focus)
    build_many_lights(scene, m_many, &m_set, &m_direct);

    // The VPLs dealt round-robin to the sub-buffers (VPLs are in light-path order, so every
    // subset draws from paths all over the set); each subset stands for all of them.
    const int w = ctx.film.width(), h = ctx.film.height();
    InterleavedLayout layout(w, h, m_igi.n, m_igi.m);
    const int k = layout.sub_buffers();
    m_emitters.clear();
    m_subsets.assign(k, {});
    size_t vpls = 0;
    for (uint32_t i = 0; i < m_set.lights.size(); ++i) {
        if (!m_set.lights[i].is_vpl)
            m_emitters.push_back(i);
        else
            m_subsets[vpls++ % k].push_back(i);
    }
    m_scales.assign(k, 0.f);
    for (int s = 0; s < k; ++s)
        if (!m_subsets[s].empty()) m_scales[s] = float(vpls) / float(m_subsets[s].size());

    // Creation and shading: the render loop walks the split buffer a row of a tile at a time
    // (up to 8 pixels of one sub-buffer, but at its seams). For each sample the row's camera
    // paths gather first (G-buffer, direct light, the emitters' lights); then each VPL of the
    // row's subset shades all the row's gather points, its shadow rays one coherent packet (close
    // origins, one end point). Per gather point the VPLs still add up in the subset's order, so
    // the image is the one pixel-by-pixel shading gives. The first gather point of each pixel's
    // first sample is its G-buffer texel.
    auto t_shade = std::chrono::steady_clock::now();
    std::vector<Pixel> pixels(size_t(w) * h);
    std::vector<GBufferTexel> gbuffer(pixels.size());
    ThreadLocal<RowState> states([&] {
        RowState rs;
        rs.sampler = ctx.sampler.clone();
        return rs;
    });
    RenderResult result;
    result.spp = int(render_rows(ctx, ctx.spp, [&](int y, int x0, int x1, int64_t s0, int64_t s1) {
        RowState& rs = states.local();
        auto t0 = std::chrono::steady_clock::now();
        for (int64_t s = s0; s < s1; ++s) {
            gather_row(ctx, layout, y, x0, x1, int(s), rs, gbuffer);
            auto t1 = std::chrono::steady_clock::now();
            shade_row_vpls(scene, rs);
            // Per pixel, its gather points in path order, as one pixel's shading adds them.
            for (const RowPixel& rp : rs.pixels) {
                RGB indirect;
                for (size_t i = rp.first; i < rp.last; ++i) {
                    if (m_igi.filter_direct) indirect += rs.points[i].direct;
                    indirect += rs.points[i].vpls;
                }
                if (rp.direct.is_finite() && indirect.is_finite()) {
                    Pixel& px = pixels[rp.index];
                    px.direct += rp.direct * (rp.weight * rp.camera_weight);
                    px.indirect += indirect * (rp.weight * rp.camera_weight);
                    px.weight += rp.weight;
                }
            }
            rs.scratch.reset();
            auto t2 = std::chrono::steady_clock::now();
            rs.seconds_gather += std::chrono::duration<double>(t1 - t0).count();
            rs.seconds_vpls += std::chrono::duration<double>(t2 - t1).count();
            t0 = t2;
        }
    }));
    double gather_seconds = 0, vpl_seconds = 0;
    for (const RowState& rs : states) {
        gather_seconds += rs.seconds_gather;
        vpl_seconds += rs.seconds_vpls;
    }
    double shade_seconds = seconds_since(t_shade);

    // Across ranks each shaded the pixels of its tiles; the filter needs their neighbours, so
    // rank 0 sums every rank's pixels and texels (the others' slots are zero: exact) and alone
    // filters and writes the film. 15 floats a pixel.
    if (ctx.ranks() > 1) {
        constexpr size_t kFloats = 15;
        std::vector<float> packed(pixels.size() * kFloats, 0.f);
        for (size_t i = 0; i < pixels.size(); ++i) {
            const Pixel& px = pixels[i];
            const GBufferTexel& g = gbuffer[i];
            float v[kFloats] = {
                px.direct.r,   px.direct.g, px.direct.b, px.indirect.r, px.indirect.g,
                px.indirect.b, px.weight,   g.p.x,       g.p.y,         g.p.z,
                g.n.x,         g.n.y,       g.n.z,       g.depth,       g.valid ? 1.f : 0.f};
            std::copy(v, v + kFloats, packed.begin() + ptrdiff_t(i * kFloats));
        }
        ctx.world->reduce_sum(packed.data(), packed.size());
        if (!ctx.world->root()) {
            result.point_lights = m_set.lights.size();
            result.vpls = m_set.vpls;
            return result;
        }
        for (size_t i = 0; i < pixels.size(); ++i) {
            const float* v = &packed[i * kFloats];
            pixels[i] = Pixel{RGB(v[0], v[1], v[2]), RGB(v[3], v[4], v[5]), v[6]};
            gbuffer[i] =
                GBufferTexel{Vec3(v[7], v[8], v[9]), Vec3(v[10], v[11], v[12]), v[13], v[14] != 0};
        }
    }

    // Gathering is implicit (each pixel wrote its own slot); filtering and blending.
    auto t_filter = std::chrono::steady_clock::now();
    std::vector<RGB> indirect(pixels.size());
    for (size_t i = 0; i < pixels.size(); ++i)
        if (pixels[i].weight != 0) indirect[i] = pixels[i].indirect / pixels[i].weight;
    // The window spans igi.filter whole n x m patterns: every VPL subset counts equally.
    if (m_igi.filter > 0)
        indirect = discontinuity_filter(indirect, gbuffer, w, h, m_igi.filter * m_igi.n,
                                        m_igi.filter * m_igi.m, m_igi.thresholds);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = size_t(y) * w + x;
            const Pixel& px = pixels[i];
            if (px.weight == 0) continue;
            ctx.film.add_sample({x, y}, px.direct / px.weight + indirect[i], px.weight);
        }
    double filter_seconds = seconds_since(t_filter);

    result.point_lights = m_set.lights.size();
    result.vpls = m_set.vpls;
    if (std::string w = vpl_budget_warning(m_set, "igi.vpls"); !w.empty())
        result.warnings.push_back(w);
    nlohmann::json figures = many_light_figures(m_set, m_direct);
    figures["interleave"] = fmt::format("{}x{}", m_igi.n, m_igi.m);
    figures["filter"] = m_igi.filter;
    figures["seconds_shade"] = shade_seconds;
    // Summed over the threads (CPU seconds, not wall): the camera paths with their G-buffer,
    // direct light and emitters, and the VPLs with their shadow rays.
    figures["thread_seconds_gather"] = gather_seconds;
    figures["thread_seconds_vpls"] = vpl_seconds;
    figures["seconds_filter"] = filter_seconds;
    result.stats["igi"] = figures;
    return result;
}

}  // namespace ml
