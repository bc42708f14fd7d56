#!/usr/bin/env python3
"""The VPL samplers (issue 15): relMSE against a converged BDPT reference of ours.

Scenes: veach-ajar and veach-bidir (light arriving by indirect paths) at 64x36, cornell-box at
48x48. Reference: `bdpt` at the same resolution, --ref-spp (4096) spp, seed 97 (kept in TMP
between runs); its own relMSE is estimated from a second, independent BDPT render of 256 spp
(seed 99): relMSE(256 vs ref) * 256 / ref_spp.
Each sampler at --counts VPLs through `vpl` (4 spp) and `mdlightcuts` (4 spp, one pass of 32),
seeds 1 and 2, relMSE averaged; with it, from `vpl`'s --stats, the VPL point lights (distinct
VPLs: bidirectional merges a candidate drawn k times into one) and the share of them that light
some gather point. Then equal time: `vpl` with 1024 VPLs under --time-limit EQUAL_TIME seconds.
Every cell with the defaults (vpl.clamp=0.2) or, with --clamps=default,0, also with
vpl.clamp=0 (no clamping bias).

Usage: bench/vpl_samplers.py [--scenes=veach-ajar,...] [--counts=256,1024,4096]
  [--samplers=standard,power,bidirectional,metropolis,metropolis:4] [--integrators=vpl,mdlightcuts]
  [--ref-spp=4096] [--clamps=default,0] [--equal-only] [--seeds=1,2]
(prints markdown tables; metropolis:K sets vpl.metropolis.tries=K)
"""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("MANYLIGHT_BIN", os.path.join(ROOT, "build", "manylight"))
SCENES = os.path.join(ROOT, "..", "shared", "scenes")
TMP = "/tmp/vpl_samplers_bench"
EQUAL_TIME = 4.0
RES = {"veach-ajar": "64x36", "veach-bidir": "64x36", "cornell-box": "48x48"}


def arg(name, default):
    for a in sys.argv[1:]:
        if a.startswith(f"--{name}="):
            return a.split("=", 1)[1]
    return default


SCENE_LIST = arg("scenes", "veach-ajar,veach-bidir,cornell-box").split(",")
SAMPLERS = arg("samplers", "standard,power,bidirectional,metropolis,metropolis:4").split(",")
COUNTS = [int(c) for c in arg("counts", "256,1024,4096").split(",") if c]
INTEGRATORS = arg("integrators", "vpl,mdlightcuts").split(",")
SEEDS = [int(s) for s in arg("seeds", "1,2").split(",")]
REF_SPP = int(arg("ref-spp", "4096"))
CLAMPS = [None if c == "default" else c for c in arg("clamps", "default").split(",")]
EQUAL_ONLY = "--equal-only" in sys.argv


def sampler_args(smp):
    """'metropolis:4' is metropolis with vpl.metropolis.tries=4."""
    name, _, tries = smp.partition(":")
    args = ["--set", f"vpl.sampler={name}"]
    return args + (["--set", f"vpl.metropolis.tries={tries}"] if tries else [])


def render(scene, out, args):
    stats = out + ".json"
    cmd = [BIN, "render", os.path.join(SCENES, scene, "scene-v4.pbrt"), "-q", "--threads", "2",
           "--resolution", RES[scene], "-o", out, "--stats", stats] + args
    subprocess.run(cmd, check=True)
    with open(stats) as f:
        return json.load(f)


def relmse(a, ref):
    out = subprocess.run([BIN, "diff", "--json", a, ref], check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out)["relmse"]


def reference(scene):
    ref = os.path.join(TMP, f"{scene}-{RES[scene]}-bdpt{REF_SPP}.exr")
    if not os.path.exists(ref):
        render(scene, ref, ["--integrator", "bdpt", "--spp", str(REF_SPP), "--seed", "97"])
    low = os.path.join(TMP, f"{scene}-{RES[scene]}-bdpt256.exr")
    if not os.path.exists(low):
        render(scene, low, ["--integrator", "bdpt", "--spp", "256", "--seed", "99"])
    own = relmse(low, ref) * 256 / REF_SPP
    print(f"reference {scene}: bdpt {REF_SPP} spp; its own relMSE about {own:.2g}", flush=True)
    return ref, own


def cell(scene, ref, integ, smp, clamp, extra, tag):
    errs, secs, lights, lit = [], [], [], []
    for seed in SEEDS:
        c = "" if clamp is None else f"-c{clamp}"
        out = os.path.join(TMP, f"{scene}-{integ}-{smp}{c}-{tag}-{seed}.exr")
        args = ["--integrator", integ, "--seed", str(seed)] + extra + sampler_args(smp)
        if clamp is not None:
            args += ["--set", f"vpl.clamp={clamp}"]
        st = render(scene, out, args)
        errs.append(relmse(out, ref))
        secs.append(st["seconds"]["render"])
        v = st.get("vpl")
        if v:
            lights.append(v["vpl_lights"])
            lit.append(v["lighting"] / max(1, v["vpl_lights"]))
    mean = lambda x: sum(x) / len(x) if x else float("nan")
    return mean(errs), mean(secs), mean(lights), mean(lit)


def fmt_cell(c, show_vpls):
    e, s, n, f = c
    text = f"{e:.3g} ({s:.1f} s"
    if show_vpls and n == n:
        text += f"; {n:.0f} VPLs, {100 * f:.0f}% light"
    return text + ")"


def main():
    os.makedirs(TMP, exist_ok=True)
    rows = []
    for scene in SCENE_LIST:
        ref, own = reference(scene)
        for clamp in CLAMPS:
            label = "" if clamp is None else ", clamp 0"
            if not EQUAL_ONLY:
                for integ in INTEGRATORS:
                    for count in COUNTS:
                        extra = ["--spp", "4", "--set", f"vpl.count={count}"]
                        cells = [cell(scene, ref, integ, smp, clamp, extra, str(count))
                                 for smp in SAMPLERS]
                        rows.append((scene, integ + label, str(count), cells, integ == "vpl"))
                        print(rows[-1], flush=True)
            extra = ["--spp", "1024", "--time-limit", str(EQUAL_TIME), "--set", "vpl.count=1024"]
            cells = [cell(scene, ref, "vpl", smp, clamp, extra, "eqt") for smp in SAMPLERS]
            rows.append((scene, "vpl, equal time" + label, f"1024, {EQUAL_TIME:g} s", cells,
                         False))
            print(rows[-1], flush=True)
    print("| scene | integrator | VPLs | " + " | ".join(SAMPLERS) + " |")
    print("|---|---|---|" + "---|" * len(SAMPLERS))
    for scene, integ, count, cells, show in rows:
        print(f"| {scene} | {integ} | {count} | " +
              " | ".join(fmt_cell(c, show) for c in cells) + " |")


if __name__ == "__main__":
    main()
