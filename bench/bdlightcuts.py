#!/usr/bin/env python3
"""Bidirectional Lightcuts at equal time (issue 17): `bdlightcuts` (its defaults unless --set
says otherwise) against `mdlightcuts` (defaults), `path` and `bdpt` on the kitchen at 320x180,
each given the same --time-limit, alternated in one run (--repeats rounds), against the shared
reference /work/refs/kitchen-path-320x180-4096spp.exr (our `path`, 4096 spp, seed 4242). Per
integrator: the per-channel means' relative difference and relMSE from
`manylight diff --json --block 16`, and bdlightcuts' relMSE over mdlightcuts'.

Usage: bench/bdlightcuts.py [--seconds 10] [--repeats 1] [--seed 1] [--only bdlightcuts,...]
       [--set KEY=VALUE ...] [--scene PATH] [--ref PATH] [--bin build/manylight]
"""
import argparse
import json
import os
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = "/work/shared/scenes/kitchen/scene-v4.pbrt"
REF = "/work/refs/kitchen-path-320x180-4096spp.exr"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=10)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--only", default="bdlightcuts,mdlightcuts,path,bdpt")
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--scene", default=SCENE)
    ap.add_argument("--ref", default=REF)
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "manylight"))
    a = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="bdlc-bench-")
    rows = {}
    for rep in range(a.repeats):
        for integ in a.only.split(","):
            out = os.path.join(tmp, f"{integ}-{rep}.exr")
            stats = out + ".json"
            cmd = [a.bin, "render", a.scene, "-q", "--integrator", integ, "--resolution",
                   "320x180", "--seed", str(a.seed + rep), "--time-limit", str(a.seconds),
                   "-o", out, "--stats", stats]
            if integ == "bdlightcuts":
                for s in a.set:
                    cmd += ["--set", s]
            subprocess.run(cmd, check=True)
            d = json.loads(subprocess.run([a.bin, "diff", "--json", "--block", "16", out, a.ref],
                                          check=True, capture_output=True, text=True).stdout)
            st = json.load(open(stats))
            rows.setdefault(integ, []).append((d, st))
            print(integ, rep, "relMSE %.4f" % d["relmse"],
                  "means rel diff", ["%+.4f" % x for x in d["mean_rel_diff"]], flush=True)
    print()
    print("| integrator | spp | mean rel diff R | G | B | relMSE |")
    print("|---|---|---|---|---|---|")
    mean_rel = {}
    for integ, rs in rows.items():
        n = len(rs)
        rel = sum(d["relmse"] for d, _ in rs) / n
        mean_rel[integ] = rel
        md = [sum(d["mean_rel_diff"][c] for d, _ in rs) / n for c in range(3)]
        spp = sum(st.get("spp", 0) for _, st in rs) / n
        print(f"| {integ} | {spp:.0f} | {md[0]:+.2%} | {md[1]:+.2%} | {md[2]:+.2%} | {rel:.4f} |")
    if "bdlightcuts" in mean_rel and "mdlightcuts" in mean_rel:
        print("\nbdlightcuts relMSE / mdlightcuts relMSE: %.2f" %
              (mean_rel["bdlightcuts"] / mean_rel["mdlightcuts"]))


if __name__ == "__main__":
    main()
