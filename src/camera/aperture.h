// pbrt-v4's built-in aperture shapes for the realistic camera ("gaussian", "square", "pentagon",
// "star"), or an image file's: a single-channel image (the built-in ones 256 x 256) over the stop's
// bounding square, scaled so that its mean is pi / 4 (a shaped stop passes as much light as the
// round one), looked up bilinearly with zero outside. Each shape is built as pbrt-v4 builds it,
// pixel for pixel: pixel (x, y) covers [-1 + 2x/256, -1 + 2(x+1)/256] along x, and row y is flipped
// (pbrt-v4's FlipY).
#pragma once

#include <string>
#include <vector>

#include "core/math.h"

namespace ml {

class ApertureImage {
public:
    ApertureImage() = default;  // none: the round stop
    // The named shape, or nullopt-like empty image for an unknown name (see is_builtin_name).
    static ApertureImage builtin(const std::string& name);
    static bool is_builtin_name(const std::string& name);
    // An image file's aperture (pbrt-v4's "aperture" naming a file): its values (one channel,
    // linear, row-major, top row first; pbrt-v4 averages R, G and B), flipped and scaled as the
    // built-in shapes are. With `at_most_one` the scaled values stop at 1: pbrt-v4 keeps a
    // one-channel 8-bit file in 8 bits, which cannot hold more, so such a stop covering less than
    // pi / 4 of its square passes less light than the round one.
    static ApertureImage from_values(int width, int height, std::vector<float> values,
                                     bool at_most_one = false);
    bool empty() const { return m_values.empty(); }
    // The weight at the stop point (x, y) / stop radius, each in [-1, 1] inside the square.
    float lookup(float x, float y) const;
    static constexpr int kResolution = 256;  // the built-in shapes'

private:
    // Flips the rows and scales the values so that their mean is pi / 4 (at most 1 each with
    // at_most_one).
    void normalize(bool at_most_one = false);
    float at(int x, int y) const;
    int m_width = 0, m_height = 0;
    std::vector<float> m_values;  // row-major, after the flip
};

}  // namespace ml
