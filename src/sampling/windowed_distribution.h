// A piecewise-constant density over [0,1]^2 that samples within any axis-aligned window of it
// (pbrt-v4's WindowedPiecewiseConstant2D): the window's integral from a summed-area table, the v
// coordinate by bisecting the window's marginal, u within the chosen row. Used by the portal
// infinite light, whose window is the part of its image a shading point sees through the portal.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "core/math.h"

namespace ml {

struct Window2 {
    Vec2 lo, hi;  // [lo, hi] inside [0,1]^2
    bool inside(const Vec2& p) const {
        return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y;
    }
};

class WindowedDistribution2D {
public:
    WindowedDistribution2D() = default;
    // func is nu x nv values, row-major (row v holds nu values along u); negatives count as 0.
    WindowedDistribution2D(std::span<const float> func, int nu, int nv);

    // A point of the window with density pdf (over [0,1]^2) proportional to the function there;
    // none where the window holds nothing.
    std::optional<Vec2> sample(const Vec2& u, const Window2& w, float* pdf) const;
    // The density of sample(., w) at p: 0 outside the window.
    float pdf(const Vec2& p, const Window2& w) const;
    // The function's integral over the window (over [0,1]^2 measure).
    double integral(const Window2& w) const;

private:
    // The integral over [0, u] x [0, v]: the summed-area table, bilinear within a cell (exact
    // for a piecewise-constant function).
    double sat(float u, float v) const;
    // The integral of row r over [0, u].
    double row_prefix(int r, float u) const;
    float value(const Vec2& p) const;

    int m_nu = 0, m_nv = 0;
    std::vector<float> m_func;
    std::vector<double> m_sat;  // (nu + 1) x (nv + 1)
};

}  // namespace ml
