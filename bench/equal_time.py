#!/usr/bin/env python3
"""Equal-time comparison of the unbiased and Metropolis integrators (issue 4).

Renders each scene with each integrator under --time-limit for every budget (seconds of render
time: scene loading and BVH build are not counted; a Metropolis integrator's bootstrap is), then
computes relMSE against the scene's reference with `manylight diff`, prints a table and appends
it with the commands to bench/history/log.md (the dated log; bench/RESULTS.md keeps the current figures).

Usage:
  bench/equal_time.py [--budgets 30,120,480] [--scenes veach-bidir,cornell-box]
                      [--integrators path,bdpt,pssmlt,mlt,cmlt] [--bin build/manylight]
                      [--threads 2] [--seed 1] [--no-append]

Integrators the binary does not have are skipped (and listed). The full default table costs
about (sum of budgets) x scenes x integrators of machine time: 30+120+480 s x 2 x 5 = 1h45.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared")

# Scene, the reference it is compared with (from ../shared/references/, see its README), and the
# settings that reference was rendered with.
SCENES = {
    "veach-bidir": {
        "scene": "scenes/veach-bidir/scene-v4.pbrt",
        "reference": "references/veach-bidir-bdpt-256-256spp.exr",
        "reference_note": "pbrt-v4 bdpt, 256 spp",
        "resolution": "256x256",
        "max_depth": 7,
    },
    "cornell-box": {
        "scene": "scenes/cornell-box/scene-v4.pbrt",
        "reference": "references/cornell-box-path-256-2048spp.exr",
        "reference_note": "pbrt-v4 path, 2048 spp",
        "resolution": "256x256",
        "max_depth": 16,
    },
}


def available_integrators(binary):
    r = subprocess.run([binary, "render", "--help"], capture_output=True, text=True)
    m = re.search(r"one of: ([a-z0-9_, ]+)", r.stdout + r.stderr)
    return set(n.strip() for n in m.group(1).split(",")) if m else set()


def rel(path):
    return os.path.relpath(path, ROOT) if os.path.isabs(path) else path


def render(binary, scene, integrator, budget, args, tmp):
    cfg = SCENES[scene]
    name = f"{scene}-{integrator}-{budget}"
    out = os.path.join(tmp, name + ".exr")
    stats = os.path.join(tmp, name + ".json")
    cmd = [binary, "render", os.path.join(SHARED, cfg["scene"]), "--quiet",
           "--integrator", integrator, "--time-limit", str(budget),
           "--resolution", cfg["resolution"], "--max-depth", str(cfg["max_depth"]),
           "--threads", str(args.threads), "--seed", str(args.seed), "-o", out, "--stats", stats]
    t0 = time.time()
    subprocess.run(cmd, check=True)
    wall = time.time() - t0
    with open(stats) as f:
        s = json.load(f)
    r = subprocess.run([binary, "diff", out, os.path.join(SHARED, cfg["reference"]), "--json"],
                       check=True, capture_output=True, text=True)
    d = json.loads(r.stdout)
    shown = " ".join(rel(c) for c in cmd).replace(tmp, "OUT")
    return {"cmd": shown, "stats": s, "diff": d, "wall": wall}


def work_done(s):
    """Samples per pixel, or mutations per pixel for the Metropolis integrators."""
    for key in ("pssmlt", "mlt", "cmlt"):
        if key in s and "mutations_per_pixel" in s[key]:
            return f"{s[key]['mutations_per_pixel']:.0f} mpp"
    return f"{s['spp']} spp"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--budgets", default="30,120,480")
    p.add_argument("--scenes", default="veach-bidir,cornell-box")
    p.add_argument("--integrators", default="path,bdpt,pssmlt,mlt,cmlt")
    p.add_argument("--bin", default=os.path.join(ROOT, "build", "manylight"))
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--no-append", action="store_true")
    args = p.parse_args()
    budgets = [float(b) if "." in b else int(b) for b in args.budgets.split(",")]
    scenes = args.scenes.split(",")
    for s in scenes:
        if s not in SCENES:
            sys.exit(f"unknown scene {s} (have {', '.join(SCENES)})")
    have = available_integrators(args.bin)
    wanted = args.integrators.split(",")
    integrators = [i for i in wanted if i in have]
    skipped = [i for i in wanted if i not in have]

    results = {}
    commands = []
    with tempfile.TemporaryDirectory() as tmp:
        print(f"OUT = {tmp}", file=sys.stderr)
        for scene in scenes:
            for integrator in integrators:
                for budget in budgets:
                    r = render(args.bin, scene, integrator, budget, args, tmp)
                    results[(scene, integrator, budget)] = r
                    commands.append(r["cmd"])
                    print(f"{scene} {integrator} {budget}s: relMSE {r['diff']['relmse']:.5g} "
                          f"({work_done(r['stats'])}, render {r['stats']['seconds']['render']:.1f} s)",
                          file=sys.stderr)
                    if integrator in r["stats"]:
                        print(f"  {integrator} stats: {json.dumps(r['stats'][integrator])}",
                              file=sys.stderr)

    lines = []
    header = "| scene | integrator | " + " | ".join(f"relMSE @ {b} s" for b in budgets) + \
        " | " + " | ".join(f"work @ {b} s" for b in budgets) + " | mean rel. diff @ " + \
        f"{budgets[-1]} s (R, G, B) |"
    lines.append(header)
    lines.append("|---" * (3 + 2 * len(budgets)) + "|")
    for scene in scenes:
        for integrator in integrators:
            rs = [results[(scene, integrator, b)] for b in budgets]
            m = rs[-1]["diff"]["mean_rel_diff"]
            lines.append(f"| {scene} | {integrator} | " +
                         " | ".join(f"{r['diff']['relmse']:.4g}" for r in rs) + " | " +
                         " | ".join(work_done(r["stats"]) for r in rs) + " | " +
                         f"{100 * m[0]:+.1f}%, {100 * m[1]:+.1f}%, {100 * m[2]:+.1f}% |")
    lines.append("")
    for scene in scenes:
        lines.append(f"Reference for {scene}: `../shared/{SCENES[scene]['reference']}` "
                     f"({SCENES[scene]['reference_note']}).")
    if skipped:
        lines.append(f"Not in this binary, skipped: {', '.join(skipped)}.")
    text = "\n".join(lines)
    print(text)
    if not args.no_append:
        with open(os.path.join(ROOT, "bench", "history", "log.md"), "a") as f:
            f.write(f"\n### {time.strftime('%Y-%m-%d')}: `bench/equal_time.py "
                    f"{' '.join(sys.argv[1:])}`\n\n")
            for c in commands:
                f.write(f"    {c}\n")
            f.write("\n" + text + "\n")


if __name__ == "__main__":
    main()
