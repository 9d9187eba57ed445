#!/usr/bin/env python3
"""Each pair's score over the iterations of a run, from its pair_stats, drawn with matplotlib.

    PYTHONPATH=build/python /usr/bin/python3 examples/plot_scores.py RUN_DIR scores.png
"""

import sys

import matplotlib

matplotlib.use("Agg")  # a file, no display
import matplotlib.pyplot as plt  # noqa: E402

import poet  # noqa: E402


def main(run_dir, out):
    run = poet.Run(run_dir)
    stats = run.pair_stats
    figure, axes = plt.subplots(figsize=(8, 4.5))
    for pair, rows in stats.groupby("pair"):
        env = run.pairs.loc[pair, "env"]
        axes.plot(rows["iteration"], rows["score"], label=f"pair {pair} ({env})", linewidth=1)
    axes.axhline(230, color="grey", linestyle="--", linewidth=0.8)  # the paper's "solved"
    axes.set_xlabel("iteration")
    axes.set_ylabel("score on its own environment")
    axes.set_title(f"{run_dir}: {len(run.pairs)} pairs, {run.next_iteration} iterations")
    axes.legend(fontsize="small", loc="lower right")
    figure.tight_layout()
    figure.savefig(out, dpi=100)
    print(f"{out}: {stats['pair'].nunique()} pairs over {run.next_iteration} iterations")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        print(__doc__.strip(), file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1], sys.argv[2]))
