// pbrt-v4's built-in aperture shapes for the realistic camera ("gaussian", "square", "pentagon",
// "star"): a 256 x 256 single-channel image over the stop's bounding square, scaled so that its
// mean is pi / 4 (a shaped stop passes as much light as the round one), looked up bilinearly
// with zero outside. Each shape is built as pbrt-v4 builds it, pixel for pixel: pixel (x, y)
// covers [-1 + 2x/256, -1 + 2(x+1)/256] along x, and row y is flipped (pbrt-v4's FlipY).
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
    bool empty() const { return m_values.empty(); }
    // The weight at the stop point (x, y) / stop radius, each in [-1, 1] inside the square.
    float lookup(float x, float y) const;
    static constexpr int kResolution = 256;

private:
    float at(int x, int y) const;
    std::vector<float> m_values;  // row-major, kResolution^2, after the flip
};

}  // namespace ml
