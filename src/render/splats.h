// Contributions that land anywhere on the film (light tracing, BDPT's t = 1 strategies, Markov
// chains), summed so that the image does not depend on the thread schedule: float atomics on the
// film would. Each work item (a tile of pixel samples, a chain's segment) collects its splats in
// a list of its own; after the items of a wave have run, the lists are summed in item order into
// double-precision sums. Same seed, any thread count: the same image, bit for bit.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/assert.h"
#include "core/color.h"
#include "core/math.h"
#include "core/parallel.h"
#include "core/stats.h"
#include "film/film.h"
#include "film/image.h"
#include "film/splat_filter.h"

namespace ml {

struct Splat {
    Vec2 p;              // raster position: spread over the pixel filter when merged
    int32_t image = -1;  // -1: the rendered image; i >= 0: extra image i
    RGB v;
    bool spread = true;  // false: added to the pixel that holds p, as a camera sample is
};

// Where one work item's splats go.
class SplatList {
public:
    SplatList(std::vector<Splat>& out, int width, int height, const Vec2& reach = Vec2())
        : m_out(out), m_width(width), m_height(height), m_reach(reach) {}
    // A contribution at raster position p (pixels); dropped when not finite or when it lies
    // past the film's edge by more than the filter's radius (`reach`): nearer, it still
    // reaches border pixels.
    void add(const Vec2& p, const RGB& v, int image = -1) {
        if (!v.is_finite()) return stats::count_nonfinite_splat();  // in film.nonfinite_samples
        if (!(p.x >= -m_reach.x && p.y >= -m_reach.y && p.x < float(m_width) + m_reach.x &&
              p.y < float(m_height) + m_reach.y) ||
            v.is_black())
            return;
        m_out.push_back(Splat{p, image, v});
    }
    // A camera sample's contribution to pixel `pixel` of an extra image (not spread: it was
    // drawn from the filter, as the film's camera samples are).
    void add_to_pixel(Point2i pixel, const RGB& v, int image) {
        if (!v.is_finite()) return stats::count_nonfinite_splat();
        if (v.is_black()) return;
        m_out.push_back(Splat{Vec2(pixel.x + 0.5f, pixel.y + 0.5f), image, v, false});
    }

private:
    std::vector<Splat>& m_out;
    int m_width, m_height;
    Vec2 m_reach;
};

// Per-pixel sums of splats in double precision: the rendered image's, then `extra` images'.
// Splats are spread over the pixel filter by `spread` (clamped as camera samples are).
class SplatSums {
public:
    SplatSums(int width, int height, const SplatFilter& spread, int extra = 0)
        : m_width(width),
          m_height(height),
          m_spread(spread),
          m_sums(size_t(1 + extra), std::vector<double>(size_t(width) * size_t(height) * 3, 0.0)) {}
    int width() const { return m_width; }
    int height() const { return m_height; }
    // How far past the film's edge a spread splat still reaches a pixel: the filter's radius.
    Vec2 reach() const { return m_spread.radius(); }
    // Adds a list's splats in list order.
    void add(const std::vector<Splat>& list) {
        for (const Splat& s : list) {
            [[maybe_unused]] const Vec2 r = s.spread ? m_spread.radius() : Vec2();
            ML_ASSERT(s.image >= -1 && size_t(s.image + 1) < m_sums.size() && s.p.x >= -r.x &&
                          s.p.y >= -r.y && s.p.x < float(m_width) + r.x &&
                          s.p.y < float(m_height) + r.y,
                      "a splat outside the sums");
            std::vector<double>& sum = m_sums[size_t(s.image + 1)];
            auto add_to = [&](size_t pixel, const RGB& v) {
                double* d = &sum[pixel * 3];
                for (int c = 0; c < 3; ++c) d[c] += v[c];
            };
            if (s.spread)
                m_spread.spread(s.p, s.v, add_to);
            else
                add_to(size_t(s.p.y) * size_t(m_width) + size_t(s.p.x), s.v);
        }
    }
    // The sum at `pixel` of image `image` (-1: the rendered one) times `scale`.
    RGB value(int image, size_t pixel, double scale) const {
        const double* d = &m_sums[size_t(image + 1)][pixel * 3];
        return RGB(float(d[0] * scale), float(d[1] * scale), float(d[2] * scale));
    }
    // The rendered image's sums times `scale`, splatted at the pixel centres, once per pixel.
    void add_to_film(Film& film, double scale) const {
        for (int y = 0; y < m_height; ++y)
            for (int x = 0; x < m_width; ++x) {
                RGB v = value(-1, size_t(y) * size_t(m_width) + size_t(x), scale);
                if (!v.is_black()) film.add_splat(Vec2(float(x) + 0.5f, float(y) + 0.5f), v);
            }
    }
    // The sums of image `image` (-1: the rendered one), 3 per pixel, and back: the exact state a
    // checkpoint keeps.
    const std::vector<double>& sums(int image) const { return m_sums[size_t(image + 1)]; }
    void set_sums(int image, std::vector<double> sums) {
        ML_ASSERT(sums.size() == m_sums[size_t(image + 1)].size(), "splat sums of another size");
        m_sums[size_t(image + 1)] = std::move(sums);
    }
    int images() const { return int(m_sums.size()); }
    // Extra image `image` times `scale`.
    Image image(int image, double scale) const {
        Image img(m_width, m_height);
        for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = value(image, i, scale);
        return img;
    }

private:
    int m_width, m_height;
    const SplatFilter& m_spread;
    std::vector<std::vector<double>> m_sums;
};

// Runs fn(i, splats) for the items i in [begin, end) in parallel, each with a SplatList of its
// own (from `lists`, which holds at least end - begin lists), then adds the lists to `sums` in
// the order of i.
template <typename F>
void run_and_merge(int64_t begin, int64_t end, std::vector<std::vector<Splat>>& lists,
                   SplatSums& sums, const F& fn) {
    parallel_for(begin, end, [&](int64_t i) {
        std::vector<Splat>& list = lists[size_t(i - begin)];
        list.clear();
        SplatList splats(list, sums.width(), sums.height(), sums.reach());
        fn(i, splats);
    });
    for (int64_t i = begin; i < end; ++i) sums.add(lists[size_t(i - begin)]);
}

}  // namespace ml
