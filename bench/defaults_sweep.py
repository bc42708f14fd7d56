#!/usr/bin/env python3
"""The sweep behind the default settings of `lightcuts` and `mdlightcuts` (issue 13, item 3).

Renders each scene at a small resolution with a list of settings (the old defaults, then one
change at a time) and measures relMSE and the channel means against a reference (our `path`
at high spp, --max-depth 17), the CPU seconds of the whole process (load, light set, tree and
render; CPU time, not wall time, because the machine is shared) and the fraction of cuts that
reached max_cut. relMSE x CPU s is the figure of merit where the error is mostly noise (the
error of an unbiased render falls as 1 / time).

Usage:
  bench/defaults_sweep.py --scene kitchen --ref build/sweep/ref_kitchen.exr [--res 160x90]
                          [--bin build/manylight] [--only NAME,...]
Prints a markdown table.
"""
import argparse
import json
import os
import resource
import subprocess
import tempfile

SCENES = {
    "kitchen": "../shared/scenes/kitchen/scene-v4.pbrt",
    "cornell-box": "../shared/scenes/cornell-box/scene-v4.pbrt",
}

# The old defaults written out, so that the rows stay meaningful whatever the defaults become.
OLD = ["vpl.count=10000", "vpl.glossy=bsdf", "lights.direct=points", "vpl.clamp=0"]
NEW_LIGHTS = ["vpl.glossy=diffuse", "lights.direct=sample", "vpl.clamp=0.2"]
MD_OLD = ["mdlightcuts.samples=16", "mdlightcuts.error=0.02", "mdlightcuts.max_cut=2000"]
MD_BENCH = ["mdlightcuts.samples=32", "mdlightcuts.error=0.05", "mdlightcuts.max_cut=200"]
LC_OLD = ["lightcuts.error=0.02", "lightcuts.max_cut=1000"]


def settings(*groups):
    """Later settings override earlier ones of the same key."""
    out = {}
    for g in groups:
        for kv in g:
            k, v = kv.split("=", 1)
            out[k] = v
    return [f"{k}={v}" for k, v in out.items()]


