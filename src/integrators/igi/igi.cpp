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

}  // namespace

IgiSettings IgiSettings::read(const Settings& s) {
    IgiSettings r;
    std::string interleave = s.get_string("interleave", kDefaultInterleave);
    char extra = 0;
    if (std::sscanf(interleave.c_str(), "%dx%d%c", &r.n, &r.m, &extra) != 2 || r.n < 1 || r.m < 1 ||
        r.n > 64 || r.m > 64)
        throw UsageError("igi.interleave must be NxM with N and M from 1 to 64 (e.g. 4x4), not " +
                         interleave);
    r.filter = s.get_int("filter", kDefaultFilter);
    if (r.filter < 0 || r.filter > 8)
        throw UsageError(
            "igi.filter (the blur's size in interleave patterns; 0: none) must be from 0 to 8");
    r.thresholds.depth = s.get_float("depth_threshold", r.thresholds.depth);
    r.thresholds.normal = s.get_float("normal_threshold", r.thresholds.normal);
    if (!(r.thresholds.depth >= 0) || !(r.thresholds.normal >= 0 && r.thresholds.normal <= 180))
        throw UsageError(
            "igi.depth_threshold must be >= 0 (relative depth) and igi.normal_threshold from 0 to "
            "180 (degrees)");
    r.packets = s.get_bool("packets", r.packets);
    r.filter_direct = s.get_bool("filter_direct", r.filter_direct);
    return r;
}

IgiIntegrator::IgiIntegrator(const Settings& settings)
    : m_many(ManyLightSettings::read(settings)), m_igi(IgiSettings::read(settings)) {
    // igi.vpls, or the vpl.count the other many-light integrators read (under igi's default);
    // both only if they agree. vpl.count is read last, so that its default listed for igi
    // (integrator_settings) is igi's.
    int vpls = settings.get_int("vpls", kDefaultVpls);
    int count = settings.get_int("vpl.count", vpls);
    if (settings.has("vpls") && settings.has("vpl.count") && vpls != count)
        throw UsageError("give igi.vpls or vpl.count, not both (they are the same count)");
    if (count < 0) throw UsageError("igi.vpls must be >= 0");
    m_many.lights.vpl_count = count;
    m_many.lights.vpls = m_many.lights.vpl_count > 0;
}

// Per pixel: the sums of its samples, the direct and the interleaved VPL parts apart.
struct IgiIntegrator::Pixel {
    RGB direct, indirect;
    float weight = 0;
};

RGB IgiIntegrator::shade(const Scene& scene, const GatherPoint& g,
                         const std::vector<uint32_t>& indices, float scale) const {
    RGB L;
    if (!m_igi.packets) {
        for (uint32_t i : indices) {
            const PointLight& pl = m_set.lights[i];
            RGB c;
            Ray shadow;
            if (!point_light_contribution(m_set, pl, g, &c, &shadow)) continue;
            c = m_many.clamped(c, pl.is_vpl);
            if (!scene.occluded(shadow)) L += c;
        }
        return L * scale;
    }
    // Eight shadow rays from one gather point at a time: coherent origins, one Embree packet.
    Ray rays[8];
    RGB values[8];
    bool active[8] = {}, occluded[8];
    int count = 0;
    auto flush = [&] {
        for (int k = count; k < 8; ++k) active[k] = false;
        scene.occluded8(rays, active, occluded);
        for (int k = 0; k < count; ++k)
            if (!occluded[k]) L += values[k];
        count = 0;
    };
    for (uint32_t i : indices) {
        const PointLight& pl = m_set.lights[i];
        if (!point_light_contribution(m_set, pl, g, &values[count], &rays[count])) continue;
        values[count] = m_many.clamped(values[count], pl.is_vpl);
        active[count] = true;
        if (++count == 8) flush();
    }
    if (count > 0) flush();
    return L * scale;
}

RenderResult IgiIntegrator::render(const RenderContext& ctx) {
    const Scene& scene = ctx.scene;
    m_many.use_render_seed(ctx.seed);
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

    // Creation and shading: the render loop walks the split buffer, whose tiles lie in one
    // sub-buffer each (but at its seams), so a tile is shaded by one subset of the VPLs. The
    // first gather point of each pixel's first sample is its G-buffer texel.
    auto t_shade = std::chrono::steady_clock::now();
    std::vector<Pixel> pixels(size_t(w) * h);
    std::vector<GBufferTexel> gbuffer(pixels.size());
    struct ThreadState {
        std::unique_ptr<Sampler> sampler;
        ScratchBuffer scratch;
    };
    ThreadLocal<ThreadState> states([&] {
        return ThreadState{ctx.sampler.clone(), ScratchBuffer()};
    });
    RenderResult result;
    result.spp = int(render_pixels(ctx, ctx.spp, [&](Point2i split, int64_t s0, int64_t s1) {
        ThreadState& ts = states.local();
        Sampler& sampler = *ts.sampler;
        const Point2i pixel = layout.to_image(split);
        const int sub = layout.sub_buffer(pixel);
        const size_t index = size_t(pixel.y) * w + pixel.x;
        Pixel& px = pixels[index];
        for (int64_t s = s0; s < s1; ++s) {
            sampler.start_pixel_sample(pixel, int(s));
            float weight;
            Ray ray = pixel_sample_ray(ctx, pixel, sampler, &weight);
            RGB indirect;
            bool first = s == 0;
            RGB direct = gather_along(
                scene, ray, sampler, ts.scratch, m_many.max_depth,
                [&](const GatherPoint& g, float) {
                    if (first) {
                        gbuffer[index] = {g.si.p, g.si.ns, length(g.si.p - ray.o), true};
                        first = false;
                    }
                    RGB L = m_direct.estimate(scene, g, sampler);
                    if (m_igi.filter_direct) {
                        indirect += L;
                        L = RGB();
                    }
                    L += shade(scene, g, m_emitters, 1.f);
                    indirect += shade(scene, g, m_subsets[sub], m_scales[sub]);
                    return L;
                });
            if (direct.is_finite() && indirect.is_finite()) {
                px.direct += direct * weight;
                px.indirect += indirect * weight;
                px.weight += weight;
            }
            ts.scratch.reset();
        }
    }));
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
    nlohmann::json figures = many_light_figures(m_set, m_direct);
    figures["interleave"] = fmt::format("{}x{}", m_igi.n, m_igi.m);
    figures["filter"] = m_igi.filter;
    figures["seconds_shade"] = shade_seconds;
    figures["seconds_filter"] = filter_seconds;
    result.stats["igi"] = figures;
    return result;
}

}  // namespace ml
