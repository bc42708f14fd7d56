#!/usr/bin/env python3
"""Every integrator at equal time, with its defaults (issue 13, item 4).

For each scene, renders every integrator the binary has (or --integrators) with no --set, at
320x180 on 2 threads under --time-limit, and compares with a converged reference of our own
(`path` at 4096 spp, same resolution, the scene's maxdepth; made when missing, which takes
about 45 minutes per scene on two shared cores). Prints, per render: the wall time of the whole
process (load, light set, trees and render: what a user waits), relMSE
(mean((x - r)^2 / (r^2 + 0.01))), each channel's mean against the reference, and the worst 16x16
block (whole blocks, per channel, blocks whose reference mean is at least 0.01), and whether the
issue's goal holds (relMSE <= 0.05, every channel within 1%, no block over 10%). Appends the
table with the command to bench/RESULTS.md unless --no-append.

Usage:
  bench/many_light_equal_time.py [--scenes kitchen:10,classroom:20,veach-ajar:20]
      [--integrators path,mdlightcuts,...] [--refs /work/refs] [--seed 1]
      [--bin build/manylight] [--no-append]
"""
import argparse
import json
import os
import re
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared")
RES = "320x180"
REF_SPP = 4096


def available_integrators(binary):
    r = subprocess.run([binary, "render", "--help"], capture_output=True, text=True)
    m = re.search(r"one of: ([a-z0-9_, ]+)", r.stdout + r.stderr)
    return [n.strip() for n in m.group(1).split(",")] if m else []


def scene_path(name):
    return os.path.join(SHARED, "scenes", name, "scene-v4.pbrt")


def reference(binary, name, refs):
    path = os.path.join(refs, f"{name}-path-{RES}-{REF_SPP}spp.exr")
    if not os.path.exists(path):
        os.makedirs(refs, exist_ok=True)
        print(f"rendering the reference {path} ...", flush=True)
        subprocess.run([binary, "render", scene_path(name), "--integrator", "path", "--resolution",
                        RES, "--spp", str(REF_SPP), "--seed", "4242", "--threads", "2", "-q",
                        "-o", path], check=True)
    return path


def diff(binary, image, ref):
    out = subprocess.run([binary, "diff", "--json", "--block", "16", image, ref], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenes", default="kitchen:10,classroom:20,veach-ajar:20")
    ap.add_argument("--integrators", default="")
    ap.add_argument("--refs", default=os.path.join(ROOT, "build", "refs"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "manylight"))
    ap.add_argument("--no-append", action="store_true")
    a = ap.parse_args()
    integrators = a.integrators.split(",") if a.integrators else [
        i for i in available_integrators(a.bin) if i not in ("whitted", "direct")]
    rows = []
    tmp = tempfile.mkdtemp()
    for item in a.scenes.split(","):
        name, seconds = item.split(":")
        ref = reference(a.bin, name, a.refs)
        for integ in integrators:
            out = os.path.join(tmp, f"{name}-{integ}.exr")
            stats = os.path.join(tmp, f"{name}-{integ}.json")
            cmd = [a.bin, "render", scene_path(name), "--integrator", integ, "--resolution", RES,
                   "--threads", "2", "--seed", str(a.seed), "--time-limit", seconds, "-q", "-o",
                   out, "--stats", stats]
            t0 = time.time()
            r = subprocess.run(cmd, capture_output=True, text=True)
            wall = time.time() - t0
            if r.returncode != 0:
                rows.append((name, seconds, integ, wall, None, r.stderr.strip()[-200:]))
                print(rows[-1], flush=True)
                continue
            d = diff(a.bin, out, ref)
            spp = json.load(open(stats)).get("spp", 0)
            rows.append((name, seconds, integ, wall, d, spp))
            print(f"{name} {integ}: {wall:.1f} s, relMSE {d['relmse']:.4f}, means "
                  + " ".join(f"{100 * m:+.2f}%" for m in d["mean_rel_diff"])
                  + f", worst block {100 * d['worst_block_rel_diff']:.1f}%", flush=True)
    lines = ["| scene | limit | integrator | wall s | spp | relMSE | channel means | worst 16x16 "
             "block | goal |", "|---|---|---|---|---|---|---|---|---|"]
    for name, seconds, integ, wall, d, extra in rows:
        if d is None:
            lines.append(f"| {name} | {seconds} s | {integ} | {wall:.1f} | | failed: {extra} | | | |")
            continue
        goal = (d["relmse"] <= 0.05 and all(abs(m) <= 0.01 for m in d["mean_rel_diff"])
                and d["worst_block_rel_diff"] <= 0.10)
        lines.append(
            f"| {name} | {seconds} s | {integ} | {wall:.1f} | {extra} | {d['relmse']:.4f} | "
            + " ".join(f"{100 * m:+.2f}%" for m in d["mean_rel_diff"])
            + f" | {100 * d['worst_block_rel_diff']:.1f}% | {'met' if goal else 'no'} |")
    table = "\n".join(lines)
    print(table)
    if not a.no_append:
        with open(os.path.join(ROOT, "bench", "RESULTS.md"), "a") as f:
            f.write(f"\n### {time.strftime('%Y-%m-%d')}: `bench/many_light_equal_time.py "
                    f"--scenes {a.scenes}`\n\n{table}\n")


if __name__ == "__main__":
    main()
