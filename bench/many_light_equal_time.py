#!/usr/bin/env python3
"""Every integrator at equal time, with its defaults (issue 13, item 4).

For each scene, renders every integrator the binary has (or --integrators) with no --set, at
320x180 on 2 threads under --time-limit, and compares with a converged reference of our own
(`path` at 4096 spp, same resolution, the scene's maxdepth; made when missing, which takes
about 45 minutes per scene on two shared cores). Prints, per render: the wall time of the whole
process (load, light set, trees and render: what a user waits), relMSE
(mean((x - r)^2 / (r^2 + 0.01))), each channel's mean against the reference, and the worst 16x16
block (whole blocks, per channel, blocks whose reference mean is at least 0.01), and whether the
issue's goal holds (relMSE <= 0.05, every channel within 1%, no block over 10%), and how many
pixels got no sample (a first pass the time limit cut short). Appends the table with the command
to bench/history/log.md (the dated log; bench/RESULTS.md keeps the current figures) unless --no-append.

Settings: --set KEY=VALUE (repeatable) goes to every render; an --integrators entry may carry its
own as NAME+KEY=VALUE+... (a KEY without a dot is NAME's: bdlightcuts+rest=drop is
bdlightcuts.rest=drop), so that A and B of one integrator alternate in one run. --rounds N repeats
the whole run with seeds seed ... seed + N - 1 (A and B alternating within each scene) and adds
each entry's mean over the rounds.

Usage:
  bench/many_light_equal_time.py [--scenes kitchen:10,classroom:20,veach-ajar:20]
      [--integrators path,mdlightcuts,bdlightcuts+rest=drop,...] [--set KEY=VALUE ...]
      [--rounds 1] [--refs /work/refs] [--seed 1] [--bin build/manylight] [--no-append]
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


def parse_entry(entry):
    """NAME+KEY=VALUE+... -> (NAME, ["NAME.KEY=VALUE", ...])."""
    name, *settings = entry.split("+")
    out = []
    for kv in settings:
        if "=" not in kv:
            raise SystemExit(f"--integrators: '{kv}' in '{entry}' is not KEY=VALUE")
        out.append(kv if "." in kv.split("=")[0] else f"{name}.{kv}")
    return name, out


def diff(binary, image, ref):
    out = subprocess.run([binary, "diff", "--json", "--block", "16", image, ref], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenes", default="kitchen:10,classroom:20,veach-ajar:20")
    ap.add_argument("--integrators", default="")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a setting for every render (repeatable)")
    ap.add_argument("--rounds", type=int, default=1, help="repeat with seeds seed, seed + 1, ...")
    ap.add_argument("--refs", default=os.path.join(ROOT, "build", "refs"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "manylight"))
    ap.add_argument("--no-append", action="store_true")
    a = ap.parse_args()
    integrators = a.integrators.split(",") if a.integrators else [
        i for i in available_integrators(a.bin) if i not in ("whitted", "direct")]
    for kv in a.set:
        if "=" not in kv:
            raise SystemExit(f"--set: '{kv}' is not KEY=VALUE")
    rows = []
    tmp = tempfile.mkdtemp()
    for round_ in range(a.rounds):
        seed = a.seed + round_
        for item in a.scenes.split(","):
            name, seconds = item.split(":")
            ref = reference(a.bin, name, a.refs)
            for k, entry in enumerate(integrators):
                integ, settings = parse_entry(entry)
                out = os.path.join(tmp, f"{name}-{k}.exr")
                stats = os.path.join(tmp, f"{name}-{k}.json")
                cmd = [a.bin, "render", scene_path(name), "--integrator", integ, "--resolution",
                       RES, "--threads", "2", "--seed", str(seed), "--time-limit", seconds, "-q",
                       "-o", out, "--stats", stats]
                for kv in a.set + settings:
                    cmd += ["--set", kv]
                t0 = time.time()
                r = subprocess.run(cmd, capture_output=True, text=True)
                wall = time.time() - t0
                if r.returncode != 0:
                    rows.append((name, seconds, entry, seed, wall, None, r.stderr.strip()[-200:]))
                    print(rows[-1], flush=True)
                    continue
                d = diff(a.bin, out, ref)
                st = json.load(open(stats))
                d["spp"] = st.get("spp", 0)
                d["unsampled"] = st.get("film", {}).get("pixels_without_samples", 0)
                rows.append((name, seconds, entry, seed, wall, d, ""))
                print(f"{name}:{seconds} {entry} seed {seed}: {wall:.1f} s, relMSE "
                      f"{d['relmse']:.4f}, means "
                      + " ".join(f"{100 * m:+.2f}%" for m in d["mean_rel_diff"])
                      + f", worst block {100 * d['worst_block_rel_diff']:.1f}%, "
                      f"{d['unsampled']} pixels unsampled", flush=True)
    lines = ["| scene | limit | integrator | seed | wall s | spp | unsampled px | relMSE | "
             "channel means | worst 16x16 block | goal |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, seconds, entry, seed, wall, d, err in rows:
        if d is None:
            lines.append(f"| {name} | {seconds} s | {entry} | {seed} | {wall:.1f} | | | failed: "
                         f"{err} | | | |")
            continue
        goal = (d["relmse"] <= 0.05 and all(abs(m) <= 0.01 for m in d["mean_rel_diff"])
                and d["worst_block_rel_diff"] <= 0.10)
        lines.append(
            f"| {name} | {seconds} s | {entry} | {seed} | {wall:.1f} | {d['spp']} | "
            f"{d['unsampled']} | {d['relmse']:.4f} | "
            + " ".join(f"{100 * m:+.2f}%" for m in d["mean_rel_diff"])
            + f" | {100 * d['worst_block_rel_diff']:.1f}% | {'met' if goal else 'no'} |")
    if a.rounds > 1:
        lines += ["", f"Means over the {a.rounds} rounds:", "",
                  "| scene | limit | integrator | relMSE | channel means |", "|---|---|---|---|---|"]
        keys = []
        for name, seconds, entry, *_ in rows:
            if (name, seconds, entry) not in keys:
                keys.append((name, seconds, entry))
        for key in keys:
            ds = [r[5] for r in rows if r[:3] == key and r[5] is not None]
            if not ds:
                continue
            n = len(ds)
            rel = sum(d["relmse"] for d in ds) / n
            means = [sum(d["mean_rel_diff"][c] for d in ds) / n for c in range(3)]
            lines.append(f"| {key[0]} | {key[1]} s | {key[2]} | {rel:.4f} | "
                         + " ".join(f"{100 * m:+.2f}%" for m in means) + f" (n={n}) |")
    table = "\n".join(lines)
    print(table)
    if not a.no_append:
        with open(os.path.join(ROOT, "bench", "history", "log.md"), "a") as f:
            f.write(f"\n### {time.strftime('%Y-%m-%d')}: `bench/many_light_equal_time.py "
                    f"--scenes {a.scenes} --integrators {','.join(integrators)}"
                    + "".join(f" --set {kv}" for kv in a.set)
                    + (f" --rounds {a.rounds}" if a.rounds > 1 else "") + f"`\n\n{table}\n")


if __name__ == "__main__":
    main()
