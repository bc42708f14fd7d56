#!/usr/bin/env python3
"""Scene-language coverage (issue 35): which pbrt-v4 scenes of a folder manylight renders.

Walks FOLDER for top-level pbrt-v4 scenes (*.pbrt files holding a WorldBegin; fragments pulled
in by Include/Import have none), renders each at 1 spp and a small size with `manylight render`,
and prints a Markdown table: the scene, whether it rendered, the load and render seconds, and for
a scene that did not, the first error manylight reported (its first unsupported feature, at
file:line). Renders are niced; each gets --timeout seconds.

Usage: bench/scene_coverage.py [FOLDER] [--bin build/manylight] [--resolution 64x36]
       [--timeout 300] [--integrator path]
"""
import argparse
import json
import os
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def top_level_scenes(folder):
    found = []
    for dirpath, dirnames, filenames in os.walk(folder):
        dirnames.sort()
        for name in sorted(filenames):
            if not name.endswith(".pbrt"):
                continue
            path = os.path.join(dirpath, name)
            with open(path, "rb") as f:
                if b"WorldBegin" in f.read():
                    found.append(path)
    return found


def first_error(stderr):
    # The first line that carries a message (file:line:col: message), without the program name.
    for line in stderr.splitlines():
        line = line.strip()
        if not line:
            continue
        if line.startswith("manylight: "):
            line = line[len("manylight: "):]
        return line.replace("|", "\\|")
    return "(no message)"


def render(binary, scene, args, out_dir):
    out = os.path.join(out_dir, "out.exr")
    stats = os.path.join(out_dir, "stats.json")
    cmd = ["nice", "-n", "15", binary, "render", scene, "-o", out, "--spp", "1",
           "--resolution", args.resolution, "--quiet", "--stats", stats]
    if args.integrator:
        cmd += ["--integrator", args.integrator]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
    except subprocess.TimeoutExpired:
        return False, "", f"(no result within {args.timeout} s)"
    if p.returncode != 0:
        return False, "", first_error(p.stderr)
    with open(stats) as f:
        s = json.load(f)["seconds"]
    return True, f"{s['load']:.1f} / {s['render']:.1f}", ""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", nargs="?", default=os.path.join(ROOT, "..", "shared", "scenes"))
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "manylight"))
    ap.add_argument("--resolution", default="64x36")
    ap.add_argument("--timeout", type=int, default=300)
    ap.add_argument("--integrator", default="")
    args = ap.parse_args()

    folder = os.path.normpath(args.folder)
    scenes = top_level_scenes(folder)
    rows, ok = [], 0
    with tempfile.TemporaryDirectory() as tmp:
        for scene in scenes:
            rendered, seconds, error = render(args.bin, scene, args, tmp)
            ok += rendered
            rel = os.path.relpath(scene, folder)
            rows.append(f"| {rel} | {'yes' if rendered else 'no'} | {seconds} | {error} |")
            print(rows[-1], flush=True)
    print()
    print(f"`bench/scene_coverage.py {args.folder}` (1 spp, {args.resolution}"
          f"{', ' + args.integrator if args.integrator else ''}): {ok} of {len(scenes)} render")
    print()
    print("| scene | renders | load / render s | first unsupported feature |")
    print("|---|---|---|---|")
    for r in rows:
        print(r)


if __name__ == "__main__":
    main()
