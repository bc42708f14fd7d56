// Interleaved sampling's bookkeeping (seed 000, "non-interleaved deferred shading of interleaved
// sample patterns"): an image's pixels split into n x m sub-buffers and gathered back, and the
// discontinuity filter that blurs the interleaved result only within continuous regions.
//
// Splitting: pixel (x, y) belongs to sub-buffer (x mod n, y mod m), at (x / n, y / m) inside it.
// The sub-buffers are laid out side by side in one buffer of the image's size: sub-buffer i of a
// row of them is ceil((width - i) / n) pixels wide (likewise for the rows), so every image size
// splits, whether or not n and m divide it. Within a sub-buffer every pixel is shaded by the
// same subset of the VPLs, so neighbouring pixels of the image see different subsets while one
// sub-buffer is a coherent block of work.
#pragma once

#include <vector>

#include "core/assert.h"
#include "core/color.h"
#include "core/math.h"
#include "sampling/sampler.h"  // Point2i

namespace ml {

class InterleavedLayout {
public:
    // An image of width x height split into n x m sub-buffers (n, m >= 1).
    InterleavedLayout(int width, int height, int n, int m);

    int width() const { return m_width; }
    int height() const { return m_height; }
    int n() const { return m_n; }
    int m() const { return m_m; }
    int sub_buffers() const { return m_n * m_m; }
    // The sub-buffer of an image pixel, numbered row-major: (y mod m) * n + x mod n.
    int sub_buffer(Point2i pixel) const { return (pixel.y % m_m) * m_n + pixel.x % m_n; }
    // Where an image pixel lies in the split buffer.
    Point2i to_split(Point2i pixel) const {
        return {m_x0[pixel.x % m_n] + pixel.x / m_n, m_y0[pixel.y % m_m] + pixel.y / m_m};
    }
    // The image pixel at a position of the split buffer (the inverse of to_split).
    Point2i to_image(Point2i split) const { return {m_image_x[split.x], m_image_y[split.y]}; }

    // The split buffer of a row-major image, and the image gathered back from a split buffer.
    template <typename T>
    std::vector<T> split(const std::vector<T>& image) const {
        return remap(image, true);
    }
    template <typename T>
    std::vector<T> gather(const std::vector<T>& split_buffer) const {
        return remap(split_buffer, false);
    }

private:
    template <typename T>
    std::vector<T> remap(const std::vector<T>& in, bool to_split_buffer) const {
        ML_ASSERT(in.size() == size_t(m_width) * m_height, "buffer of the wrong size");
        std::vector<T> out(in.size());
        for (int y = 0; y < m_height; ++y)
            for (int x = 0; x < m_width; ++x) {
                Point2i s = to_split({x, y});
                size_t i = size_t(y) * m_width + x, j = size_t(s.y) * m_width + s.x;
                if (to_split_buffer)
                    out[j] = in[i];
                else
                    out[i] = in[j];
            }
        return out;
    }
    int m_width, m_height, m_n, m_m;
    std::vector<int> m_x0, m_y0;            // first column (row) of each sub-buffer column (row)
    std::vector<int> m_image_x, m_image_y;  // split column (row) -> image column (row)
};

// What the discontinuity filter knows of a pixel: the first surface the camera saw there.
struct GBufferTexel {
    Vec3 p;              // the surface point
    Vec3 n;              // shading normal
    float depth = 0;     // distance from the camera
    bool valid = false;  // false where the camera saw no surface to gather at
};

struct DiscontinuityThresholds {
    // Relative depth: q is off p's surface when its distance from p's tangent plane exceeds
    // depth * (p's distance from the camera). The plane, not the depths, so that a surface seen
    // at a grazing angle, whose depth changes fast from pixel to pixel, stays continuous.
    float depth = 0.05f;
    float normal = 25.f;  // degrees between normals beyond which there is an edge
};

// True when q belongs to p's continuous region: both valid, q within the relative distance of
// p's tangent plane and the normals within the angle.
bool continuous(const GBufferTexel& p, const GBufferTexel& q, const DiscontinuityThresholds& t);

// The box blur over continuous regions: each valid pixel becomes the mean of the pixels of its
// size_x x size_y window that are continuous with it (itself included); invalid pixels keep
// their value. The window spans offsets -(size / 2) to size - 1 - size / 2 on each axis, so an
// n x m window covers each of n x m sub-buffers once. Sizes of 1 return the image unchanged.
// Parallel over rows.
std::vector<RGB> discontinuity_filter(const std::vector<RGB>& image,
                                      const std::vector<GBufferTexel>& gbuffer, int width,
                                      int height, int size_x, int size_y,
                                      const DiscontinuityThresholds& t);

}  // namespace ml
