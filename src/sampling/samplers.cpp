// create_sampler: the names a scene or the command line may ask for.
#include <cmath>

#include "core/error.h"
#include "core/rng.h"
#include "sampling/samplers.h"

namespace ml {

std::unique_ptr<Sampler> create_sampler(const std::string& name, int spp, uint64_t seed) {
    if (spp < 1) throw UsageError("samples per pixel must be at least 1");
    if (name == "independent" || name == "random") return make_independent_sampler(spp, seed);
    if (name == "stratified") {
        // Rounded up to a square so both 1D and 2D requests are fully stratified.
        int n = int(std::ceil(std::sqrt(double(spp)) - 1e-9));
        return make_stratified_sampler(n, n, true, seed);
    }
    if (name == "sobol" || name == "paddedsobol" || name == "zsobol")
        return make_sobol_sampler(spp, seed);
    throw UsageError("unknown sampler \"" + name + "\"");
}

uint64_t seed_from(const Sampler& prototype) {
    auto s = prototype.clone();
    s->start_pixel_sample(Point2i{0, 0}, 0, 0);
    uint64_t a = uint64_t(s->get_1d() * 16777216.f), c = uint64_t(s->get_1d() * 16777216.f);
    return hash_ints(a, c);
}

}  // namespace ml
