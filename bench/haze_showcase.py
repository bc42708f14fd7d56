#!/usr/bin/env python3
"""The README's showcase of many lights in a medium: the haze stage of examples/haze_stage.py
rendered by `path` and by a many-light integrator for the same time, with their error against a
longer `path` render, as the gallery does for ../shared/scenes (bench/gallery.py).

Writes docs/images/haze-showcase.png (the two renders on top, their error below: each pixel's
relative squared error, (x - r)^2 / (r^2 + 0.01), averaged over the channels, on a log scale,
black 1e-4 or less, white 1 or more) and prints the table of spp, relMSE and channel means.

Usage: /usr/bin/python3 bench/haze_showcase.py [--integrator manylight] [--seconds 20]
    [--ref-seconds 480] [--ref REF.pfm] [--seed 1] [--out docs/images/haze-showcase.png]
    [--bin build/manylight]
(--ref: a reference rendered before, `path` for --ref-seconds at seed 4242, as a .pfm.)
"""
import argparse
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import gallery  # noqa: E402  (bench/gallery.py: rendering, diffs and PNG writing)

ROOT = gallery.ROOT


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--integrator", default="manylight")
    ap.add_argument("--seconds", type=float, default=20)
    ap.add_argument("--ref-seconds", type=float, default=480)
    ap.add_argument("--ref", default="", help="a reference rendered before (.pfm)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--out", default=str(ROOT / "docs" / "images" / "haze-showcase.png"))
    ap.add_argument("--bin", default=str(ROOT / "build" / "manylight"))
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="manylight-haze-") as tmp:
        tmp = pathlib.Path(tmp)
        scene = tmp / "haze.pbrt"
        scene.write_text(subprocess.run([sys.executable, str(ROOT / "examples" / "haze_stage.py")],
                                        check=True, stdout=subprocess.PIPE, text=True).stdout)
        size = (320, 180)
        if args.ref:
            ref = pathlib.Path(args.ref)
        else:
            ref = tmp / "ref.pfm"
            print(f"haze: reference, path for {args.ref_seconds:g} s", file=sys.stderr,
                  flush=True)
            gallery.render(args, scene, "path", args.ref_seconds, 4242, size, ref)
        images, rows = [], []
        for integrator in ("path", args.integrator):
            print(f"haze: {integrator} for {args.seconds:g} s", file=sys.stderr, flush=True)
            img = tmp / f"{integrator}.pfm"
            stats = gallery.render(args, scene, integrator, args.seconds, args.seed, size, img)
            d = gallery.diff(args, img, ref)
            rows.append((integrator, stats["spp"], d["relmse"], d["mean_rel_diff"]))
            images.append(gallery.read_pfm(img))
        r = gallery.read_pfm(ref)
        top = np.concatenate([gallery.srgb8(i) for i in images], axis=1)
        bottom = np.concatenate([gallery.error_image(i, r) for i in images], axis=1)
        gallery.write_png(args.out, np.concatenate([top, bottom], axis=0))
    print("| integrator | spp | relMSE | channel means against the reference |")
    print("|---|---|---|---|")
    for integrator, spp, relmse, means in rows:
        m = " / ".join(f"{100 * v:+.1f}%" for v in means)
        print(f"| `{integrator}` | {spp} | {relmse:.3g} | {m} |")
    print(f"\nReference: `path` for {args.ref_seconds:g} s (seed 4242).")


if __name__ == "__main__":
    main()
