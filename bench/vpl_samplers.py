#!/usr/bin/env python3
"""The VPL samplers (issue 15): relMSE against a converged BDPT reference of ours.

Scenes: veach-ajar and veach-bidir (light arriving by indirect paths) at 64x36, cornell-box at
48x48. Reference: `bdpt` at the same resolution, REF_SPP spp, seed 99 (kept in /tmp between runs).
Each sampler (vpl.sampler=standard|power|bidirectional) at 256, 1024 and 4096 VPLs through `vpl`
and `mdlightcuts` (4 spp, the other settings at their defaults), seeds 1 and 2, relMSE averaged;
then equal time: `vpl` with 1024 VPLs under --time-limit EQUAL_TIME seconds.

Usage: bench/vpl_samplers.py [--quick] [--samplers=standard,power,bidirectional,metropolis:4]
(prints a markdown table; metropolis:K sets vpl.metropolis.tries=K)
"""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "manylight")
SCENES = os.path.join(ROOT, "..", "shared", "scenes")
TMP = "/tmp/vpl_samplers_bench"
QUICK = "--quick" in sys.argv
REF_SPP = 64 if QUICK else 256
EQUAL_TIME = 4.0
SCENE_RES = [("veach-ajar", "64x36"), ("veach-bidir", "64x36"), ("cornell-box", "48x48")]
SAMPLERS = ["standard", "power", "bidirectional"]
for a in sys.argv[1:]:
    if a.startswith("--samplers="):
        SAMPLERS = a.split("=", 1)[1].split(",")
COUNTS = [256] if QUICK else [256, 1024, 4096]
SEEDS = [1] if QUICK else [1, 2]


def sampler_args(smp):
    """'metropolis:4' is metropolis with vpl.metropolis.tries=4."""
    name, _, tries = smp.partition(":")
    args = ["--set", f"vpl.sampler={name}"]
    return args + (["--set", f"vpl.metropolis.tries={tries}"] if tries else [])


def scene_path(name):
    return os.path.join(SCENES, name, "scene-v4.pbrt")


def render(scene, res, out, args):
    stats = out + ".json"
    cmd = [BIN, "render", scene_path(scene), "-q", "--threads", "2", "--resolution", res,
           "-o", out, "--stats", stats] + args
    subprocess.run(cmd, check=True)
    with open(stats) as f:
        return json.load(f)


def relmse(a, ref):
    out = subprocess.run([BIN, "diff", "--json", a, ref], check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out)["relmse"]


def main():
    os.makedirs(TMP, exist_ok=True)
    rows = []
    for scene, res in SCENE_RES:
        ref = os.path.join(TMP, f"{scene}-{res}-bdpt{REF_SPP}.exr")
        if not os.path.exists(ref):
            render(scene, res, ref, ["--integrator", "bdpt", "--spp", str(REF_SPP), "--seed", "99"])
        for integ in ["vpl", "mdlightcuts"]:
            for count in COUNTS:
                cells = []
                for smp in SAMPLERS:
                    errs, secs = [], []
                    for seed in SEEDS:
                        out = os.path.join(TMP, f"{scene}-{integ}-{smp}-{count}-{seed}.exr")
                        st = render(scene, res, out, [
                            "--integrator", integ, "--spp", "4", "--seed", str(seed),
                            "--set", f"vpl.count={count}"] + sampler_args(smp))
                        errs.append(relmse(out, ref))
                        secs.append(st["seconds"]["render"])
                    cells.append((sum(errs) / len(errs), sum(secs) / len(secs)))
                rows.append((scene, integ, str(count), cells))
                print(rows[-1], flush=True)
        cells = []
        for smp in SAMPLERS:
            errs = []
            for seed in SEEDS:
                out = os.path.join(TMP, f"{scene}-eqt-{smp}-{seed}.exr")
                render(scene, res, out, [
                    "--integrator", "vpl", "--spp", "1024", "--time-limit", str(EQUAL_TIME),
                    "--seed", str(seed), "--set", "vpl.count=1024"] + sampler_args(smp))
                errs.append(relmse(out, ref))
            cells.append((sum(errs) / len(errs), EQUAL_TIME))
        rows.append((scene, "vpl", f"1024, {EQUAL_TIME:g} s", cells))
        print(rows[-1], flush=True)
    print("| scene | integrator | VPLs | " + " | ".join(SAMPLERS) + " |")
    print("|---|---|---|" + "---|" * len(SAMPLERS))
    for scene, integ, count, cells in rows:
        print(f"| {scene} | {integ} | {count} | " +
              " | ".join(f"{e:.3g} ({s:.1f} s)" for e, s in cells) + " |")


if __name__ == "__main__":
    main()
