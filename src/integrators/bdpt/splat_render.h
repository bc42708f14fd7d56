// The render loop of integrators whose samples land anywhere on the film (light tracing, BDPT's
// t = 1 strategies). Splats are not added to the film as they come, where float atomics would
// make the image depend on the thread schedule: each tile of pixel samples collects its splats
// in a list, and after every wave of tiles the lists are summed in tile order into a
// double-precision buffer. Same seed, any thread count: the same image, bit for bit.
#pragma once

#include <string>
#include <vector>

#include "integrators/integrator.h"

namespace ml {

struct Splat {
    Vec2 p;              // raster position: spread over the pixel filter when merged
    int32_t image = -1;  // -1: the rendered image; i >= 0: extra image i
    RGB v;
    bool spread = true;  // false: added to the pixel that holds p, as a camera sample is
};

// Where one tile's splats go.
class SplatList {
public:
    SplatList(std::vector<Splat>& out, int width, int height)
        : m_out(out), m_width(width), m_height(height) {}
    // A contribution at raster position p (pixels); dropped off the film or when not finite.
    void add(const Vec2& p, const RGB& v, int image = -1) {
        if (!(p.x >= 0 && p.y >= 0 && p.x < float(m_width) && p.y < float(m_height)) ||
            !v.is_finite() || v.is_black())
            return;
        m_out.push_back(Splat{p, image, v});
    }
    // A camera sample's contribution to pixel `pixel` of an extra image (not spread: it was
    // drawn from the filter, as the film's camera samples are).
    void add_to_pixel(Point2i pixel, const RGB& v, int image) {
        if (!v.is_finite() || v.is_black()) return;
        m_out.push_back(Splat{Vec2(pixel.x + 0.5f, pixel.y + 0.5f), image, v, false});
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
