#!/usr/bin/env python3
"""The VPL samplers (issue 15): relMSE against a converged BDPT reference of ours.

Scenes: veach-ajar and veach-bidir (light arriving by indirect paths) at 64x36, cornell-box at
48x48. Reference: `bdpt` at the same resolution, --ref-spp (4096) spp, seed 97 (kept in TMP
between runs); its own relMSE is estimated from a second, independent BDPT render of 256 spp
(seed 99): relMSE(256 vs ref) * 256 / ref_spp.
Each sampler at --counts VPLs through `vpl` (4 spp) and `mdlightcuts` (4 spp, one pass of 32),
--seeds (1 and 2), relMSE averaged; with it, from `vpl`'s --stats, the VPL point lights (distinct
VPLs: bidirectional merges a candidate drawn k times into one) and the share of them that light
some gather point. Then equal time: `vpl` with 1024 VPLs under --time-limit EQUAL_TIME seconds.
Every cell with the defaults (vpl.clamp=0.2) or, with --clamps=default,0, also with
vpl.clamp=0 (no clamping bias).

With --budget, a second equal-time mode: each integrator under --time-limit with vpl.count left
out (mdlightcuts unless --budget-integrators says; `vpl`'s pass grows with the count), so that the
VPL build fits its share of the time (manylight/vpl_budget.h) and a sampler that
needs fewer VPLs for an image gets more pixel passes; the cell then shows the VPL count used.

Usage: bench/vpl_samplers.py [--scenes=veach-ajar,...] [--counts=256,1024,4096]
  [--samplers=standard,power,bidirectional,metropolis,metropolis:4] [--integrators=vpl,mdlightcuts]
  [--ref-spp=4096] [--clamps=default,0] [--equal-only] [--no-equal] [--budget] [--time=4]
  [--budget-integrators=mdlightcuts]
  [--seeds=1,2] [--out=DIR]
(prints markdown tables; metropolis:K sets vpl.metropolis.tries=K, and metropolis:K/cC/lP/kB also
vpl.metropolis.chains=C, vpl.metropolis.large_step=P and vpl.metropolis.cap=B; --out: where the renders go, TMP's
reference stays where it is)
"""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("MANYLIGHT_BIN", os.path.join(ROOT, "build", "manylight"))
SCENES = os.path.join(ROOT, "..", "shared", "scenes")
TMP = "/tmp/vpl_samplers_bench"
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
NO_EQUAL = "--no-equal" in sys.argv
BUDGET = "--budget" in sys.argv
BUDGET_INTEGRATORS = arg("budget-integrators", "mdlightcuts").split(",")
EQUAL_TIME = float(arg("time", "4"))
OUT = arg("out", TMP)


def sampler_args(smp):
    """'metropolis:4' is metropolis with vpl.metropolis.tries=4; '/c16' adds 16 chains, '/l0.5'
    a large-step probability of 0.5 and '/k0' vpl.metropolis.cap=0."""
    name, _, rest = smp.partition(":")
    args = ["--set", f"vpl.sampler={name}"]
    parts = rest.split("/") if rest else []
    keys = {"c": "chains", "l": "large_step", "k": "cap"}
    for i, p in enumerate(parts):
        if i == 0 and p:
            args += ["--set", f"vpl.metropolis.tries={p}"]
        elif i > 0:
            args += ["--set", f"vpl.metropolis.{keys[p[0]]}={p[1:]}"]
    return args


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
        name = smp.replace("/", "_")
        out = os.path.join(OUT, f"{scene}-{integ}-{name}{c}-{tag}-{seed}.exr")
        args = ["--integrator", integ, "--seed", str(seed)] + extra + sampler_args(smp)
        if clamp is not None:
            args += ["--set", f"vpl.clamp={clamp}"]
        st = render(scene, out, args)
        errs.append(relmse(out, ref))
        secs.append(st["seconds"]["render"])
        v = st.get("vpl")
        if tag == "budget":
            lights.append(used_vpls(st))
            lit.append(float("nan"))
        elif v:
            lights.append(v["vpl_lights"])
            lit.append(v["lighting"] / max(1, v["vpl_lights"]))
    mean = lambda x: sum(x) / len(x) if x else float("nan")
    return mean(errs), mean(secs), mean(lights), mean(lit)


def used_vpls(st):
    """The VPL count the time limit left (vpl_count_used, wherever --stats puts it)."""
    if isinstance(st, dict):
        if "vpl_count_used" in st:
            return st["vpl_count_used"]
        for v in st.values():
            n = used_vpls(v)
            if n == n:
                return n
    return float("nan")


def fmt_cell(c, show_vpls):
    e, s, n, f = c
    text = f"{e:.3g} ({s:.1f} s"
    if show_vpls and n == n and f != f:
        text += f"; {n:.0f} VPLs used"
    elif show_vpls and n == n:
        text += f"; {n:.0f} VPLs, {100 * f:.0f}% light"
    return text + ")"


def main():
    os.makedirs(TMP, exist_ok=True)
    os.makedirs(OUT, exist_ok=True)
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
            if not NO_EQUAL:
                extra = ["--spp", "1024", "--time-limit", str(EQUAL_TIME), "--set",
                         "vpl.count=1024"]
                cells = [cell(scene, ref, "vpl", smp, clamp, extra, "eqt") for smp in SAMPLERS]
                rows.append((scene, "vpl, equal time" + label, f"1024, {EQUAL_TIME:g} s", cells,
                             False))
                print(rows[-1], flush=True)
            if BUDGET:
                for integ in BUDGET_INTEGRATORS:
                    extra = ["--spp", "4096", "--time-limit", str(EQUAL_TIME)]
                    cells = [cell(scene, ref, integ, smp, clamp, extra, "budget")
                             for smp in SAMPLERS]
                    rows.append((scene, f"{integ}, equal time, count to the time" + label,
                                 f"{EQUAL_TIME:g} s", cells, True))
                    print(rows[-1], flush=True)
    print("| scene | integrator | VPLs | " + " | ".join(SAMPLERS) + " |")
    print("|---|---|---|" + "---|" * len(SAMPLERS))
    for scene, integ, count, cells, show in rows:
        print(f"| {scene} | {integ} | {count} | " +
              " | ".join(fmt_cell(c, show) for c in cells) + " |")


if __name__ == "__main__":
    main()
