#!/usr/bin/env python3
"""The Python module's figures: the overhead of brdffit.fit over the command line's fit of the
same table, and the time of brdffit.eval per million directions.

    PYTHONPATH=build/python python3 bench/bench_python.py [TABLE] [--models lambert,ggx]
        [--cli build/apps/brdffit] [--repeat 3]

Fit: the fits' own time in `brdffit fit TABLE --models M` (the models' seconds in its result
document) against the wall time of the brdffit.fit call on the same table (and that call against
the library's time inside it: what the binding itself costs), and end to end the CLI process
against brdffit.read + brdffit.fit; the best of --repeat runs each, alternated so that both see
the same machine load (on a shared machine the CLI comparison is as noisy as the load). Eval: ggx at 10^6
random pairs of directions, best of --repeat.
"""
import argparse
import json
import pathlib
import subprocess
import tempfile
import time

import numpy as np

import brdffit

HERE = pathlib.Path(__file__).resolve().parents[1]


def best_time(run, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("table", nargs="?", default=str(HERE / "data" / "cc_ibiza_sunset_rgb.bsdf"))
    parser.add_argument("--models", default="lambert,ggx")
    parser.add_argument("--cli", default=str(HERE / "build" / "apps" / "brdffit"))
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()

    document = pathlib.Path(tempfile.mkdtemp()) / "fit.json"

    def cli_fit():  # the process's wall time, and the fits' own time from its document
        start = time.perf_counter()
        subprocess.run([args.cli, "fit", args.table, "--models", args.models, "--out", document], check=True,
                       capture_output=True)
        wall = time.perf_counter() - start
        return wall, sum(m["seconds"] for m in json.loads(document.read_text())["models"])

    def python_fit():  # read + fit, the fit call alone, and the fits' own time inside it
        start = time.perf_counter()
        table = brdffit.read(args.table)
        fit_start = time.perf_counter()
        results = brdffit.fit(table, models=args.models)
        end = time.perf_counter()
        return end - start, end - fit_start, sum(r.seconds for r in results)

    cli_runs, python_runs = [], []
    for _ in range(args.repeat):  # alternated, so that both see the same machine load
        cli_runs.append(cli_fit())
        python_runs.append(python_fit())
    cli_wall, cli_fit_seconds = min(r[0] for r in cli_runs), min(r[1] for r in cli_runs)
    python_wall, python_fit_seconds = min(r[0] for r in python_runs), min(r[1] for r in python_runs)
    binding = min((r[1] - r[2]) / r[2] for r in python_runs)
    print(f"fit {args.table} --models {args.models} (best of {args.repeat}):")
    print(f"  the binding's own cost (brdffit.fit call over the library's fit time inside it): {100 * binding:+.2f} %")
    print(f"  the fits alone: CLI {cli_fit_seconds:.3f} s, brdffit.fit call {python_fit_seconds:.3f} s, "
          f"overhead {100 * (python_fit_seconds / cli_fit_seconds - 1):+.1f} %")
    print(f"  end to end: CLI process {cli_wall:.3f} s, brdffit.read + brdffit.fit {python_wall:.3f} s, "
          f"{100 * (python_wall / cli_wall - 1):+.1f} %")

    rng = np.random.default_rng(1)
    n = 1_000_000
    light, view = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    light[:, 2], view[:, 2] = np.abs(light[:, 2]), np.abs(view[:, 2])
    params = {"albedo": (0.2, 0.3, 0.4), "roughness": 0.3, "f0": 0.5}
    for model in ("lambert", "ggx", "cook-torrance"):
        seconds = best_time(lambda: brdffit.eval(model, None if model != "ggx" else params, light, view), args.repeat)
        print(f"eval {model}: {seconds:.3f} s per million directions (shaded and f, every core)")
    table = brdffit.read(args.table)
    picks = rng.integers(0, len(table), n)
    light, view = table.light[picks], table.view[picks]
    seconds = best_time(lambda: table.lookup(light, view), args.repeat)
    print(f"Table.lookup: {seconds:.3f} s per million directions")


if __name__ == "__main__":
    main()
