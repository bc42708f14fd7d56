#!/usr/bin/env python3
"""The gallery (docs/gallery.md): each scene of ../shared/scenes rendered by `path` and by the
recommended many-light integrator for the same time, with their error against a longer `path`
render of the same scene.

Per scene, three renders: the reference (`path`, --ref-seconds, seed 4242), then `path` and the
many-light integrator (--integrator) each under --time-limit --seconds (seed 1). One picture per
scene, docs/images/gallery-SCENE.png: the two renders on top, their error below (each pixel's
relative squared error (x - r)^2 / (r^2 + 0.01), averaged over the channels, on a log scale:
black 1e-4 or less, white 1 or more). The page lists each one's relMSE (`manylight diff`) and
channel means against the reference, and the scene's licence (CC-BY scenes are credited).

The reference is only --ref-seconds of `path`: its own noise counts in both errors, and the page
says so. Renders are PNG as `manylight render` writes them (clamped, sRGB).

Usage: /usr/bin/python3 bench/gallery.py [--scenes kitchen,coffee,...] [--integrator bdlightcuts] [--seconds 5]
    [--ref-seconds 60] [--resolution 200x112] [--threads N] [--out docs/images]
    [--page docs/gallery.md] [--bin build/manylight]
--out without --page writes the page into that folder too (so a trial run leaves docs/ alone).
"""
import argparse
import json
import math
import os
import pathlib
import re
import struct
import subprocess
import sys
import tempfile
import zlib

import numpy as np

# Not resolved: run through a link to the source (tests/docs_commands.py), build/ is beside it.
ROOT = pathlib.Path(os.path.abspath(__file__)).parents[1]


