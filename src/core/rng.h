// PCG32 (O'Neill 2014): the one random number generator; reached only through a Sampler or by
// code that builds samplers.
#pragma once

#include <cstdint>

#include "core/math.h"

namespace ml {

class Rng {
public:
    Rng() = default;
    Rng(uint64_t seq_index, uint64_t offset) { set_sequence(seq_index, offset); }
    explicit Rng(uint64_t seq_index) { set_sequence(seq_index, mix_bits(seq_index)); }

    void set_sequence(uint64_t seq_index, uint64_t offset) {
        m_state = 0u;
        m_inc = (seq_index << 1u) | 1u;
        next_u32();
        m_state += offset;
        next_u32();
    }
    uint32_t next_u32() {
        uint64_t old = m_state;
        m_state = old * 0x5851f42d4c957f2dULL + m_inc;
        uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        uint32_t rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
    }
    // Uniform in [0, 1).
    float next_float() { return std::min(kOneMinusEpsilon, float(next_u32()) * 0x1p-32f); }
    void advance(int64_t delta);

    static uint64_t mix_bits(uint64_t v) {
        v ^= (v >> 31);
        v *= 0x7fb5d329728ea185ULL;
        v ^= (v >> 27);
        v *= 0x81dadef4bc2dd44dULL;
        v ^= (v >> 33);
        return v;
    }

private:
    uint64_t m_state = 0x853c49e6748fea9bULL;
    uint64_t m_inc = 0xda3e39cb94b95bdbULL;
};

inline void Rng::advance(int64_t idelta) {
    uint64_t cur_mult = 0x5851f42d4c957f2dULL, cur_plus = m_inc, acc_mult = 1u, acc_plus = 0u;
    uint64_t delta = uint64_t(idelta);
    while (delta > 0) {
        if (delta & 1) {
            acc_mult *= cur_mult;
            acc_plus = acc_plus * cur_mult + cur_plus;
        }
        cur_plus = (cur_mult + 1) * cur_plus;
        cur_mult *= cur_mult;
        delta /= 2;
    }
    m_state = acc_mult * m_state + acc_plus;
}

// A hash of several integers, for seeding per-pixel sequences.
inline uint64_t hash_ints(uint64_t a, uint64_t b = 0, uint64_t c = 0, uint64_t d = 0) {
    uint64_t h = Rng::mix_bits(a + 0x9e3779b97f4a7c15ULL);
    h = Rng::mix_bits(h ^ (b + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2)));
    h = Rng::mix_bits(h ^ (c + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2)));
    h = Rng::mix_bits(h ^ (d + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2)));
    return h;
}

}  // namespace ml
