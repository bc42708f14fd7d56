#include <fmt/format.h>

#include "commands.h"
#include "film/image.h"
#include "film/image_metrics.h"

namespace ml {

void add_diff_command(CLI::App& app, DiffArgs& a) {
    CLI::App* d = app.add_subcommand("diff", "compare image A against reference B");
    d->add_option("A", a.a, "image")->required();
    d->add_option("B", a.b, "reference image")->required();
    d->add_flag("--json", a.json, "print one JSON object");
}

int run_diff(const DiffArgs& a) {
    Image ia = read_image(a.a, FileLoc{a.a}), ib = read_image(a.b, FileLoc{a.b});
    ImageDiff d = compare_images(ia, ib);
    if (a.json) {
        fmt::print(
            "{{\"relmse\": {:.6g}, \"rmse\": {:.6g}, \"mean_a\": [{:.6g}, {:.6g}, {:.6g}], "
            "\"mean_b\": [{:.6g}, {:.6g}, {:.6g}], \"mean_rel_diff\": [{:.6g}, {:.6g}, {:.6g}]}}\n",
            d.rel_mse, d.rmse, d.mean_a.r, d.mean_a.g, d.mean_a.b, d.mean_b.r, d.mean_b.g,
            d.mean_b.b, d.mean_rel_diff.r, d.mean_rel_diff.g, d.mean_rel_diff.b);
    } else {
        fmt::print("relMSE {:.6g}  RMSE {:.6g}\n", d.rel_mse, d.rmse);
        fmt::print("mean A       {:.6g} {:.6g} {:.6g}\n", d.mean_a.r, d.mean_a.g, d.mean_a.b);
        fmt::print("mean B       {:.6g} {:.6g} {:.6g}\n", d.mean_b.r, d.mean_b.g, d.mean_b.b);
        fmt::print("mean rel diff {:+.3f}% {:+.3f}% {:+.3f}%\n", 100 * d.mean_rel_diff.r,
                   100 * d.mean_rel_diff.g, 100 * d.mean_rel_diff.b);
    }
    return 0;
}

}  // namespace ml
