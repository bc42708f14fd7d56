// Multiple importance sampling weights (Veach's thesis, chapter 9).
#pragma once

#include <cmath>

namespace ml {

// The power heuristic (beta = 2) weight of the strategy with density f_pdf against one with
// g_pdf; 1 when f_pdf is infinite (a delta strategy the other cannot sample).
inline float power_heuristic(float f_pdf, float g_pdf) {
    float f = f_pdf * f_pdf, g = g_pdf * g_pdf;
    if (std::isinf(f)) return 1.f;
    return f + g > 0 ? f / (f + g) : 0.f;
}

}  // namespace ml
