#include "integrators/igi/interleave.h"

#include <cmath>

#include "core/parallel.h"

namespace ml {

InterleavedLayout::InterleavedLayout(int width, int height, int n, int m)
    : m_width(width), m_height(height), m_n(n), m_m(m), m_image_x(width), m_image_y(height) {
    ML_ASSERT(width > 0 && height > 0 && n >= 1 && m >= 1, "bad interleaved layout");
    // Sub-buffer column i holds the pixels x = i, i + n, ...: ceil((width - i) / n) of them
    // (none when n > width and i >= width).
    auto starts = [](int size, int k, std::vector<int>* first, std::vector<int>* inverse) {
        first->assign(k, 0);
        int at = 0;
        for (int i = 0; i < k; ++i) {
            (*first)[i] = at;
            for (int v = i; v < size; v += k) (*inverse)[at++] = v;
        }
    };
    starts(width, n, &m_x0, &m_image_x);
    starts(height, m, &m_y0, &m_image_y);
}

bool continuous(const GBufferTexel& p, const GBufferTexel& q, const DiscontinuityThresholds& t) {
    if (!p.valid || !q.valid) return false;
    if (std::abs(dot(p.n, q.p - p.p)) > t.depth * p.depth) return false;
    return dot(p.n, q.n) >= std::cos(t.normal * kPi / 180.f);
}

std::vector<RGB> discontinuity_filter(const std::vector<RGB>& image,
                                      const std::vector<GBufferTexel>& gbuffer, int width,
                                      int height, int size_x, int size_y,
                                      const DiscontinuityThresholds& t) {
    ML_ASSERT(image.size() == size_t(width) * height && gbuffer.size() == image.size(),
              "filter buffers of the wrong size");
    if (size_x <= 1 && size_y <= 1) return image;
    const int x_lo = size_x / 2, x_hi = size_x - 1 - size_x / 2;
    const int y_lo = size_y / 2, y_hi = size_y - 1 - size_y / 2;
    std::vector<RGB> out(image.size());
    const float cos_normal = std::cos(t.normal * kPi / 180.f);
    parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            size_t i = size_t(y) * width + x;
            const GBufferTexel& p = gbuffer[i];
            if (!p.valid) {
                out[i] = image[i];
                continue;
            }
            RGB sum;
            int count = 0;
            for (int qy = std::max(0, y - y_lo); qy <= std::min(height - 1, y + y_hi); ++qy)
                for (int qx = std::max(0, x - x_lo); qx <= std::min(width - 1, x + x_hi); ++qx) {
                    size_t j = size_t(qy) * width + qx;
                    const GBufferTexel& q = gbuffer[j];
                    // continuous(p, q) with the cosine taken once.
                    if (!q.valid || std::abs(dot(p.n, q.p - p.p)) > t.depth * p.depth ||
                        dot(p.n, q.n) < cos_normal)
                        continue;
                    sum += image[j];
                    ++count;
                }
            out[i] = sum / float(count);  // count >= 1: p is continuous with itself
        }
    });
    return out;
}

}  // namespace ml
