#!/usr/bin/env python3
"""Reconstruction cuts (issue 13, item 5): `lightcuts` on the kitchen at 320x180 with and without
`lightcuts.reconstruct`, at the same lightcuts.error, spp and seed; CPU seconds of the render
process (user + system, from the OS: the machine is shared, so wall time is not compared), relMSE
against the converged `path` reference (`manylight diff`), shadow rays per pixel and the share of
samples reconstructed (--stats). The configurations alternate within each seed, so that a change
of the machine's load falls on all of them alike.

relMSE x CPU s is the figure of merit at equal error: where the error is mostly noise
(relMSE ~ 1/spp), a config that is k times cheaper at the same relMSE takes k times the samples
in the same CPU time.

Usage:
  bench/reconstruction_cuts.py [--ref /work/refs/kitchen-path-320x180-4096spp.exr] [--spp 4]
                               [--seeds 1,2] [--blocks 0,2,4,8] [--error 0.1] [--bin build/manylight]
"""
import argparse
import json
import os
import re
import resource
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "..", "shared", "scenes", "kitchen", "scene-v4.pbrt")


def cpu_seconds():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ref", default="/work/refs/kitchen-path-320x180-4096spp.exr")
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--blocks", default="0,2,4,8")
    ap.add_argument("--error", default="0.1")
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "manylight"))
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for seed in [int(s) for s in a.seeds.split(",")]:
            for block in [int(b) for b in a.blocks.split(",")]:
                out = os.path.join(tmp, f"r{block}-{seed}.exr")
                cmd = [a.bin, "render", SCENE, "--integrator", "lightcuts", "--threads", "2",
                       "--resolution", "320x180", "-q", "--spp", str(a.spp), "--seed", str(seed),
                       "--set", f"lightcuts.error={a.error}",
                       "--set", f"lightcuts.reconstruct={block}",
                       "-o", out, "--stats", out + ".json"]
                t0 = cpu_seconds()
                subprocess.run(cmd, check=True)
                cpu = cpu_seconds() - t0
                with open(out + ".json") as f:
                    lc = json.load(f)["lightcuts"]
                d = subprocess.run([a.bin, "diff", out, a.ref], check=True, capture_output=True,
                                   text=True).stdout
                rel = float(re.search(r"relMSE (\S+)", d).group(1))
                recon = lc.get("reconstruction", {}).get("reconstructed_fraction", 0.0)
                rows.append((block, seed, cpu, rel, lc["shadow_rays_per_pixel"], recon))
                print(f"block {block} seed {seed}: {cpu:.1f} CPU s, relMSE {rel:.4f}, "
                      f"{lc['shadow_rays_per_pixel']:.0f} shadow rays/pixel, "
                      f"{100 * recon:.0f}% reconstructed", flush=True)
    lines = ["| lightcuts.reconstruct | seed | CPU s | relMSE | relMSE x CPU s | shadow rays / pixel "
             "| reconstructed |", "|---|---|---|---|---|---|---|"]
    for block, seed, cpu, rel, rays, recon in rows:
        lines.append(f"| {block} | {seed} | {cpu:.1f} | {rel:.4f} | {rel * cpu:.3f} | {rays:.0f} "
                     f"| {100 * recon:.0f}% |")
    for block in dict.fromkeys(r[0] for r in rows):
        rs = [r for r in rows if r[0] == block]
        cpu = sum(r[2] for r in rs) / len(rs)
        rel = sum(r[3] for r in rs) / len(rs)
        rays = sum(r[4] for r in rs) / len(rs)
        lines.append(f"| **{block}, mean** | | {cpu:.1f} | {rel:.4f} | {rel * cpu:.3f} | {rays:.0f} "
                     f"| |")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
