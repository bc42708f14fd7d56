// Owen-scrambled 2D Sobol' samples padded over dimension pairs, in the spirit of pbrt-v4's
// PaddedSobolSampler: every pair of dimensions uses the first two Sobol' dimensions (a
// (0,2)-sequence) with its own scramble, and the sample index is permuted per pixel and pair so
// that pairs do not correlate with each other.
#include <array>

#include "sampling/samplers.h"

namespace ml {
namespace {

using sampling_detail::owen_scramble_reversed;
using sampling_detail::permutation_element;
using sampling_detail::u32_to_float;

// Generator matrix columns of Sobol' dimension 1, from the primitive polynomial x + 1: the
// direction numbers obey v_k = v_{k-1} xor (v_{k-1} >> 1) with v_0 = 1 in the top bit (Pascal's
// triangle mod 2).
constexpr std::array<uint32_t, 32> make_dimension1_matrix() {
    std::array<uint32_t, 32> v{};
    v[0] = 1u << 31;
    for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
    return v;
}
constexpr std::array<uint32_t, 32> kSobolDim1 = make_dimension1_matrix();

// Owen scrambling works on the bits in reversed order, so the sampler produces both Sobol'
// dimensions bit-reversed. Dimension 0 (van der Corput) reversed is the index itself; dimension 1
// reversed is the xor of the reversed matrix columns picked by the index's bits, looked up a byte
// at a time.
struct ReversedDim1Tables {
    uint32_t byte[4][256];
};
constexpr ReversedDim1Tables make_reversed_dim1_tables() {
    ReversedDim1Tables t{};
    for (int b = 0; b < 4; ++b)
        for (uint32_t v = 0; v < 256; ++v) {
            uint32_t x = 0;
            for (int k = 0; k < 8; ++k)
                if (v & (1u << k)) {
                    uint32_t c = kSobolDim1[size_t(8 * b + k)], r = 0;
                    for (int j = 0; j < 32; ++j) r |= ((c >> j) & 1u) << (31 - j);
                    x ^= r;
                }
            t.byte[b][v] = x;
        }
    return t;
}
constexpr ReversedDim1Tables kReversedDim1 = make_reversed_dim1_tables();

inline uint32_t sobol_dim1_reversed(uint32_t i) {
    uint32_t v = kReversedDim1.byte[0][i & 0xff];
    if (i >> 8)
        v ^= kReversedDim1.byte[1][(i >> 8) & 0xff] ^ kReversedDim1.byte[2][(i >> 16) & 0xff] ^
             kReversedDim1.byte[3][i >> 24];
    return v;
}

// A dimension id outside the range of ordinary dimensions, for the pixel position.
constexpr uint64_t kPixelDimension = 0xfffffffeull;

class SobolSampler final : public Sampler {
public:
    SobolSampler(int spp, uint64_t seed) : m_spp(spp), m_seed(seed) {}
    int samples_per_pixel() const override { return m_spp; }
    void start_pixel_sample(Point2i pixel, int index, int dimension) override {
        // The pixel's hash once per sample; each dimension then costs one more mix.
        m_pixel_hash =
            hash_ints(uint64_t(uint32_t(pixel.x)) | (uint64_t(uint32_t(pixel.y)) << 32), m_seed);
        m_index = index;
        m_dim = dimension;
    }
    float get_1d() override {
        uint64_t h = pair_hash(uint64_t(m_dim));
        ++m_dim;
        uint32_t i = permuted_index(h);
        return u32_to_float(owen_scramble_reversed(i, uint32_t(h)));
    }
    Vec2 get_2d() override {
        Vec2 u = sample_pair(uint64_t(m_dim));
        m_dim += 2;
        return u;
    }
    Vec2 get_pixel_2d() override { return sample_pair(kPixelDimension); }
    std::unique_ptr<Sampler> clone() const override {
        return std::make_unique<SobolSampler>(m_spp, m_seed);
    }
    std::string name() const override { return "sobol"; }

private:
    uint64_t pair_hash(uint64_t dim) const {
        return Rng::mix_bits(m_pixel_hash ^ ((dim + 1) * 0x9e3779b97f4a7c15ull));
    }
    // The pixel's spp indices in a random order of their own for this pair; indices beyond spp
    // (progressive rendering past the budget) go through in blocks of spp.
    uint32_t permuted_index(uint64_t h) const {
        uint32_t n = uint32_t(m_spp), idx = uint32_t(m_index);
        uint32_t block = idx / n;
        return block * n + permutation_element(idx % n, n, h ^ (uint64_t(block) << 40));
    }
    Vec2 sample_pair(uint64_t dim) const {
        uint64_t h = pair_hash(dim);
        uint32_t i = permuted_index(h);
        // Separate scrambles per coordinate, from the two halves of the hash.
        uint32_t x = owen_scramble_reversed(i, uint32_t(h));
        uint32_t y = owen_scramble_reversed(sobol_dim1_reversed(i), uint32_t(h >> 32));
        return {u32_to_float(x), u32_to_float(y)};
    }

    int m_spp;
    uint64_t m_seed;
    uint64_t m_pixel_hash = 0;
    int m_index = 0, m_dim = 0;
};

}  // namespace

std::unique_ptr<Sampler> make_sobol_sampler(int spp, uint64_t seed) {
    return std::make_unique<SobolSampler>(std::max(1, spp), seed);
}

}  // namespace ml
