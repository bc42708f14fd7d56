// A bilinear density over [0,1]^2 from a grid of values, optionally one grid per point of a
// lattice of parameters (interpolated linearly between them): the warp of Dupuy and Jakob's
// measured BRDFs (2018), which pbrt-v4 and Mitsuba call a piecewise-linear 2D distribution.
//
// The grid holds nx x ny values at the corners of (nx - 1) x (ny - 1) bilinear patches. As a
// density it is normalised per parameter slice, and sample() draws rows by their marginal and
// then a column given the row, each by inverting a piecewise-quadratic CDF, so that invert()
// undoes sample() exactly. As a plain table (density = false) it only interpolates the values.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/math.h"

namespace ml {

class PiecewiseLinear2D {
public:
    struct Point {
        Vec2 p;
        float pdf = 0;  // density over [0,1]^2 (of sample(): of p; of invert(): of the input)
    };

    PiecewiseLinear2D() = default;
    // values: one nx * ny grid (row-major, x fastest) per slice, the slices ordered by the
    // parameters with the last one fastest. params[d]: the increasing values of parameter d.
    // nx, ny >= 2; every value finite and >= 0, and every slice's sum > 0 when `density`.
    PiecewiseLinear2D(std::span<const float> values, int nx, int ny,
                      std::vector<std::vector<float>> params, bool density);

    // The warp of u in [0,1)^2, and the density at what it returns.
    Point sample(Vec2 u, std::span<const float> params) const;
    // The u that sample() maps p to, and the density at p.
    Point invert(Vec2 p, std::span<const float> params) const;
    // The interpolated value at p (the density, when built as one).
    float eval(Vec2 p, std::span<const float> params) const;
    // The largest value of the grid, over all slices (a bound on eval: interpolation never
    // exceeds its corners).
    float max_value() const { return m_max; }
    size_t parameter_count() const { return m_params.size(); }

private:
    // Up to 2^3 slices and their weights for a parameter point.
    struct Slices {
        int count = 1;
        uint32_t index[8] = {0};
        float weight[8] = {1};
    };
    Slices slices(std::span<const float> params) const;
    // The value at `at` within each slice's part of `table` (`stride` entries per slice),
    // blended over the slices.
    float lookup(const std::vector<float>& table, uint32_t stride, uint32_t at,
                 const Slices& s) const;
    // The bilinear patch holding p: its corner `at`, p's place in it, and the values along its
    // two columns' edges interpolated to p's height (c0 on the left, c1 on the right).
    struct Patch {
        int col = 0, row = 0;
        uint32_t at = 0;
        float sx = 0, ty = 0, c0 = 0, c1 = 0;
    };
    Patch patch(Vec2 p, const Slices& s) const;

    int m_nx = 0, m_ny = 0;
    std::vector<std::vector<float>> m_params;
    std::vector<uint32_t> m_strides;   // slices per step of each parameter
    std::vector<float> m_data;         // per slice: nx * ny values (normalised for a density)
    std::vector<float> m_marginal;     // per slice: ny CDF values over rows
    std::vector<float> m_conditional;  // per slice: nx * ny CDF values along each row
    float m_scale = 1;  // (nx - 1)(ny - 1) for a density: from unit patches to [0,1]^2
    float m_max = 0;
};

}  // namespace ml
