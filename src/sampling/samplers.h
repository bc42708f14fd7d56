// The concrete samplers behind `Sampler`, for callers that need settings create_sampler() does not
// take (pbrt-v4's "xsamples"/"ysamples"/"jitter" of the stratified sampler). Every sampler is a
// pure function of (seed, pixel, sample index, dimension): no state survives between pixel
// samples, so thread count and call order never change an image.
#pragma once

#include <cstdint>
#include <memory>

#include "core/rng.h"
#include "sampling/sampler.h"

namespace ml {

std::unique_ptr<Sampler> make_independent_sampler(int spp, uint64_t seed);
// xs * ys strata per 2D request and xs * ys per 1D request, in a per-pixel, per-dimension random
// order; jitter=false puts samples at the stratum centres.
std::unique_ptr<Sampler> make_stratified_sampler(int xs, int ys, bool jitter, uint64_t seed);
// Owen-scrambled 2D Sobol' padded over dimension pairs; spp should be a power of two for the
// stratification guarantees (any count works).
std::unique_ptr<Sampler> make_sobol_sampler(int spp, uint64_t seed);

namespace sampling_detail {

inline uint32_t reverse_bits32(uint32_t v) {
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
    v = ((v >> 8) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8);
    return (v >> 16) | (v << 16);
}

// Element i of a pseudo-random permutation of [0, n) chosen by `seed`: a bijective hash on the
// enclosing power of two, cycle-walked until it lands inside [0, n).
inline uint32_t permutation_element(uint32_t i, uint32_t n, uint64_t seed) {
    if (n <= 1) return 0;
    uint32_t mask = n - 1;
    mask |= mask >> 1, mask |= mask >> 2, mask |= mask >> 4, mask |= mask >> 8, mask |= mask >> 16;
    uint32_t s0 = uint32_t(seed), s1 = uint32_t(seed >> 32);
    do {
        // Each step is a bijection of [0, mask]: xor and add of constants, multiply by an odd
        // number, and xor-shift right of the masked value.
        i ^= s0;
        i = (i * 0x9e3779b1u) & mask;
        i ^= (i & mask) >> 3;
        i = (i + s1) & mask;
        i = (i * (s1 | 1u)) & mask;
        i ^= (i & mask) >> 5;
        i = (i * 0x85ebca6bu) & mask;
        i ^= (i & mask) >> 7;
    } while (i >= n);
    return i;
}

// Nested uniform (Owen) scrambling of a 32-bit fixed-point value: in the bit-reversed domain every
// operation below changes bit k only as a function of bits <= k, so each output digit is the input
// digit flipped by a pseudo-random function of the digits above it (Laine and Karras 2011, Burley
// 2020); the seed picks the scramble. Our own constants.
// The same scramble applied to a value given with its bits already reversed (saves a reversal
// when the caller has them in that order, as the Sobol' sampler does).
inline uint32_t owen_scramble_reversed(uint32_t v, uint32_t seed) {
    v += seed;
    v ^= v * 0x6c50b47cu;
    v ^= seed * 0x2c1b3c6du;
    v *= (seed >> 15) | 1u;
    v ^= v * 0xb82f1e52u;
    v += seed ^ 0xa2c7e6b9u;
    v ^= v * 0xc7afe638u;
    v ^= v * 0x4b7f2d58u;
    return reverse_bits32(v);
}

inline uint32_t owen_scramble(uint32_t v, uint32_t seed) {
    return owen_scramble_reversed(reverse_bits32(v), seed);
}

inline float u32_to_float(uint32_t v) { return std::min(float(v) * 0x1p-32f, kOneMinusEpsilon); }

}  // namespace sampling_detail
}  // namespace ml
