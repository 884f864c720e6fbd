#!/usr/bin/env python3
"""Fit a measured table with brdffit and plot the fits against the data.

    python3 examples/fit_and_plot.py [TABLE] [--models lambert,ggx,cook-torrance] [--out fits.png]

TABLE defaults to the bundled RGL table (data/cc_ibiza_sunset_rgb.bsdf). Prints each model's
parameters and errors, saves the result document beside the plot (readable by `brdffit report`),
and plots two views of fit vs data with Matplotlib (skipped, with a note, when Matplotlib is not
installed: Debian python3-matplotlib):
  left   the plane of incidence: f·cosθi for light at 30° as the viewer sweeps from -80° to 80°,
         the table's look-up against each model's prediction, per colour channel;
  right  every sample: predicted against measured f·cosθi for the best model.
Run it from a build tree with PYTHONPATH=build/python, or after `cmake --install`.
"""
import argparse
import pathlib

import numpy as np

import brdffit

BUNDLED = pathlib.Path(__file__).resolve().parents[1] / "data" / "cc_ibiza_sunset_rgb.bsdf"


def incidence_plane(theta_i_deg=30.0, count=161):
    """Light fixed at theta_i in the x-z plane; the viewer swept through the same plane."""
    theta_i = np.radians(theta_i_deg)
    light = np.array([-np.sin(theta_i), 0.0, np.cos(theta_i)])
    theta_o = np.radians(np.linspace(-80.0, 80.0, count))
    view = np.stack([np.sin(theta_o), np.zeros_like(theta_o), np.cos(theta_o)], axis=1)
    return light, view, np.degrees(theta_o)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("table", nargs="?", default=str(BUNDLED))
    parser.add_argument("--models", default="lambert,ggx,cook-torrance")
    parser.add_argument("--out", default="fit_and_plot.png")
    args = parser.parse_args()

    table = brdffit.read(args.table)
    print(f"{table.path}: {len(table)} samples ({table.weighting} weights)")
    results = brdffit.fit(table, models=args.models)
    for result in sorted(results, key=lambda r: r.metrics["cosine"]):
        print(f"{result.model:<16} {result.verdict:<6} cosine {result.metrics['cosine']:.4g}  "
              + "  ".join(f"{name}={p.value}" for name, p in result.parameters.items()))
    document = pathlib.Path(args.out).with_suffix(".json")
    results.save(str(document))
    print(f"result document: {document}")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("Matplotlib is not installed (Debian: python3-matplotlib): no plot")
        return

    light, view, theta_o = incidence_plane()
    measured = table.lookup(np.broadcast_to(light, view.shape), view) * light[2]
    figure, (plane, scatter) = plt.subplots(1, 2, figsize=(12, 4.5))
    colours = ("tab:red", "tab:green", "tab:blue")
    for c, colour in enumerate(colours):
        plane.plot(theta_o, measured[:, c], color=colour, linewidth=2.5, alpha=0.4, label="data" if c == 0 else None)
    for result, style in zip(results, ("--", "-", ":", "-.")):
        if not result.ok:
            continue
        predicted, _ = brdffit.eval(result.model, result, light, view)
        for c, colour in enumerate(colours):
            plane.plot(theta_o, predicted[:, c], style, color=colour, linewidth=1,
                       label=result.model if c == 0 else None)
    plane.set(yscale="log", xlabel="θo in the plane of incidence (degrees)", ylabel="f·cosθi (1/sr)",
              title="light at 30°: data (thick) and fits")
    plane.legend()

    best = results.best
    predicted, _ = brdffit.eval(best.model, best, table.light, table.view)
    for c, colour in enumerate(colours):
        scatter.scatter(table.rgb[:, c], predicted[:, c], s=1, color=colour, alpha=0.2)
    top = float(table.rgb.max())
    scatter.plot([1e-4, top], [1e-4, top], "k-", linewidth=0.8)
    scatter.set(xscale="log", yscale="log", xlim=(1e-4, top), ylim=(1e-4, top), xlabel="measured f·cosθi",
                ylabel="predicted f·cosθi", title=f"every sample, {best.model} (cosine {best.metrics['cosine']:.3g})")
    figure.tight_layout()
    figure.savefig(args.out, dpi=110)
    print(f"plot: {args.out}")


if __name__ == "__main__":
    main()
