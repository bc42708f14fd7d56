// The materials create_material builds. Parameters that may be textured are held as a constant
// plus an optional texture, so untextured materials make no virtual texture calls per hit.
#pragma once

#include <memory>
#include <optional>

#include "materials/material.h"
#include "materials/microfacet.h"
#include "materials/texture.h"

namespace ml {

class ImageLookup;

struct FloatParam {
    float value = 0;
    std::shared_ptr<FloatTexture> tex;
    float eval(const TextureEvalContext& ctx) const { return tex ? tex->eval(ctx) : value; }
};

struct RGBParam {
    RGB value;
    std::shared_ptr<RGBTexture> tex;
    RGB eval(const TextureEvalContext& ctx) const { return tex ? tex->eval(ctx) : value; }
};

// Roughness as pbrt-v4 reads it: u/v roughness (each defaulting to "roughness"), optionally
// remapped to alpha = sqrt(roughness).
struct RoughnessParams {
    FloatParam u, v;
    bool remap = true;
    TrowbridgeReitz distribution(const TextureEvalContext& ctx) const {
        float ur = u.eval(ctx), vr = v.eval(ctx);
        if (remap) ur = roughness_to_alpha(ur), vr = roughness_to_alpha(vr);
        return TrowbridgeReitz(ur, vr);
    }
};

// The shading frame at a hit: from ns and dpdu, after bump mapping by `displacement` if any
// (pbrt-v4's BumpMap without ray differentials: finite differences over du = dv = 0.0005, and
// without the displacement * dn/du term, since meshes here carry no normal derivatives).
Frame shading_frame(const SurfaceInteraction& si, const FloatTexture* displacement,
                    const ImageLookup* normal_map = nullptr);

class MaterialBase : public Material {
public:
    explicit MaterialBase(std::shared_ptr<FloatTexture> displacement)
        : m_displacement(std::move(displacement)) {}
    // pbrt-v4's "normalmap": tangent-space normals that replace the shading normal (and take
    // precedence over "displacement").
    void set_normal_map(std::shared_ptr<const ImageLookup> normal_map) {
        m_normal_map = std::move(normal_map);
    }

protected:
    Frame frame(const SurfaceInteraction& si) const {
        return shading_frame(si, m_displacement.get(), m_normal_map.get());
    }
    static TextureEvalContext context(const SurfaceInteraction& si) { return {si.p, si.uv, si.ng}; }

private:
    std::shared_ptr<FloatTexture> m_displacement;
    std::shared_ptr<const ImageLookup> m_normal_map;
};

class DiffuseMaterial final : public MaterialBase {
public:
    DiffuseMaterial(RGBParam reflectance, std::shared_ptr<FloatTexture> displacement)
        : MaterialBase(std::move(displacement)), m_reflectance(std::move(reflectance)) {}
    Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const override;
    std::string type() const override { return "diffuse"; }

private:
    RGBParam m_reflectance;
};

class DiffuseTransmissionMaterial final : public MaterialBase {
public:
    DiffuseTransmissionMaterial(RGBParam r, RGBParam t, float scale,
                                std::shared_ptr<FloatTexture> displacement)
        : MaterialBase(std::move(displacement)),
          m_r(std::move(r)),
          m_t(std::move(t)),
          m_scale(scale) {}
    Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const override;
    std::string type() const override { return "diffusetransmission"; }

private:
    RGBParam m_r, m_t;
    float m_scale;
};

class ConductorMaterial final : public MaterialBase {
public:
    // With `use_reflectance`, eta = 1 and k follows from the reflectance (pbrt-v4's mapping).
    ConductorMaterial(RGBParam eta, RGBParam k, RGBParam reflectance, bool use_reflectance,
                      RoughnessParams roughness, std::shared_ptr<FloatTexture> displacement)
        : MaterialBase(std::move(displacement)),
          m_eta(std::move(eta)),
          m_k(std::move(k)),
          m_reflectance(std::move(reflectance)),
          m_use_reflectance(use_reflectance),
          m_roughness(std::move(roughness)) {}
    Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const override;
    std::string type() const override { return "conductor"; }

private:
    RGBParam m_eta, m_k, m_reflectance;
    bool m_use_reflectance;
    RoughnessParams m_roughness;
};

// pbrt-v4's "dielectric"; with an interior medium, its "subsurface": the same boundary over a
// homogeneous medium that light walks through by the integrators' own volumetric transport.
class DielectricMaterial final : public MaterialBase {
public:
    DielectricMaterial(FloatParam eta, RoughnessParams roughness,
                       std::shared_ptr<FloatTexture> displacement,
                       std::optional<InteriorMedium> interior = std::nullopt)
        : MaterialBase(std::move(displacement)),
          m_eta(std::move(eta)),
          m_roughness(std::move(roughness)),
          m_interior(std::move(interior)) {}
    Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const override;
    std::string type() const override { return m_interior ? "subsurface" : "dielectric"; }
    const InteriorMedium* interior_medium() const override {
        return m_interior ? &*m_interior : nullptr;
    }

private:
    FloatParam m_eta;
    RoughnessParams m_roughness;
    std::optional<InteriorMedium> m_interior;
};

class ThinDielectricMaterial final : public MaterialBase {
public:
    ThinDielectricMaterial(FloatParam eta, std::shared_ptr<FloatTexture> displacement)
        : MaterialBase(std::move(displacement)), m_eta(std::move(eta)) {}
    Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const override;
    std::string type() const override { return "thindielectric"; }

private:
    FloatParam m_eta;
};

// pbrt-v4's "mix": at each hit one of two materials, the second with probability `amount`,
// chosen by a hash of the hit point and the outgoing direction (pbrt-v4's ChooseMaterial): no
// sampler dimension, and the same choice wherever the same point is seen from the same
// direction. Averaged over a pixel it is the blend of the two.
class MixMaterial final : public Material {
public:
    MixMaterial(const Material* first, const Material* second, FloatParam amount)
        : m_materials{first, second}, m_amount(std::move(amount)) {}
    Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const override {
        return choose(si)->get_bsdf(si, scratch);
    }
    std::string type() const override { return "mix"; }
    const Material* choose(const SurfaceInteraction& si) const;

private:
    const Material* m_materials[2];
    FloatParam m_amount;
};

class CoatedDiffuseMaterial final : public MaterialBase {
public:
    // thickness, maxdepth: pbrt-v4's layer parameters (defaults 0.01 and 10); see CoatLayer.
    CoatedDiffuseMaterial(RGBParam reflectance, FloatParam eta, RoughnessParams roughness,
                          float thickness, int maxdepth,
                          std::shared_ptr<FloatTexture> displacement);
    Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const override;
    std::string type() const override { return "coateddiffuse"; }

private:
    float round_trip(float eta) const;
    RGBParam m_reflectance;
    FloatParam m_eta;
    RoughnessParams m_roughness;
    float m_thickness;
    int m_base_visits;
    // coat_internal_round_trip(eta, thickness) tabulated over eta in [1/4, 4] for textured eta;
    // exact for a constant one.
    static constexpr int kRoundTripTable = 256;
    float m_round_trip_const = 0;
    std::unique_ptr<float[]> m_round_trip_table;
};

// pbrt-v4's "coatedconductor": a dielectric coat (roughness "interface.*", IOR "interface.eta")
// over a conductor ("conductor.eta"/"conductor.k", or "reflectance"; roughness "conductor.*").
struct CoatedConductorLayers;
struct CoatedConductorTrap;
struct CoatedConductorParams {
    RoughnessParams interface_roughness, conductor_roughness;
    float eta = 1.5f;
    FloatParam thickness{0.01f, nullptr};
    RGBParam conductor_eta, conductor_k, reflectance;
    bool use_reflectance = false;
    int maxdepth = 10;
};

class CoatedConductorMaterial final : public MaterialBase {
public:
    CoatedConductorMaterial(CoatedConductorParams params,
                            std::shared_ptr<FloatTexture> displacement);
    ~CoatedConductorMaterial() override;
    Bsdf get_bsdf(const SurfaceInteraction& si, ScratchBuffer& scratch) const override;
    std::string type() const override { return "coatedconductor"; }

private:
    CoatedConductorLayers layers(const TextureEvalContext& ctx) const;
    CoatedConductorParams m_params;
    // With no texture among the parameters it depends on, the trapped light's tables, once.
    std::unique_ptr<CoatedConductorTrap> m_trap;
};

// pbrt-v4's "interface": a surface that only marks where participating media meet and does not
// scatter. manylight has no media, so such a shape has nothing to do: the scene builder leaves
// it out of the scene (every ray passes straight through it, and an area light on it emits
// nothing, as pbrt-v4 ignores it). Its get_bsdf is never reached; a mix naming it is refused.
class InterfaceMaterial final : public Material {
public:
    Bsdf get_bsdf(const SurfaceInteraction&, ScratchBuffer&) const override { return Bsdf(); }
    std::string type() const override { return "interface"; }
};

}  // namespace ml