CONFIGS = [
    # name, integrator, spp, settings
    ("md: old defaults", "mdlightcuts", 32, settings(OLD, MD_OLD)),
    ("md: + glossy=diffuse", "mdlightcuts", 32, settings(OLD, MD_OLD, ["vpl.glossy=diffuse"])),
    ("md: + direct=sample", "mdlightcuts", 32,
     settings(OLD, MD_OLD, ["vpl.glossy=diffuse", "lights.direct=sample"])),
    ("md: + clamp 0.2", "mdlightcuts", 32, settings(OLD, MD_OLD, NEW_LIGHTS)),
    ("md: + 32/0.05/200", "mdlightcuts", 32, settings(OLD, NEW_LIGHTS, MD_BENCH)),
    ("md: + 100k VPLs", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000"])),
    ("md: 100k, clamp 0", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000", "vpl.clamp=0"])),
    ("md: 100k, clamp 0.05", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000", "vpl.clamp=0.05"])),
    ("md: 100k, error 0.02", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000", "mdlightcuts.error=0.02"])),
    ("md: 100k, error 0.1", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000", "mdlightcuts.error=0.1"])),
    ("md: 100k, max_cut 500", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000", "mdlightcuts.max_cut=500"])),
    ("md: 100k, samples 16", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000", "mdlightcuts.samples=16"])),
    ("md: 100k, samples 64", "mdlightcuts", 64,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000", "mdlightcuts.samples=64"])),
    ("md: 100k, error 0.05, max_cut 1000", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000", "mdlightcuts.max_cut=1000"])),
    ("md: 100k, error 0.05, max_cut 2000", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000", "mdlightcuts.max_cut=2000"])),
    ("md: 100k, error 0.1, max_cut 1000", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH,
              ["vpl.count=100000", "mdlightcuts.error=0.1", "mdlightcuts.max_cut=1000"])),
    ("md: 100k, error 0.2, max_cut 1000", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH,
              ["vpl.count=100000", "mdlightcuts.error=0.2", "mdlightcuts.max_cut=1000"])),
    ("md: 100k, error 0.1, max_cut 4000", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH,
              ["vpl.count=100000", "mdlightcuts.error=0.1", "mdlightcuts.max_cut=4000"])),
    ("md: 100k, error 0.05, max_cut 1000, tighten 8", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH,
              ["vpl.count=100000", "mdlightcuts.max_cut=1000", "mdlightcuts.tighten=8"])),
    ("md: 10k, error 0.05, max_cut 1000", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["mdlightcuts.max_cut=1000"])),
    ("md: 100k, error 0.1, max_cut 1000, maxdepth 8", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000", "mdlightcuts.error=0.1",
                                          "mdlightcuts.max_cut=1000", "mdlightcuts.maxdepth=8"])),
    ("md: 100k, error 0.1, max_cut 1000, maxdepth 17", "mdlightcuts", 32,
     settings(OLD, NEW_LIGHTS, MD_BENCH, ["vpl.count=100000", "mdlightcuts.error=0.1",
                                          "mdlightcuts.max_cut=1000", "mdlightcuts.maxdepth=17"])),
    ("lc: old defaults", "lightcuts", 4, settings(OLD, LC_OLD)),
    ("lc: + glossy, direct, clamp", "lightcuts", 4, settings(OLD, LC_OLD, NEW_LIGHTS)),
    ("lc: + 100k VPLs", "lightcuts", 4, settings(OLD, LC_OLD, NEW_LIGHTS, ["vpl.count=100000"])),
    ("lc: 100k, error 0.05", "lightcuts", 4,
     settings(OLD, LC_OLD, NEW_LIGHTS, ["vpl.count=100000", "lightcuts.error=0.05"])),
    ("lc: 100k, max_cut 200", "lightcuts", 4,
     settings(OLD, LC_OLD, NEW_LIGHTS, ["vpl.count=100000", "lightcuts.max_cut=200"])),
    ("lc: 100k, error 0.05, max_cut 200", "lightcuts", 4,
     settings(OLD, LC_OLD, NEW_LIGHTS,
              ["vpl.count=100000", "lightcuts.error=0.05", "lightcuts.max_cut=200"])),
    ("lc: 10k, error 0.05", "lightcuts", 4,
     settings(OLD, LC_OLD, NEW_LIGHTS, ["lightcuts.error=0.05"])),
    ("lc: 100k, error 0.1", "lightcuts", 4,
     settings(OLD, LC_OLD, NEW_LIGHTS, ["vpl.count=100000", "lightcuts.error=0.1"])),
    ("lc: 10k, error 0.05, max_cut 200", "lightcuts", 4,
     settings(OLD, LC_OLD, NEW_LIGHTS, ["lightcuts.error=0.05", "lightcuts.max_cut=200"])),
    ("defaults (no --set)", "mdlightcuts", 32, []),
    ("defaults (no --set)", "lightcuts", 4, []),
    ("path", "path", 64, []),
]


def run_one(binary, scene, res, ref, name, integrator, spp, sets, tmp, seed):
    out = os.path.join(tmp, "out.exr")
    stats = os.path.join(tmp, "out.json")
    cmd = [binary, "render", scene, "--integrator", integrator, "--resolution", res, "--spp",
           str(spp), "--seed", str(seed), "--threads", "2", "-q", "-o", out, "--stats", stats]
    if integrator == "path":
        cmd += ["--max-depth", "17"]
    for s in sets:
        cmd += ["--set", s]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)}\n{r.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    d = json.loads(subprocess.run([binary, "diff", "--json", out, ref], capture_output=True,
                                  text=True, check=True).stdout)
    st = json.load(open(stats))
    extra = st.get(integrator, {})
    return {
        "name": name, "integrator": integrator, "spp": st["spp"], "cpu": cpu,
        "render": st["seconds"]["render"], "relmse": d["relmse"],
        "means": " ".join(f"{100 * m:+.1f}%" for m in d["mean_rel_diff"]),
        "cut": extra.get("avg_cut_size"), "capped": extra.get("capped_fraction"),
        "sets": " ".join(sets),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", required=True, choices=sorted(SCENES))
    ap.add_argument("--ref", required=True)
    ap.add_argument("--res", default="160x90")
    ap.add_argument("--bin", default="build/manylight")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--only", default="", help="row names (prefixes), separated by semicolons")
    a = ap.parse_args()
    only = [s for s in a.only.split(";") if s]
    print(f"{a.scene} {a.res}, seed {a.seed}, reference {a.ref}\n")
    print("| settings | integrator | spp | CPU s | render s | relMSE | relMSE x CPU s | "
          "channel means | avg cut | capped |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, integ, spp, sets in CONFIGS:
            if only and not any(name.startswith(o) for o in only):
                continue
            r = run_one(a.bin, SCENES[a.scene], a.res, a.ref, name, integ, spp, sets, tmp,
                        a.seed)
            cut = "" if r["cut"] is None else f"{r['cut']:.0f}"
            capped = "" if r["capped"] is None else f"{100 * r['capped']:.1f}%"
            print(f"| {name} | {integ} | {r['spp']} | {r['cpu']:.1f} | {r['render']:.1f} | "
                  f"{r['relmse']:.4f} | {r['relmse'] * r['cpu']:.3f} | {r['means']} | {cut} | "
                  f"{capped} |", flush=True)


if __name__ == "__main__":
    main()
