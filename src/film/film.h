// The film: per-pixel weighted sums of radiance (filter-importance-sampled camera samples land
// in their own pixel) plus a splat buffer for samples that may land anywhere (light tracing).
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "core/color.h"
#include "core/world.h"
#include "film/image.h"
#include "sampling/sampler.h"

namespace ml {

class Film {
public:
    // `imaging_ratio` scales every sample and splat (pbrt-v4's exposure time * iso / 100); the
    // clamp to `max_component_value` applies after it, as in pbrt-v4.
    Film(int width, int height, float max_component_value = kInfinity, float imaging_ratio = 1.f);
    int width() const { return m_width; }
    int height() const { return m_height; }
    // Adds a camera sample of pixel p; only the thread rendering p calls this for p.
    void add_sample(Point2i p, RGB L, float weight);
    // Adds to the splat sum of the pixel that holds raster position p_film, from any thread
    // (atomic): contributions already spread over the filter (SplatFilter).
    void add_splat(const Vec2& p_film, RGB v);
    // The clamp SplatFilter applies to each splat: add_splat scales by the imaging ratio
    // afterwards, so clamping at max_component_value / imaging_ratio is pbrt-v4's clamp after it.
    float splat_clamp() const { return m_max_component / m_imaging_ratio; }
    // The image: weighted mean per pixel, plus splats times `splat_scale`.
    Image to_image(float splat_scale = 1.f) const;
    void clear();
    // Across ranks (each rendered its share into its own film): adds every rank's weighted sums,
    // splats and dropped-sample counts into rank 0's film; the others' are left as they were. A
    // pixel only one rank sampled arrives exactly (the others add zeros). Parts no rank wrote
    // (the splats of a pixel integrator) are not sent. A collective: every rank calls it.
    void reduce_to_root(World& world);
    // The weighted sums, 4 per pixel (r, g, b, weight), and back (with the dropped-sample
    // count): the exact state a checkpoint keeps. Splats are not in it (integrators that splat
    // keep their own sums until the end).
    std::vector<double> sums() const;
    void set_sums(const std::vector<double>& sums, uint64_t nonfinite);
    // Samples and splats dropped because a channel was NaN or infinite.
    uint64_t nonfinite_samples() const { return m_nonfinite.load(std::memory_order_relaxed); }
    // Pixels that no camera sample reached (a time limit that ended the first pass early).
    size_t pixels_without_samples() const;

private:
    struct Pixel {
        double rgb[3] = {0, 0, 0};
        double weight = 0;
    };
    int m_width, m_height;
    float m_max_component;
    float m_imaging_ratio;
    std::atomic<uint64_t> m_nonfinite{0};
    std::vector<Pixel> m_pixels;
    std::vector<std::atomic<float>> m_splats;  // 3 per pixel
};

}  // namespace ml