def read_pfm(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            raise ValueError(f"{path}: not an RGB PFM")
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(h, w, 3)[::-1].astype(np.float64)


def write_png(path, rgb8):
    h, w, _ = rgb8.shape
    raw = b"".join(b"\0" + rgb8[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
           chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
    pathlib.Path(path).write_bytes(png)


def srgb8(linear):
    x = np.clip(linear, 0, 1)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (s * 255 + 0.5).astype(np.uint8)


def error_image(x, ref):
    e = ((x - ref) ** 2 / (ref ** 2 + 0.01)).mean(axis=2)
    v = np.clip((np.log10(np.maximum(e, 1e-12)) + 4) / 4, 0, 1)
    grey = (v * 255 + 0.5).astype(np.uint8)
    return np.repeat(grey[:, :, None], 3, axis=2)


def scene_size(scene, width):
    """The render's size at the scene film's aspect: `width` wide for 16:9 or wider."""
    text = scene.read_text(errors="replace")
    xs = re.search(r'"integer xresolution"\s*\[\s*(\d+)', text)
    ys = re.search(r'"integer yresolution"\s*\[\s*(\d+)', text)
    aspect = int(ys.group(1)) / int(xs.group(1)) if xs and ys else 9 / 16
    if aspect > 9 / 16:  # as many pixels as `width` x 9/16 of it, so that pictures stay small
        width = max(8, int(round(width * math.sqrt(9 / 16 / aspect) / 2)) * 2)
    return width, max(8, int(round(width * aspect / 2)) * 2)


def credit(scene_dir):
    text = (scene_dir / "LICENSE.txt").read_text(errors="replace") if (
        scene_dir / "LICENSE.txt").exists() else ""
    m = re.search(r"version of '(.+?)' by (.+?), downloaded", text)
    licence = "CC-BY" if "CC-BY" in text else "CC0" if "CC0" in text else "see LICENSE.txt"
    return f'"{m.group(1)}" by {m.group(2)}, {licence}' if m else licence


def render(args, scene, integrator, seconds, seed, size, out):
    stats = out.with_suffix(".json")
    cmd = [args.bin, "render", str(scene), "--integrator", integrator, "--time-limit",
           f"{seconds:g}", "--resolution", f"{size[0]}x{size[1]}", "--seed", str(seed), "-q",
           "-o", str(out), "--stats", str(stats)]
    if args.threads:
        cmd += ["--threads", str(args.threads)]
    subprocess.run(cmd, check=True)
    return json.loads(stats.read_text())


def diff(args, a, b):
    r = subprocess.run([args.bin, "diff", str(a), str(b), "--json"], check=True,
                       stdout=subprocess.PIPE, text=True)
    return json.loads(r.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", default="")
    ap.add_argument("--integrator", default="bdlightcuts")
    ap.add_argument("--seconds", type=float, default=5)
    ap.add_argument("--ref-seconds", type=float, default=60)
    ap.add_argument("--resolution", default="200x112", help="the width is used; the height "
                    "follows the scene's aspect")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--shared", default=str(ROOT.parent / "shared"))
    ap.add_argument("--out", default="")
    ap.add_argument("--page", default="")
    ap.add_argument("--bin", default=str(ROOT / "build" / "manylight"))
    args = ap.parse_args()
    out = pathlib.Path(args.out) if args.out else ROOT / "docs" / "images"
    page = pathlib.Path(args.page) if args.page else (
        out / "gallery.md" if args.out else ROOT / "docs" / "gallery.md")
    out.mkdir(parents=True, exist_ok=True)
    scenes_dir = pathlib.Path(args.shared) / "scenes"
    names = args.scenes.split(",") if args.scenes else sorted(
        d.name for d in scenes_dir.iterdir() if (d / "scene-v4.pbrt").exists())
    width = int(args.resolution.split("x")[0])
    rows = []
    with tempfile.TemporaryDirectory(prefix="manylight-gallery-") as tmp:
        tmp = pathlib.Path(tmp)
        for name in names:
            scene = scenes_dir / name / "scene-v4.pbrt"
            size = scene_size(scene, width)
            print(f"gallery: {name} at {size[0]}x{size[1]}", file=sys.stderr, flush=True)
            ref = tmp / f"{name}-ref.pfm"
            ref_stats = render(args, scene, "path", args.ref_seconds, 4242, size, ref)
            images, figures = [], []
            for integrator in ("path", args.integrator):
                img = tmp / f"{name}-{integrator}.pfm"
                stats = render(args, scene, integrator, args.seconds, 1, size, img)
                d = diff(args, img, ref)
                figures.append((integrator, stats["spp"], d["relmse"], d["mean_rel_diff"]))
                images.append(read_pfm(img))
            r = read_pfm(ref)
            top = np.concatenate([srgb8(i) for i in images], axis=1)
            bottom = np.concatenate([error_image(i, r) for i in images], axis=1)
            file = f"gallery-{name}.png"
            write_png(out / file, np.concatenate([top, bottom], axis=0))
            rows.append((name, file, figures, ref_stats["spp"], credit(scenes_dir / name)))

    images_rel = os.path.relpath(out, page.parent)
    lines = [
        "# Gallery",
        "",
        f"Each scene of `../shared/scenes` rendered by `path` (left) and by `{args.integrator}` "
        f"(right), each for {args.seconds:g} seconds (`--time-limit`, seed 1), at "
        f"{width} pixels wide; below each, its error against a reference: `path` for "
        f"{args.ref_seconds:g} seconds (seed 4242). Error images show each pixel's relative "
        "squared error, (x - r)² / (r² + 0.01) averaged over the channels, on a log scale: black "
        "10⁻⁴ or less, white 1 or more. The reference is itself noisy, so both errors include "
        "its noise; the relMSE and channel means are `manylight diff` against it. The times are "
        "wall-clock: on a busy machine every render gets fewer samples, and a many-light render "
        "that does not finish its first pass (spp 0) is black where no sample landed. Run it on "
        "a quiet machine for figures to compare.",
        "",
        "Made by:",
        "",
        "```sh",
        f"/usr/bin/python3 bench/gallery.py --integrator {args.integrator} --seconds {args.seconds:g} "
        f"--ref-seconds {args.ref_seconds:g} --resolution {args.resolution}",
        "```",
        "",
        "Which integrator suits which scene, measured at larger sizes: "
        "[guide.md](guide.md#choosing-an-integrator).",
    ]
    for name, file, figures, ref_spp, who in rows:
        lines += ["", f"## {name}", "", f"![{name}: path and {args.integrator}, and their error]"
                  f"({images_rel}/{file})", "",
                  "| integrator | spp | relMSE | channel means against the reference |",
                  "|---|---|---|---|"]
        for integrator, spp, relmse, means in figures:
            m = " ".join(f"{100 * v:+.1f}%" for v in means)
            lines.append(f"| `{integrator}` | {spp} | {relmse:.3g} | {m} |")
        lines += ["", f"Reference: {ref_spp} spp. Scene: {who}, from Benedikt Bitterli's "
                  "rendering resources."]
    page.write_text("\n".join(lines) + "\n")
    print(f"gallery: wrote {page} and {len(rows)} images in {out}", file=sys.stderr)


if __name__ == "__main__":
    main()
