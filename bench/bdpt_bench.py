#!/usr/bin/env python3
"""Bidirectional path tracing on veach-bidir (issue 4: light tracing and BDPT).

Accuracy: `bdpt` at 256x256, 256 spp (the scene's max depth 7) against pbrt-v4's bdpt render
../shared/references/veach-bidir-bdpt-256-256spp.exr, per-channel means and 16x16 block means
(`manylight diff --block 16`). Goal: within 3% on each channel's mean, 8% on every block.
Speed: `bdpt` at 1024x1024, 8 spp, max depth 7, 2 threads, against pbrt-v4's 172 s for the same
on this machine kind. Goal: at most 0.6x (103 s).

Prints a table and appends it with the commands to bench/history/log.md (the dated log; bench/RESULTS.md keeps the current figures).
Usage: bench/bdpt_bench.py [--quick] [--no-append] [--bin PATH]
"""
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "manylight")
SHARED = os.path.join(ROOT, "..", "shared")
SCENE = os.path.join(SHARED, "scenes/veach-bidir/scene-v4.pbrt")
REFERENCE = os.path.join(SHARED, "references/veach-bidir-bdpt-256-256spp.exr")
PBRT_SECONDS = 172.0  # pbrt-v4 bdpt, 1024x1024, 8 spp, max depth 7, this machine kind


def rel(p):
    return os.path.relpath(p, ROOT) if p.startswith(ROOT) or p.startswith(SHARED) else p


def render(args, tmp, name):
    out = os.path.join(tmp, name + ".exr")
    stats = os.path.join(tmp, name + ".json")
    cmd = [BIN, "render", SCENE, "-q", "--threads", "2", "-o", out, "--stats", stats] + args
    t0 = time.time()
    subprocess.run(cmd, check=True)
    wall = time.time() - t0
    with open(stats) as f:
        s = json.load(f)
    s["wall"] = wall
    s["cmd"] = " ".join(rel(c) for c in cmd).replace(tmp, "OUT")
    return out, s


def diff(a, b, block):
    cmd = [BIN, "diff", a, b, "--json", "--block", str(block)]
    r = subprocess.run(cmd, check=True, capture_output=True, text=True)
    return json.loads(r.stdout)


def main():
    global BIN
    if "--bin" in sys.argv:
        BIN = os.path.abspath(sys.argv[sys.argv.index("--bin") + 1])
    quick = "--quick" in sys.argv
    with tempfile.TemporaryDirectory() as tmp:
        print(f"OUT = {tmp}", file=sys.stderr)
        spp = "16" if quick else "256"
        img, acc = render(["--integrator", "bdpt", "--resolution", "256x256", "--spp", spp,
                           "--max-depth", "7", "--seed", "1"], tmp, "veach256")
        d = diff(img, REFERENCE, 16)
        tres, tspp = ("256x256", "8") if quick else ("1024x1024", "8")
        _, tim = render(["--integrator", "bdpt", "--resolution", tres, "--spp", tspp,
                         "--max-depth", "7", "--seed", "1"], tmp, "veach1024")
    m = d["mean_rel_diff"]
    worst_block = d["worst_block_rel_diff"]
    means_ok = all(abs(x) <= 0.03 for x in m)
    blocks_ok = abs(worst_block) <= 0.08
    lines = []
    lines.append("| run | render s | process wall s | Mrays/s | result | goal |")
    lines.append("|---|---|---|---|---|---|")
    lines.append(f"| veach-bidir 256x256 {spp} spp, bdpt vs pbrt-v4 | {acc['seconds']['render']:.1f} | "
                 f"{acc['wall']:.1f} | {acc['rays_per_second'] / 1e6:.2f} | channel means "
                 f"{100*m[0]:+.2f}% {100*m[1]:+.2f}% {100*m[2]:+.2f}%, worst 16x16 block "
                 f"{100*worst_block:+.1f}%, relMSE {d['relmse']:.4f} | 3% / 8%: "
                 f"{'met' if means_ok and blocks_ok else 'NOT met'} |")
    ratio = tim["wall"] / PBRT_SECONDS
    if quick:
        verdict = "(quick: no peer) | |"
    else:
        verdict = (f"{ratio:.2f}x pbrt-v4's {PBRT_SECONDS:.0f} s (process wall) | 0.6x: "
                   f"{'met' if ratio <= 0.6 else 'NOT met'} |")
    lines.append(f"| veach-bidir {tres} {tspp} spp depth 7, bdpt | {tim['seconds']['render']:.1f} | "
                 f"{tim['wall']:.1f} | {tim['rays_per_second'] / 1e6:.2f} | " + verdict)
    text = "\n".join(lines)
    print(text)
    if "--no-append" not in sys.argv:
        with open(os.path.join(ROOT, "bench", "history", "log.md"), "a") as f:
            f.write(f"\n### {time.strftime('%Y-%m-%d')}: `bench/bdpt_bench.py{' --quick' if quick else ''}`\n\n")
            for s in (acc, tim):
                f.write(f"    {s['cmd']}\n")
            f.write(f"    {rel(BIN)} diff OUT/veach256.exr {rel(REFERENCE)} --block 16\n")
            f.write("\n" + text + "\n")


if __name__ == "__main__":
    main()
