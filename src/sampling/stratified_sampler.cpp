// Jittered stratified samples (pbrt-v4's StratifiedSampler): each dimension of each pixel visits
// its strata in its own random order, so the sample index picks a stratum and a hash of
// (pixel, index, dimension) the jitter inside it.
#include "sampling/samplers.h"

namespace ml {
namespace {

using sampling_detail::permutation_element;

class StratifiedSampler final : public Sampler {
public:
    StratifiedSampler(int xs, int ys, bool jitter, uint64_t seed)
        : m_xs(xs), m_ys(ys), m_jitter(jitter), m_seed(seed) {}
    int samples_per_pixel() const override { return m_xs * m_ys; }
    void start_pixel_sample(Point2i pixel, int index, int dimension) override {
        m_pixel = pixel;
        m_index = index;
        m_dim = dimension;
    }
    float get_1d() override {
        uint32_t n = uint32_t(samples_per_pixel());
        uint64_t h = dim_hash(m_dim);
        uint32_t stratum = permutation_element(uint32_t(m_index) % n, n, h);
        float j = jitter(h, 0);
        ++m_dim;
        return std::min((float(stratum) + j) / float(n), kOneMinusEpsilon);
    }
    Vec2 get_2d() override {
        uint32_t n = uint32_t(samples_per_pixel());
        uint64_t h = dim_hash(m_dim);
        uint32_t stratum = permutation_element(uint32_t(m_index) % n, n, h);
        uint32_t x = stratum % uint32_t(m_xs), y = stratum / uint32_t(m_xs);
        float jx = jitter(h, 0), jy = jitter(h, 1);
        m_dim += 2;
        return {std::min((float(x) + jx) / float(m_xs), kOneMinusEpsilon),
                std::min((float(y) + jy) / float(m_ys), kOneMinusEpsilon)};
    }
    std::unique_ptr<Sampler> clone() const override {
        return std::make_unique<StratifiedSampler>(m_xs, m_ys, m_jitter, m_seed);
    }
    std::string name() const override { return "stratified"; }

private:
    uint64_t dim_hash(int dim) const {
        return hash_ints(uint64_t(uint32_t(m_pixel.x)) | (uint64_t(uint32_t(m_pixel.y)) << 32),
                         uint64_t(dim), m_seed);
    }
    float jitter(uint64_t h, int axis) const {
        if (!m_jitter) return 0.5f;
        uint64_t r = hash_ints(h, uint64_t(m_index), uint64_t(axis));
        return sampling_detail::u32_to_float(uint32_t(r >> 32));
    }

    int m_xs, m_ys;
    bool m_jitter;
    uint64_t m_seed;
    Point2i m_pixel;
    int m_index = 0, m_dim = 0;
};

}  // namespace

std::unique_ptr<Sampler> make_stratified_sampler(int xs, int ys, bool jitter, uint64_t seed) {
    return std::make_unique<StratifiedSampler>(std::max(1, xs), std::max(1, ys), jitter, seed);
}

}  // namespace ml
