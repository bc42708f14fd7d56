// Placeholder until the samplers land (replaced by the sampling work).
#include <stdexcept>

#include "sampling/sampler.h"

namespace ml {

std::unique_ptr<Sampler> create_sampler(const std::string& name, int spp, uint64_t seed) {
    throw std::invalid_argument("sampler \"" + name + "\" is not built yet");
}

}  // namespace ml
