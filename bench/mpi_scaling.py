#!/usr/bin/env python3
"""Issue 18: scaling from 1 to 2 MPI ranks on one machine, and the traffic of a frame.

Alternates, `--repeat` times in one run (the machine is shared: compare ratios, not seconds):
  1 process x 1 thread | mpirun -np 2, 1 thread each | 1 process x 2 threads (the same cores)
for each integrator, on the built-in Cornell box. Prints wall and render seconds (--stats) and
the images' agreement with the 1-process render (`manylight diff`).
Usage: bench/mpi_scaling.py [--repeat N] [--resolution WxH] [--spp N]
"""
import argparse
import json
import os
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "manylight")


def mpirun(n):
    cmd = ["mpirun", "-np", str(n), "--oversubscribe"]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    return cmd


def render(prefix, args, out):
    cmd = prefix + [BIN, "render", "-q"] + args + ["-o", out, "--stats", out + ".json"]
    t0 = time.monotonic()
    subprocess.run(cmd, check=True)
    wall = time.monotonic() - t0
    with open(out + ".json") as f:
        stats = json.load(f)
    return wall, stats


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--resolution", default="200x150")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--integrators", default="path,lighttracer,mdlightcuts")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="mpi-scaling-")
    print(f"# {a.resolution}, {a.spp} spp, seed 1, the built-in Cornell box; {a.repeat} rounds")
    print("| integrator | 1 process, 1 thread | 2 ranks x 1 thread | 1 process, 2 threads "
          "| speed-up 2 ranks | 2 ranks / 2 threads | image vs 1 process |")
    print("|---|---|---|---|---|---|---|")
    for integ in a.integrators.split(","):
        base = ["--integrator", integ, "--resolution", a.resolution, "--spp", str(a.spp),
                "--seed", "1"]
        if integ == "mdlightcuts":
            base += ["--set", "vpl.count=10000"]
        times = {"one": [], "mpi": [], "two": []}
        for _ in range(a.repeat):
            o1 = os.path.join(tmp, integ + "-1.pfm")
            w, s = render([], base + ["--threads", "1"], o1)
            times["one"].append((w, s["seconds"]["render"]))
            o2 = os.path.join(tmp, integ + "-mpi.pfm")
            w, s = render(mpirun(2), base + ["--threads", "1"], o2)
            times["mpi"].append((w, s["seconds"]["render"]))
            o3 = os.path.join(tmp, integ + "-t2.pfm")
            w, s = render([], base + ["--threads", "2"], o3)
            times["two"].append((w, s["seconds"]["render"]))
        d = subprocess.run([BIN, "diff", o1, o2], capture_output=True, text=True).stdout
        same = d.splitlines()[0] if d else "?"
        med = {k: sorted(v, key=lambda x: x[1])[len(v) // 2] for k, v in times.items()}
        fmt = lambda t: f"{t[1]:.2f} s (wall {t[0]:.2f} s)"
        print(f"| {integ} | {fmt(med['one'])} | {fmt(med['mpi'])} | {fmt(med['two'])} | "
              f"{med['one'][1] / med['mpi'][1]:.2f}x | {med['mpi'][1] / med['two'][1]:.2f} | "
              f"{same} |")


if __name__ == "__main__":
    main()
