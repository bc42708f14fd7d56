#!/usr/bin/env python3
"""Stochastic lightcuts on a stage of coloured spot lights (issue 34, item 5): relMSE against a
converged `path` reference, at equal samples and at equal time, for `path` and each binary's
`stochasticlightcuts` (before and after a change: --bins before=A,after=B), at 160x90 on 2
threads, seeds 1 .. --rounds. Also the CPU seconds (user + system) of each process, which do not
depend on what else the machine runs, and the image's channel means against the reference.
The scene is bench/spot_stage_scene.py's (192 spots unless --spots). Prints a markdown table.

Usage:
  bench/stochastic_spots.py --bins before=/tmp/ml-before,after=build/manylight
      [--spp 16] [--seconds 10] [--rounds 2] [--ref-spp 2048] [--refs build/refs]
      [--integrators path,stochasticlightcuts,lightcuts]
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from many_light_equal_time import diff  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RES = "160x90"


def cpu_seconds():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bins", default=f"after={os.path.join(ROOT, 'build', 'manylight')}")
    ap.add_argument("--integrators", default="path,stochasticlightcuts")
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--seconds", type=float, default=10)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--spots", type=int, default=192)
    ap.add_argument("--ref-spp", type=int, default=2048)
    ap.add_argument("--refs", default=os.path.join(ROOT, "build", "refs"))
    ap.add_argument("--no-time", action="store_true", help="equal samples only")
    a = ap.parse_args()
    bins = dict(kv.split("=", 1) for kv in a.bins.split(","))
    last_bin = list(bins.values())[-1]
    tmp = tempfile.mkdtemp(prefix="spots-")
    scene = os.path.join(tmp, "spots.pbrt")
    with open(scene, "w") as f:
        subprocess.run([sys.executable, os.path.join(ROOT, "bench", "spot_stage_scene.py"),
                        str(a.spots)], stdout=f, check=True)
    ref = os.path.join(a.refs, f"spots{a.spots}-path-{RES}-{a.ref_spp}spp.exr")
    if not os.path.exists(ref):
        os.makedirs(a.refs, exist_ok=True)
        print(f"rendering the reference {ref} ...", flush=True)
        subprocess.run([last_bin, "render", scene, "--integrator", "path", "--resolution", RES,
                        "--spp", str(a.ref_spp), "--seed", "4242", "--threads", "2", "-q", "-o",
                        ref], check=True)
    rows = []
    budgets = [("spp", ["--spp", str(a.spp)])]
    if not a.no_time:
        budgets.append(("time", ["--time-limit", str(a.seconds)]))
    for budget, args in budgets:
        for seed in range(1, a.rounds + 1):
            for integ in a.integrators.split(","):
                for tag, binary in bins.items():
                    if integ == "path" and binary != last_bin:
                        continue  # path is the same in every binary
                    out = os.path.join(tmp, f"{integ}-{tag}-{budget}-{seed}.exr")
                    c0 = cpu_seconds()
                    subprocess.run([binary, "render", scene, "--integrator", integ,
                                    "--resolution", RES, "--threads", "2", "--seed", str(seed),
                                    "-q", "-o", out, "--stats", out + ".json"] + args, check=True)
                    cpu = cpu_seconds() - c0
                    spp = json.load(open(out + ".json")).get("spp", 0)
                    d = diff(binary, out, ref)
                    name = integ if integ == "path" else f"{integ} ({tag})"
                    rows.append((budget, name, seed, spp, cpu, d["relmse"], d["mean_rel_diff"]))
                    print(f"{budget} {name} seed {seed}: {spp} spp, {cpu:.1f} CPU s, relMSE "
                          f"{d['relmse']:.4f}, means "
                          + " ".join(f"{100 * m:+.2f}%" for m in d["mean_rel_diff"]), flush=True)
    print(f"\n{a.spots} spots, {RES}, 2 threads, reference `path` {a.ref_spp} spp; "
          f"seeds 1..{a.rounds}, means over seeds\n")
    print("| budget | integrator | spp | CPU s | relMSE | relMSE / path's | relMSE x CPU s | "
          "channel means (r / g / b) |")
    print("|---|---|---|---|---|---|---|---|")
    for budget, _ in budgets:
        sel = [r for r in rows if r[0] == budget]
        names = list(dict.fromkeys(r[1] for r in sel))
        path_rel = None
        stats = {}
        for name in names:
            rs = [r for r in sel if r[1] == name]
            k = len(rs)
            stats[name] = (sum(r[3] for r in rs) / k, sum(r[4] for r in rs) / k,
                           sum(r[5] for r in rs) / k,
                           [sum(r[6][c] for r in rs) / k for c in range(3)])
            if name == "path":
                path_rel = stats[name][2]
        for name in names:
            spp, cpu, rel, means = stats[name]
            ratio = f"{rel / path_rel:.2f}x" if path_rel else ""
            label = f"{a.spp} spp" if budget == "spp" else f"{a.seconds:g} s"
            print(f"| {label} | `{name}` | {spp:.0f} | {cpu:.1f} | {rel:.4f} | {ratio} | "
                  f"{rel * cpu:.3f} | " + " / ".join(f"{100 * m:+.2f}%" for m in means) + " |")


if __name__ == "__main__":
    main()
