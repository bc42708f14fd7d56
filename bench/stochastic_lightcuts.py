#!/usr/bin/env python3
"""Stochastic lightcuts on the kitchen at equal time (issue 13, item 6).

1. --sweep: `stochasticlightcuts` with each cut size (stochasticlightcuts.cut) under the same
   --time-limit, the rest at defaults, to choose the default.
2. Then `stochasticlightcuts`, `lightcuts`, `mdlightcuts` (their defaults) and `path`, alternated
   in rounds (one render of each per round, seed = round), each under the same --time-limit, at
   320x180 on 2 threads.

3. --cpu: fixed sample counts instead of a time limit, with each process's CPU time (user + system)
   measured: on a shared machine the time limit gives whatever CPU share the others leave, CPU
   time does not depend on it. For an unbiased estimator relMSE x CPU seconds is about constant
   (variance falls as 1/samples): lower is better.

Every image is compared with the reference by `manylight diff --json --block 16` (relMSE, channel
means against the reference, worst 16x16 block). The time limit counts preparation (VPLs, tree),
so this is equal wall time per process. Prints markdown tables.

Usage:
  bench/stochastic_lightcuts.py [--seconds 10] [--sweep 4,8,16,32,64] [--rounds 2]
      [--ref /work/refs/kitchen-path-320x180-4096spp.exr] [--bin build/manylight]
  bench/stochastic_lightcuts.py --cpu stochasticlightcuts:16=8,path=32,lightcuts=1 --rounds 1
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from many_light_equal_time import RES, diff, scene_path  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def cpu_seconds():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def render(a, tmp, tag, integ, seed, extra, spp=None):
    out = os.path.join(tmp, f"{tag}-{seed}.exr".replace(" ", "_").replace("=", ""))
    stats = out + ".json"
    budget = ["--spp", str(spp)] if spp else ["--time-limit", str(a.seconds)]
    cmd = [a.bin, "render", scene_path("kitchen"), "--integrator", integ, "--resolution", RES,
           "--threads", "2", "--seed", str(seed), "-q", "-o", out, "--stats", stats] + budget + extra
    t0, c0 = time.time(), cpu_seconds()
    subprocess.run(cmd, check=True)
    wall = time.time() - t0
    cpu = cpu_seconds() - c0
    st = json.load(open(stats))
    d = diff(a.bin, out, a.ref)
    cut = st.get("stochasticlightcuts", st.get("lightcuts", {})).get("avg_cut_size", "")
    row = (tag, seed, wall, st.get("spp", 0), d, cut, cpu)
    print(f"{tag} seed {seed}: {wall:.1f} s, {cpu:.1f} CPU s, {row[3]} spp, relMSE "
          f"{d['relmse']:.4f}, means "
          + " ".join(f"{100 * m:+.2f}%" for m in d["mean_rel_diff"])
          + f", worst block {100 * d['worst_block_rel_diff']:.1f}%", flush=True)
    return row


def table(rows):
    lines = ["| run | seed | wall s | CPU s | spp | avg cut | relMSE | relMSE x CPU s | channel means "
             "| worst 16x16 block |", "|---|---|---|---|---|---|---|---|---|---|"]
    for tag, seed, wall, spp, d, cut, cpu in rows:
        cut = f"{cut:.1f}" if isinstance(cut, float) else str(cut)
        lines.append(f"| {tag} | {seed} | {wall:.1f} | {cpu:.1f} | {spp} | {cut} | "
                     f"{d['relmse']:.4f} | {d['relmse'] * cpu:.2f} | "
                     + " ".join(f"{100 * m:+.2f}%" for m in d["mean_rel_diff"])
                     + f" | {100 * d['worst_block_rel_diff']:.1f}% |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=10)
    ap.add_argument("--sweep", default="4,8,16,32,64")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--ref", default="/work/refs/kitchen-path-320x180-4096spp.exr")
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "manylight"))
    ap.add_argument("--cpu", default="", help="fixed-spp runs instead of --time-limit: "
                    "integrator[:cut]=spp,... e.g. stochasticlightcuts:16=8,path=32")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp()
    if a.cpu:
        rows = []
        for r in range(1, a.rounds + 1):
            for item in a.cpu.split(","):
                name, spp = item.split("=")
                integ, _, cut = name.partition(":")
                extra = ["--set", f"stochasticlightcuts.cut={cut}"] if cut else []
                rows.append(render(a, tmp, name, integ, r, extra, spp=int(spp)))
        print(table(rows), flush=True)
        return
    if a.sweep:
        rows = [render(a, tmp, f"stochasticlightcuts cut={c}", "stochasticlightcuts", 1,
                       ["--set", f"stochasticlightcuts.cut={c}"]) for c in a.sweep.split(",")]
        print(table(rows), flush=True)
    rows = []
    for r in range(1, a.rounds + 1):
        for integ in ("stochasticlightcuts", "lightcuts", "mdlightcuts", "path"):
            rows.append(render(a, tmp, integ, integ, r, []))
    if rows:
        print(table(rows), flush=True)


if __name__ == "__main__":
    main()
