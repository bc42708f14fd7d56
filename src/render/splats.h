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
#include "film/film.h"
#include "film/image.h"

namespace ml {

struct Splat {
    uint32_t pixel = 0;
    int32_t image = -1;  // -1: the rendered image; i >= 0: extra image i
    RGB v;
};

// Where one work item's splats go.
class SplatList {
public:
    SplatList(std::vector<Splat>& out, int width, int height)
        : m_out(out), m_width(width), m_height(height) {}
    // A contribution at raster position p (pixels); dropped off the film or when not finite.
    void add(const Vec2& p, const RGB& v, int image = -1) {
        int x = int(std::floor(p.x)), y = int(std::floor(p.y));
        if (x < 0 || y < 0 || x >= m_width || y >= m_height || !v.is_finite() || v.is_black())
            return;
        m_out.push_back(Splat{uint32_t(y) * uint32_t(m_width) + uint32_t(x), image, v});
    }

private:
    std::vector<Splat>& m_out;
    int m_width, m_height;
};

// Per-pixel sums of splats in double precision: the rendered image's, then `extra` images'.
class SplatSums {
public:
    SplatSums(int width, int height, int extra = 0)
        : m_width(width),
          m_height(height),
          m_sums(size_t(1 + extra), std::vector<double>(size_t(width) * size_t(height) * 3, 0.0)) {}
    int width() const { return m_width; }
    int height() const { return m_height; }
    // Adds a list's splats in list order.
    void add(const std::vector<Splat>& list) {
        for (const Splat& s : list) {
            ML_ASSERT(s.image >= -1 && size_t(s.image + 1) < m_sums.size() &&
                          s.pixel < uint32_t(m_width) * uint32_t(m_height),
                      "a splat outside the sums");
            double* d = &m_sums[size_t(s.image + 1)][size_t(s.pixel) * 3];
            for (int c = 0; c < 3; ++c) d[c] += s.v[c];
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
    // Extra image `image` times `scale`.
    Image image(int image, double scale) const {
        Image img(m_width, m_height);
        for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = value(image, i, scale);
        return img;
    }

private:
    int m_width, m_height;
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
        SplatList splats(list, sums.width(), sums.height());
        fn(i, splats);
    });
    for (int64_t i = begin; i < end; ++i) sums.add(lists[size_t(i - begin)]);
}

}  // namespace ml
