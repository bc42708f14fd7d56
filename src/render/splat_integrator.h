// The render loop of integrators whose samples land anywhere on the film (light tracing, BDPT's
// t = 1 strategies). Splats are not added to the film as they come, where float atomics would
// make the image depend on the thread schedule: each tile of pixel samples collects its splats
// in a list, and after every wave of tiles the lists are summed in tile order into a
// double-precision buffer. Same seed, any thread count: the same image, bit for bit.
#pragma once

#include <string>
#include <vector>

#include "render/integrator.h"
#include "render/splats.h"

namespace ml {

class SplatIntegrator : public Integrator {
public:
    RenderResult render(const RenderContext& ctx) final;
    // Saves the splat sums and the tiles' progress; a resumed render adds to them.
    bool can_checkpoint() const override { return true; }

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
