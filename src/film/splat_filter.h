// Splats, contributions that land at any raster position (light tracing, BDPT's t = 1
// strategies, MLT, PSSMLT), reconstructed as camera samples are: clamped to the film's
// "maxcomponentvalue", then spread over every pixel whose centre lies within the filter's
// radius, each getting the filter's value there over the filter's integral (pbrt-v4's
// RGBFilm::AddSplat). Camera samples instead draw their offsets from the filter and land in their
// own pixel; both reconstruct the same image. Integrators collect splats per task and spread them
// when merging, in a fixed order, so that images do not depend on the thread schedule.
#pragma once

#include <cmath>
#include <cstddef>

#include "core/color.h"
#include "film/filter.h"

namespace ml {

class SplatFilter {
public:
    SplatFilter(const Filter& filter, int width, int height, float max_component_value)
        : m_filter(filter),
          m_width(width),
          m_height(height),
          m_max(max_component_value),
          m_inv_integral(1.f / filter.integral()) {}

    Vec2 radius() const { return m_filter.radius(); }

    // Calls add(pixel index y * width + x, contribution) for each pixel the splat of v at raster
    // position p reaches; nothing for a non-finite v.
    template <typename Add>
    void spread(const Vec2& p, RGB v, Add&& add) const {
        if (!v.is_finite() || v.is_black()) return;
        float m = v.max_component();
        if (m > m_max) v *= m_max / m;
        Vec2 r = m_filter.radius();
        // Pixel x's centre is x + 1/2.
        int x0 = std::max(0, int(std::ceil(p.x - 0.5f - r.x)));
        int x1 = std::min(m_width - 1, int(std::floor(p.x - 0.5f + r.x)));
        int y0 = std::max(0, int(std::ceil(p.y - 0.5f - r.y)));
        int y1 = std::min(m_height - 1, int(std::floor(p.y - 0.5f + r.y)));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                float w = m_filter.eval(Vec2(p.x - (x + 0.5f), p.y - (y + 0.5f)));
                if (w != 0) add(size_t(y) * size_t(m_width) + size_t(x), v * (w * m_inv_integral));
            }
    }

private:
    const Filter& m_filter;
    int m_width, m_height;
    float m_max;
    float m_inv_integral;
};

}  // namespace ml
