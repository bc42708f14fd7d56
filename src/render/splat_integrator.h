// The render loop of integrators whose samples land anywhere on the film (light tracing, BDPT's
// t = 1 strategies). Splats are not added to the film as they come, where float atomics would
// make the image depend on the thread schedule: each tile of pixel samples collects its splats
// in a list, and after every wave of tiles the lists are summed in tile order into a
// double-precision buffer. Same seed, any thread count: the same image, bit for bit.
#pragma once

#include <string>
#include <vector>

#include "render/integrator.h"

namespace ml {

struct Splat {
    uint32_t pixel = 0;
    int32_t image = -1;  // -1: the rendered image; i >= 0: extra image i
    RGB v;
};

// Where one tile's splats go.
class SplatList {
public:
    SplatList(std::vector<Splat>& out, int width, int height)
        : m_out(out), m_width(width), m_height(height) {}
    // A contribution at raster position p (pixels); dropped off the film or when not finite.
    void add(const Vec2& p, const RGB& v, int image = -1) {
        int x = int(std::floor(p.x)), y = int(std::floor(p.y));
        if (x < 0 || y < 0 || x >= m_width || y >= m_height || !v.is_finite() || v.is_black())
            return;
        m_out.push_back(Splat{uint32_t(y) * uint32_t(m_width) + uint32_t(x), image, v});
    }

private:
    std::vector<Splat>& m_out;
    int m_width, m_height;
};

class SplatIntegrator : public Integrator {
public:
    RenderResult render(const RenderContext& ctx) final;

protected:
    // Called once before rendering.
    virtual void prepare(const RenderContext& ctx) {}
    // Sample `index` of `pixel` (the sampler is started on it): camera samples of this pixel go
    // to ctx.film.add_sample(); contributions elsewhere to `splats`. Splats are divided by the
    // samples per pixel in the end.
    virtual void render_sample(const RenderContext& ctx, Point2i pixel, int index, Sampler& sampler,
                               ScratchBuffer& scratch, SplatList& splats) const = 0;
    // Names of the extra images splats may go to (by index), written beside the output.
    virtual std::vector<std::string> extra_images() const { return {}; }
};

}  // namespace ml
