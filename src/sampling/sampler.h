// The Sampler: the only source of randomness for rendering. Each (pixel, sample index) starts a
// reproducible sequence of dimensions, so a pixel can be re-rendered alone and Metropolis
// samplers can stand in underneath.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "core/math.h"

namespace ml {

struct Point2i {
    int x = 0, y = 0;
    bool operator==(const Point2i& o) const { return x == o.x && y == o.y; }
};

class Sampler {
public:
    virtual ~Sampler() = default;
    virtual int samples_per_pixel() const = 0;
    // Starts sample `index` of `pixel`; `dimension` skips ahead in the sequence.
    virtual void start_pixel_sample(Point2i pixel, int index, int dimension = 0) = 0;
    virtual float get_1d() = 0;
    virtual Vec2 get_2d() = 0;
    // The 2D sample for the position inside the pixel (may use a dedicated dimension pair).
    virtual Vec2 get_pixel_2d() { return get_2d(); }
    // An independent copy for another thread, with the same seed and settings.
    virtual std::unique_ptr<Sampler> clone() const = 0;
    virtual std::string name() const = 0;
};

// "independent", "stratified", "sobol" (Owen-scrambled, padded 2D Sobol'): throws
// UsageError for an unknown name.
std::unique_ptr<Sampler> create_sampler(const std::string& name, int spp, uint64_t seed);

// A seed for randomness that is not per pixel (Markov chains), read through the render's sampler
// so that the sampler stays the only source of randomness: a hash of the first two numbers of
// pixel (0, 0) (24 bits of each), which every sampler derives from its seed.
uint64_t seed_from(const Sampler& prototype);

}  // namespace ml
