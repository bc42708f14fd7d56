#!/usr/bin/env python3
"""Per-sample variance of `path` (defaults) for several builds of manylight, with more seed pairs
than bench/light_tree_variance.py, for changes whose effect is smaller than one pair's spread
(session 12: the share of the tree sampler's top-level choice made uniformly, kTopLevelUniform).

For each binary, renders at seeds s1, s2, ... (alternating the binaries at each seed so that load
hits them alike); each consecutive pair (s1, s2), (s3, s4), ... gives one estimate of the relative
variance per sample, mean((a - b)^2 / 2 / (r^2 + 0.01)) * spp, against a render r of the first
binary at --ref-spp (seed 99). Prints each pair's estimate, their mean, and CPU seconds per render.

With --samplers (default tree), each binary runs with each `path.lightsampler` given, e.g.
`--samplers power,tree,all`: `all` samples every light at each vertex, so it has no variance of
the light choice at all; for a fixed per-light sampling, no choice of one light per vertex can do
better than it (session 13: the bound for issue 14's goal).

Usage: bench/light_choice_variance.py --bins A,B[,C] [--samplers tree] [--scene classroom]
       [--spp 16] [--seeds 1,2,3,4,5,6] [--ref-spp 128]
"""
import argparse
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import light_tree_variance as ltv  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bins", required=True, help="comma-separated manylight binaries")
    ap.add_argument("--samplers", default="tree", help="comma-separated path.lightsampler values")
    ap.add_argument("--scene", default="classroom", choices=sorted(ltv.SCENES))
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--seeds", default="1,2,3,4,5,6")
    ap.add_argument("--ref-spp", type=int, default=128)
    a = ap.parse_args()
    bins = [(b, smp) for b in a.bins.split(",") for smp in a.samplers.split(",")]
    seeds = [int(s) for s in a.seeds.split(",")]
    if len(seeds) % 2:
        sys.exit("--seeds: an even number of seeds (consecutive pairs)")
    rel, res = ltv.SCENES[a.scene]
    scene = os.path.join(ltv.SCENES_DIR, rel)
    with tempfile.TemporaryDirectory() as tmp:
        ltv.BIN = bins[0][0]
        ref_out = os.path.join(tmp, "ref.pfm")
        ltv.render(scene, res, "tree", 99, a.ref_spp, 2, ref_out)
        ref = ltv.read_pfm(ref_out)
        imgs, secs = {}, {b: 0.0 for b in bins}
        for s in seeds:
            for i, b in enumerate(bins):
                ltv.BIN = b[0]
                out = os.path.join(tmp, "%d-%d.pfm" % (i, s))
                secs[b] += ltv.render(scene, res, b[1], s, a.spp, 2, out)
                imgs[(b, s)] = ltv.read_pfm(out)
        for b in bins:
            vs = [ltv.rel_variance(imgs[(b, seeds[i])], imgs[(b, seeds[i + 1])], ref, a.spp)
                  for i in range(0, len(seeds), 2)]
            print("%s %s: rel. var. per sample %s, mean %.2f; CPU s per render %.2f" %
                  (b[0], b[1], ", ".join("%.2f" % v for v in vs), sum(vs) / len(vs),
                   secs[b] / len(seeds)), flush=True)


if __name__ == "__main__":
    main()
