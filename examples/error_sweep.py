"""Lightcuts' error threshold against time: renders a scene with `lightcuts` over a sweep of
lightcuts.error, measures each image's error against `vpl` (the exact sum over the same point
lights: the same seed gives the same VPLs) and plots error against render time.

    PYTHONPATH=build/python /usr/bin/python3 examples/error_sweep.py \\
        ../shared/scenes/cornell-box/scene-v4.pbrt -o error_sweep.png

With no scene it renders the built-in Cornell box. Prints one line per render and writes the plot
(matplotlib, Agg backend: no display needed).
"""

import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after the backend is chosen)
import numpy as np  # noqa: E402

import manylight  # noqa: E402


def relative_rms_error(image, reference):
    """The root-mean-square difference over pixels and channels, relative to the mean of the
    reference."""
    return float(np.sqrt(np.mean((image - reference) ** 2)) / np.mean(reference))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", nargs="?", help="pbrt-v4 scene (default: the built-in Cornell box)")
    parser.add_argument("--resolution", default="128x128", help="WxH (default 128x128)")
    parser.add_argument("--spp", type=int, default=1, help="samples per pixel (default 1)")
    parser.add_argument("--vpls", type=int, default=10000, help="vpl.count (default 10000)")
    parser.add_argument("--errors", default="0.005,0.01,0.02,0.05,0.1,0.2,0.5",
                        help="the lightcuts.error values, comma-separated")
    parser.add_argument("-o", "--output", default="error_sweep.png", help="the plot (.png)")
    args = parser.parse_args()

    width, height = (int(v) for v in args.resolution.lower().split("x"))
    common = dict(resolution=(width, height), spp=args.spp, seed=1)
    settings = {"vpl.count": args.vpls}

    reference, ref_stats = manylight.render(args.scene, integrator="vpl", settings=settings,
                                            **common)
    ref_seconds = ref_stats["seconds"]["render"]
    print(f"vpl (exact over {ref_stats['lights']['point_lights']} point lights): "
          f"{ref_seconds:.2f} s")

    errors = [float(e) for e in args.errors.split(",")]
    seconds, image_errors = [], []
    for threshold in errors:
        image, stats = manylight.render(args.scene, integrator="lightcuts",
                                        settings={**settings, "lightcuts.error": threshold},
                                        **common)
        seconds.append(stats["seconds"]["render"])
        image_errors.append(relative_rms_error(image, reference))
        cut = stats.get("lightcuts", {}).get("avg_cut_size")
        print(f"lightcuts.error={threshold:g}: {seconds[-1]:.2f} s, relative RMS error "
              f"{image_errors[-1]:.4f}" + (f", average cut {cut:.0f}" if cut else ""))

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(seconds, image_errors, "o-", label="lightcuts")
    for threshold, t, e in zip(errors, seconds, image_errors):
        ax.annotate(f"{threshold:g}", (t, e), textcoords="offset points", xytext=(4, 4))
    ax.axvline(ref_seconds, color="grey", linestyle="--", label=f"vpl (exact): {ref_seconds:.2f} s")
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=1e-4)
    ax.set_xlabel("render time (s)")
    ax.set_ylabel("relative RMS error against vpl")
    ax.set_title(f"lightcuts.error sweep, {args.vpls} VPLs, {width}x{height}, {args.spp} spp")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
