// Independent uniform samples: PCG32 on a stream chosen by the pixel and seed, positioned by the
// sample index and dimension, so any sample can be regenerated alone.
#include "sampling/samplers.h"

namespace ml {
namespace {

class IndependentSampler final : public Sampler {
public:
    IndependentSampler(int spp, uint64_t seed) : m_spp(spp), m_seed(seed) {}
    int samples_per_pixel() const override { return m_spp; }
    void start_pixel_sample(Point2i pixel, int index, int dimension) override {
        m_rng.set_sequence(
            hash_ints(uint64_t(uint32_t(pixel.x)), uint64_t(uint32_t(pixel.y)), m_seed), 0);
        // 2^16 dimensions per sample index before sequences of neighbouring indices overlap.
        m_rng.advance(int64_t(index) * 65536 + dimension);
    }
    float get_1d() override { return m_rng.next_float(); }
    Vec2 get_2d() override {
        float x = m_rng.next_float();
        return {x, m_rng.next_float()};
    }
    std::unique_ptr<Sampler> clone() const override {
        return std::make_unique<IndependentSampler>(m_spp, m_seed);
    }
    std::string name() const override { return "independent"; }

private:
    int m_spp;
    uint64_t m_seed;
    Rng m_rng;
};

}  // namespace

std::unique_ptr<Sampler> make_independent_sampler(int spp, uint64_t seed) {
    return std::make_unique<IndependentSampler>(spp, seed);
}

}  // namespace ml
