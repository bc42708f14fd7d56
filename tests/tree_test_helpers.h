// Random point-light sets for the light tree and bound tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/rng.h"
#include "lights/point_lights.h"

namespace ml::tree_test {

// Glossy: lights of that kind with random falloff tables and no surface (for the tree alone:
// point_light_intensity needs a surface to evaluate them). Mixed: omni, oriented, directional.
enum class LightMix { Omni, Oriented, Directional, Mixed, Glossy };

inline Vec3 random_unit(Rng& rng) {
    float z = 1 - 2 * rng.next_float();
    float r = std::sqrt(std::max(0.f, 1 - z * z)), phi = 2 * kPi * rng.next_float();
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// n lights in [-10, 10]^3, half of them in a few tight clumps; normals random or clumped
// about a few axes; intensities spanning four orders of magnitude, coloured. Some omni lights
// are spots.
inline std::vector<PointLight> random_lights(size_t n, LightMix mix, uint64_t seed) {
    Rng rng(seed);
    Vec3 clump[4], axes[3];
    for (Vec3& c : clump)
        c = Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 20 - Vec3(10, 10, 10);
    for (Vec3& a : axes) a = random_unit(rng);
    std::vector<PointLight> lights(n);
    for (size_t i = 0; i < n; ++i) {
        PointLight& pl = lights[i];
        if (rng.next_float() < 0.5f)
            pl.p =
                clump[rng.next_u32() % 4] +
                (Vec3(rng.next_float(), rng.next_float(), rng.next_float()) - Vec3(.5f, .5f, .5f));
        else
            pl.p =
                Vec3(rng.next_float(), rng.next_float(), rng.next_float()) * 20 - Vec3(10, 10, 10);
        if (rng.next_float() < 0.5f) {
            Vec3 a = axes[rng.next_u32() % 3];
            pl.n = normalize(a + random_unit(rng) * (0.2f * rng.next_float()));
        } else {
            pl.n = random_unit(rng);
        }
        float scale = std::pow(10.f, 4 * rng.next_float() - 2);
        pl.intensity = RGB(rng.next_float(), rng.next_float(), rng.next_float()) * scale;
        pl.is_vpl = i % 8 != 0;  // clusters with and without an emitter's light
        switch (mix) {
            case LightMix::Omni:
                pl.kind = PointLightKind::Omni;
                break;
            case LightMix::Oriented:
                pl.kind = PointLightKind::Oriented;
                break;
            case LightMix::Directional:
                pl.kind = PointLightKind::Directional;
                break;
            case LightMix::Mixed:
                pl.kind = PointLightKind(rng.next_u32() % 3);
                break;
            case LightMix::Glossy:
                pl.kind = PointLightKind::Glossy;
                for (int k = 1; k < kFalloffBins; ++k)
                    pl.falloff[k] =
                        uint8_t(std::min(255u, pl.falloff[k - 1] + rng.next_u32() % 40));
                break;
        }
        if (pl.kind == PointLightKind::Omni && rng.next_float() < 0.3f) {
            pl.cos_end = std::cos(0.8f * rng.next_float() + 0.1f);
            pl.cos_start = pl.cos_end + (1 - pl.cos_end) * rng.next_float();
        }
    }
    return lights;
}

}  // namespace ml::tree_test
