// Perlin noise as pbrt-v4 evaluates it (Perlin's improved noise, 2002: his permutation of 0..255,
// gradients picked from 12 cube-edge directions by the hashed lattice corner, quintic fade), and
// the sums of octaves pbrt-v4's procedural textures are built on. Deterministic functions of the
// point: a texture, not a random source.
#pragma once

#include "core/math.h"

namespace ml {

// Noise in [-1, 1] (about), zero at every integer lattice point. pbrt-v4's 2D noise is this with
// z = 0.5 (and y = 0.5 for 1D).
float perlin_noise(float x, float y, float z);
inline float perlin_noise(const Vec3& p) { return perlin_noise(p.x, p.y, p.z); }
// The noise's gradient as pbrt-v4's DNoise takes it: forward differences over 0.01.
Vec3 perlin_noise_gradient(const Vec3& p);

// The number of octaves pbrt-v4 sums for a footprint of squared size `footprint2` in noise space
// (the larger of |dp/dx|^2 and |dp/dy|^2): clamp(-1 - log2(footprint2) / 2, 0, max_octaves), so
// that no octave finer than the footprint aliases. manylight carries no ray differentials and
// passes 0: every octave, as pbrt-v4 has where a pixel covers less than 2^-9 of a noise cell.
float noise_octaves(float footprint2, int max_octaves);

// Fractional Brownian motion: sum over octaves i of omega^i noise(1.99^i p), the last, partial
// octave faded in by a smoothstep of its fraction (pbrt-v4's FBm).
float fbm(const Vec3& p, float footprint2, float omega, int max_octaves);
// The same sum of |noise|, with the octaves left out replaced by their mean, 0.2 (pbrt-v4's
// Turbulence).
float turbulence(const Vec3& p, float footprint2, float omega, int max_octaves);

}  // namespace ml
