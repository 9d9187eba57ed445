#!/usr/bin/env python3
"""ANNECS against iterations for several runs on one plot, each cut at the same wall-time budget.

    PYTHONPATH=build/python python3 experiments/annecs_compare.py \
        --run "Enhanced POET=runs/enhanced" --run "POET=runs/challenging" --out annecs.png [--wall-seconds S]

Each run's iterations count while its wall_times.csv says they ended within the budget (by default the shortest
of the runs' recorded wall times, so every run gets the same). Both of ANNECS's definitions are drawn, each named
(at admission: solid; at archiving: dashed), and a table of the figures at the budget is printed.
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402

import poet  # noqa: E402


def labelled_run(text):
    label, sep, path = text.partition("=")
    if not sep or not label or not path:
        raise argparse.ArgumentTypeError(f"expected LABEL=RUN_DIR, got {text!r}")
    return label, path


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run", action="append", type=labelled_run, required=True, help="LABEL=RUN_DIR (repeat)")
    parser.add_argument("--out", required=True, help="the plot to write (.png or .svg)")
    parser.add_argument("--wall-seconds", type=float, help="the budget (default: the shortest run's wall time)")
    args = parser.parse_args(argv)

    runs = []
    for label, path in args.run:
        try:
            run = poet.Run(path)
        except ValueError as error:
            parser.error(str(error))
        walls = pd.read_csv(os.path.join(path, "wall_times.csv")).set_index("iteration")["wall_s"]
        runs.append((label, run, walls))
    budget = args.wall_seconds if args.wall_seconds else min(walls.iloc[-1] for _, _, walls in runs)

    figure, axes = plt.subplots(figsize=(8, 4.5))
    print(f"wall-time budget: {budget:.0f} s")
    print(f"{'run':<16} {'iterations':>10} {'pairs':>6} {'ANNECS at admission':>20} {'at archiving':>13}")
    for index, (label, run, walls) in enumerate(runs):
        within = walls[walls <= budget].index
        annecs = run.annecs.loc[run.annecs.index.isin(within)]
        colour = f"C{index}"
        axes.step(annecs.index, annecs["at_admission"], where="post", color=colour,
                  label=f"{label}: at admission")
        axes.step(annecs.index, annecs["at_archiving"], where="post", color=colour, linestyle="--",
                  label=f"{label}: at archiving")
        last = annecs.iloc[-1] if len(annecs) else {"at_admission": 0, "at_archiving": 0}
        pairs = run.pairs[run.pairs["created"] <= (within.max() if len(within) else -1)]
        print(f"{label:<16} {len(within):>10} {len(pairs):>6} {int(last['at_admission']):>20} "
              f"{int(last['at_archiving']):>13}")
    axes.set_xlabel("iteration")
    axes.set_ylabel("ANNECS")
    axes.set_title(f"ANNECS within the same wall-time budget ({budget / 60:.0f} min)")
    axes.legend(fontsize=8)
    axes.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(args.out, dpi=100)
    print(f"plot: {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
