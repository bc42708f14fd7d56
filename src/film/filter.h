// Pixel reconstruction filters, used by importance sampling (pbrt-v4's approach): each camera
// sample draws its offset from the filter and carries weight f/pdf into its own pixel only, so
// pixels never share writes and renders are deterministic.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/params.h"

namespace ml {

struct FilterSample {
    Vec2 p;  // offset from the pixel centre, in pixels
    float weight = 1;
};

class Filter {
public:
    virtual ~Filter() = default;
    virtual Vec2 radius() const = 0;
    virtual float eval(const Vec2& p) const = 0;
    // The integral of eval over the plane.
    virtual float integral() const = 0;
    virtual FilterSample sample(const Vec2& u) const = 0;
};

// "box" (radius 0.5), "gaussian" (radius 1.5, sigma 0.5), "triangle" (radius 2), with pbrt-v4's
// parameter names. Throws InputError for other filters.
std::unique_ptr<Filter> create_filter(const std::string& name, const ParameterList& params,
                                      const FileLoc& loc);

}  // namespace ml
