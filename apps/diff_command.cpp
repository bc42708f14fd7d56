#include <fmt/format.h>
#include <nlohmann/json.hpp>

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
    d->add_option("--block", a.block,
                  "also list the worst N x N block means (whole blocks from the top left)")
        ->check(positive_integer());
    d->add_flag("--block-average", a.block_average,
                "compare blocks by the mean of their channels, not channel by channel");
}

int run_diff(const DiffArgs& a) {
    Image ia = read_image(a.a, FileLoc{a.a}), ib = read_image(a.b, FileLoc{a.b});
    ImageDiff d = compare_images(ia, ib);
    std::vector<BlockDiff> blocks;
    if (a.block > 0) {
        blocks = worst_blocks(ia, ib, a.block, 5, 1e-2f, !a.block_average);
    }
    if (a.json) {
        auto rgb = [](const auto& c) { return nlohmann::json{c.r, c.g, c.b}; };
        nlohmann::json j = {{"relmse", d.rel_mse},
                            {"rmse", d.rmse},
                            {"mean_a", rgb(d.mean_a)},
                            {"mean_b", rgb(d.mean_b)},
                            {"mean_rel_diff", rgb(d.mean_rel_diff)}};
        if (a.block > 0) j["worst_block_rel_diff"] = blocks.empty() ? 0.0 : blocks[0].rel();
        fmt::print("{}\n", j.dump());
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
