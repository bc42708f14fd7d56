#!/usr/bin/env python3
"""Per-sample variance and CPU time of `path` (defaults) in this build against another binary,
for a change to next-event estimation (area lights sampled by solid angle, session 8).

Same method as bench/light_tree_variance.py: two seeds a, b per binary at the same spp, relative
variance per sample mean((a - b)^2 / 2 / (r^2 + 0.01)) * spp against a separate render r (this
build, seed 99, --ref-spp), CPU seconds per spp less a 1-spp render's. Binaries alternate.

Usage: bench/nee_variance.py --base OTHER_BINARY [--spp N] [--ref-spp N] [--threads T] [scene ...]
  scenes: kitchen, cornell-box, veach-mis (default: all three)
"""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import light_tree_variance as ltv  # noqa: E402

SCENES = {
    "kitchen": ("kitchen/scene-v4.pbrt", "320x180"),
    "cornell-box": ("cornell-box/scene-v4.pbrt", "256x256"),
    "veach-mis": ("veach-mis/scene-v4.pbrt", "320x180"),
    "classroom": ("classroom/scene-v4.pbrt", "320x180"),
}


def render(binary, scene, res, seed, spp, threads, out):
    saved = ltv.BIN
    ltv.BIN = binary
    try:
        # path.lightsampler=tree is the default: the same command line as a user's.
        return ltv.render(scene, res, "tree", seed, spp, threads, out)
    finally:
        ltv.BIN = saved


def main():
    args = sys.argv[1:]
    opts = {"--spp": 8, "--ref-spp": 32, "--threads": 2, "--base": None}
    for k in list(opts):
        if k in args:
            i = args.index(k)
            opts[k] = args[i + 1] if k == "--base" else int(args[i + 1])
            del args[i : i + 2]
    if not opts["--base"]:
        sys.exit("--base OTHER_BINARY is required")
    spp, threads = opts["--spp"], opts["--threads"]
    bins = {"base": os.path.abspath(opts["--base"]), "this": ltv.BIN}
    print("| scene | spp | base: rel. var. per sample | this | this / base | "
          "CPU s per spp base / this | efficiency this / base |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name in args or list(SCENES):
            rel, res = SCENES[name]
            scene = os.path.join(ltv.SCENES_DIR, rel)
            ref_out = os.path.join(tmp, "ref.pfm")
            render(bins["this"], scene, res, 99, opts["--ref-spp"], threads, ref_out)
            ref = ltv.read_pfm(ref_out)
            imgs, secs, var = {}, {k: 0.0 for k in bins}, {}
            for seed in [1, 2]:
                for k, b in bins.items():
                    out = os.path.join(tmp, "%s-%d.pfm" % (k, seed))
                    secs[k] += render(b, scene, res, seed, spp, threads, out)
                    imgs[(k, seed)] = ltv.read_pfm(out)
            for k, b in bins.items():
                base = render(b, scene, res, 3, 1, threads, os.path.join(tmp, "one.pfm"))
                var[k] = ltv.rel_variance(imgs[(k, 1)], imgs[(k, 2)], ref, spp)
                secs[k] = (secs[k] / 2 - base) / (spp - 1)
            r = var["this"] / var["base"]
            eff = var["this"] * secs["this"] / (var["base"] * secs["base"])
            print("| %s | %d | %.4g | %.4g | **%.3f** | %.3f / %.3f | %.3f |" %
                  (name, spp, var["base"], var["this"], r, secs["base"], secs["this"], eff),
                  flush=True)


if __name__ == "__main__":
    main()
