#include <fmt/format.h>

#include "commands.h"
#include "film/image.h"
#include "film/image_metrics.h"
#include "options.h"

namespace ml {

void add_diff_command(CLI::App& app, DiffArgs& a) {
    CLI::App* d = app.add_subcommand("diff", "compare image A against reference B");
    d->add_option("A", a.a, "image")->required();
    d->add_option("B", a.b, "reference image")->required();
    d->add_flag("--json", a.json, "print one JSON object");
    d->add_option("--block", a.block, "also list the worst N x N block means")
        ->check(positive_integer());
    d->add_flag("--block-average", a.block_average,
                "compare blocks by the mean of their channels, not channel by channel");
}

int run_diff(const DiffArgs& a) {
    Image ia = read_image(a.a, FileLoc{a.a}), ib = read_image(a.b, FileLoc{a.b});
    ImageDiff d = compare_images(ia, ib);
    std::vector<BlockDiff> blocks;
    if (a.block > 0) {
        if (ia.width % a.block || ia.height % a.block)
            throw std::runtime_error("--block: the image size is not a multiple of the block");
        blocks = worst_blocks(ia, ib, a.block, 5, 1e-2f, !a.block_average);
    }
    if (a.json) {
        fmt::print(
            "{{\"relmse\": {:.6g}, \"rmse\": {:.6g}, \"mean_a\": [{:.6g}, {:.6g}, {:.6g}], "
            "\"mean_b\": [{:.6g}, {:.6g}, {:.6g}], \"mean_rel_diff\": [{:.6g}, {:.6g}, {:.6g}]",
            d.rel_mse, d.rmse, d.mean_a.r, d.mean_a.g, d.mean_a.b, d.mean_b.r, d.mean_b.g,
            d.mean_b.b, d.mean_rel_diff.r, d.mean_rel_diff.g, d.mean_rel_diff.b);
        if (a.block > 0)
            fmt::print(", \"worst_block_rel_diff\": {:.6g}",
                       blocks.empty() ? 0.0 : blocks[0].rel());
        fmt::print("}}\n");
    } else {
        fmt::print("relMSE {:.6g}  RMSE {:.6g}\n", d.rel_mse, d.rmse);
        fmt::print("mean A       {:.6g} {:.6g} {:.6g}\n", d.mean_a.r, d.mean_a.g, d.mean_a.b);
        fmt::print("mean B       {:.6g} {:.6g} {:.6g}\n", d.mean_b.r, d.mean_b.g, d.mean_b.b);
        fmt::print("mean rel diff {:+.3f}% {:+.3f}% {:+.3f}%\n", 100 * d.mean_rel_diff.r,
                   100 * d.mean_rel_diff.g, 100 * d.mean_rel_diff.b);
        for (const BlockDiff& b : blocks)
            fmt::print("block ({:3d},{:3d}) {} {:.5g} vs {:.5g}: {:+.2f}%\n", b.x * a.block,
                       b.y * a.block, b.channel < 0 ? "avg" : std::string(1, "RGB"[b.channel]), b.a,
                       b.ref, 100 * (b.a - b.ref) / b.ref);
    }
    return 0;
}

}  // namespace ml
