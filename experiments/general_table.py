#!/usr/bin/env python3
"""The generalisation comparison as a table and a plot: per method, its agents on a held-out test suite.

Usage: general_table.py [--plot FILE.png] LABEL=SUITE_JSON...
Each SUITE_JSON is poet-eval --suite --json's output: of one policy (--policy), or of every agent of a run
(--run-dir), for which the table gives the run's best single agent on the whole suite and, in a second row, the
best agent of each group on that group alone (the label under each figure). Prints a Markdown table of the fraction
finished per group (with its 95% interval), the mean progress along the courses and the mean return over the suite;
--plot draws, per group, the fraction finished (with its interval), the mean progress and the mean return (with its
interval) of each method's best single agent (matplotlib). Progress is drawn beside the return because a walker that
stands still scores more than one that walks and falls.
"""

import argparse
import json
import sys


def load(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError) as error:
        sys.exit(f"general_table.py: {path}: {error}")


def rows_of(label, doc):
    """[(row label, [(group name, group summary, agent label or None)], suite summary)]"""
    if not isinstance(doc, dict) or "suite" not in doc or ("candidates" not in doc and "groups" not in doc):
        sys.exit(f"general_table.py: {label}: not the output of poet-eval --suite --json")
    if "candidates" not in doc:  # one policy
        return [(label, [(g["group"], g, None) for g in doc["groups"]], doc)]
    if not doc["candidates"]:
        sys.exit(f"general_table.py: {label}: the run has no agents")
    by_label = {c["label"]: c["score"] for c in doc["candidates"]}
    best = by_label[doc["best"]]
    single = (f"{label}: best single agent ({doc['best']})", [(g["group"], g, None) for g in best["groups"]], best)
    per_group = []
    for i, group in enumerate(best["groups"]):
        agent = doc["best_per_group"][group["group"]]
        per_group.append((group["group"], by_label[agent]["groups"][i], agent))
    return [single, (f"{label}: best per group", per_group, None)]


def fraction(g):
    lo, hi = g["finished_interval"]
    return f"{g['finished']}/{g['episodes']} ({100 * g['finished_fraction']:.0f}%, {100 * lo:.0f}–{100 * hi:.0f}%)"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", help="write the plot here (PNG)")
    parser.add_argument("runs", nargs="+", metavar="LABEL=SUITE_JSON")
    args = parser.parse_args()
    methods, suite = [], None
    for item in args.runs:
        label, sep, path = item.partition("=")
        if not sep or not label or not path:
            sys.exit(f"general_table.py: expected LABEL=SUITE_JSON, got {item!r}")
        doc = load(path)
        methods.append((label, rows_of(label, doc)))
        suite = suite or doc["suite"]
        if doc["suite"] != suite:
            sys.exit(f"general_table.py: {label}: suite {doc['suite']}, not the first file's {suite}")

    groups = [name for name, _, _ in methods[0][1][0][1]]
    print("| agents | " + " | ".join(groups) + " | mean progress (suite) | mean return (suite) |")
    print("|---|" + "---|" * len(groups) + "---|---|")
    for _, rows in methods:
        for row_label, cells, summary in rows:
            figures = [fraction(g) + (f" — {agent}" if agent else "") for _, g, agent in cells]
            progress = f"{100 * summary['mean_progress']:.1f}%" if summary else "—"
            mean = f"{summary['mean_return']:.1f}" if summary else "—"
            print(f"| {row_label} | " + " | ".join(figures) + f" | {progress} | {mean} |")

    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, (ax, ax_progress, ax_return) = plt.subplots(3, 1, figsize=(10, 10), sharex=True)
        width = 0.8 / len(methods)
        for m, (label, rows) in enumerate(methods):
            cells = rows[0][1]
            xs = [i + (m - (len(methods) - 1) / 2) * width for i in range(len(cells))]
            ys = [100 * g["finished_fraction"] for _, g, _ in cells]
            lo = [y - 100 * g["finished_interval"][0] for y, (_, g, _) in zip(ys, cells)]
            hi = [100 * g["finished_interval"][1] - y for y, (_, g, _) in zip(ys, cells)]
            ax.bar(xs, ys, width, yerr=[lo, hi], capsize=3, label=label)
            ax_progress.bar(xs, [100 * g["mean_progress"] for _, g, _ in cells], width, label=label)
            means = [g["mean_return"] for _, g, _ in cells]
            spread = [g["mean_return_half_width"] for _, g, _ in cells]
            ax_return.bar(xs, means, width, yerr=spread, capsize=3, label=label)
        ax_return.set_xticks(range(len(groups)), groups)
        ax.set_ylabel("courses finished (%), 95% interval")
        ax_progress.set_ylabel("mean progress along the course (%)")
        ax_return.set_ylabel("mean return, 95% interval")
        ax_return.axhline(0, color="black", linewidth=0.5)
        ax.set_title(f"best single agent of each method on the test suite {suite}")
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)


if __name__ == "__main__":
    main()
