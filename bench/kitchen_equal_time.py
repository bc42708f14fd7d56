#!/usr/bin/env python3
"""The kitchen at equal time (issue: many lights I): `mdlightcuts` and `lightcuts` with 100k VPLs
against `path`, each for the same render time at 320x180, over several seeds; relMSE and RMSE
against a long `path` render, from `manylight diff`.

The reference is our own path render at 1024 spp (seed 9, maxdepth 17, the command below); it is
made first when --ref names a file that does not exist (about 100 s on two cores).

Usage:
  bench/kitchen_equal_time.py [--ref build/kitchen-path-320x180-1024spp.exr] [--seconds 15.95] [--seeds 1,2,3]
                              [--clamp 0.2] [--single] [--bin build/manylight] [--no-append]

--single also runs single-point `lightcuts` (one cut per sample) for the same time.
`path` takes seeds one above `mdlightcuts`' so that no two images share random numbers.
--seed also draws the many-light integrators' VPLs and representatives (vpl.seed is left to
follow it), so each seed is an independent VPL set.
"""
import argparse
import json
import os
import re
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "..", "shared", "scenes", "kitchen", "scene-v4.pbrt")
MANY = ["--set", "vpl.count=100000", "--set", "vpl.glossy=diffuse", "--set", "lights.direct=sample"]


def run(cmd):
    subprocess.run(cmd, check=True)


def diff(binary, image, ref):
    out = subprocess.run([binary, "diff", image, ref], check=True, capture_output=True,
                         text=True).stdout
    rel = float(re.search(r"relMSE (\S+)", out).group(1))
    rmse = float(re.search(r"RMSE (\S+)", out).group(1))
    means = re.search(r"mean rel diff (.*)", out)
    return rel, rmse, means.group(1).strip() if means else ""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ref", default=os.path.join(ROOT, "build", "kitchen-path-320x180-1024spp.exr"))
    ap.add_argument("--seconds", type=float, default=15.95)
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--clamp", default="0.2")
    ap.add_argument("--single", action="store_true")
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "manylight"))
    ap.add_argument("--no-append", action="store_true")
    a = ap.parse_args()
    common = [a.bin, "render", SCENE, "--threads", "2", "--resolution", "320x180", "-q"]
    if not os.path.exists(a.ref):
        run(common + ["--integrator", "path", "--spp", "1024", "--max-depth", "17", "--seed", "9",
                      "-o", a.ref])
    limit = ["--time-limit", str(a.seconds)]
    configs = [
        ("mdlightcuts", 0, ["--integrator", "mdlightcuts"] + MANY +
         ["--set", "mdlightcuts.samples=32", "--set", "mdlightcuts.error=0.05",
          "--set", "mdlightcuts.max_cut=200", "--set", f"vpl.clamp={a.clamp}"]),
        ("path", 1, ["--integrator", "path", "--max-depth", "17"]),
    ]
    if a.single:
        configs.append(("lightcuts", 0, ["--integrator", "lightcuts"] + MANY +
                        ["--set", f"vpl.clamp={a.clamp}"]))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in [int(s) for s in a.seeds.split(",")]:
            for name, offset, args in configs:
                out = os.path.join(tmp, f"{name}-{seed}.exr")
                cmd = common + ["--seed", str(seed + offset)] + args + limit + [
                    "-o", out, "--stats", out + ".json"]
                run(cmd)
                with open(out + ".json") as f:
                    stats = json.load(f)
                rel, rmse, means = diff(a.bin, out, a.ref)
                rows.append((name, seed + offset, stats["seconds"]["render"], stats["spp"], rel,
                             rmse, means, " ".join(os.path.relpath(c, ROOT) if c.startswith(ROOT)
                                                   else c for c in cmd).replace(tmp, "OUT")))
    lines = ["| integrator | seed | render s | spp | relMSE | RMSE | channel means |",
             "|---|---|---|---|---|---|---|"]
    for name, seed, secs, spp, rel, rmse, means, _ in rows:
        lines.append(f"| {name} | {seed} | {secs:.2f} | {spp} | {rel:.4f} | {rmse:.4f} | {means} |")
    for name in dict.fromkeys(r[0] for r in rows):
        rels = [r[4] for r in rows if r[0] == name]
        lines.append(f"| {name}, mean | | | | {sum(rels) / len(rels):.4f} | | |")
    text = "\n".join(lines)
    print(text)
    if not a.no_append:
        with open(os.path.join(ROOT, "bench", "RESULTS.md"), "a") as f:
            f.write(f"\n### {time.strftime('%Y-%m-%d')}: `bench/kitchen_equal_time.py "
                    f"--seeds {a.seeds} --seconds {a.seconds} --clamp {a.clamp}`\n\n")
            for name, offset, args in configs:
                f.write(f"    {name}: {' '.join(args)}\n")
            f.write(f"\nReference: {os.path.relpath(a.ref, ROOT)}\n\n{text}\n")


if __name__ == "__main__":
    main()
