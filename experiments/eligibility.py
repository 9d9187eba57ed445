#!/usr/bin/env python3
"""Whether a run's reproductions found parents: per block of iterations, the reproductions, those with no eligible
parent, the children admitted, and at each reproduction the active pairs whose latest and whose best evaluation had
reached the reproduction threshold.

    PYTHONPATH=build/python python3 experiments/eligibility.py RUN_DIR [--block 50]

The scores are those of the iteration before each reproduction (pair_stats.csv), the ones it saw; the threshold is
the run's (poet.repro_threshold). Prints a Markdown table.
"""

import re
import sys

from run_cli import open_run, run_parser


def main(argv):
    parser = run_parser(__doc__)
    parser.add_argument("--block", type=int, default=50, help="iterations per row (default 50)")
    args = parser.parse_args(argv)
    if args.block < 1:
        parser.error("--block must be at least 1")
    run = open_run(parser, args.run_dir)
    found = re.search(r"repro_threshold: ([-0-9.e+]+)", run.config)
    threshold = float(found.group(1)) if found else 200.0  # the schema's default
    events = run.events
    reproductions = events[events["event"] == "reproduction"] if len(events) else events
    stats = run.pair_stats
    print(f"| iterations | reproductions | with no eligible parent | admitted | active pairs with latest ≥ {threshold:g} "
          f"| with best ≥ {threshold:g} |")
    print("|---|---|---|---|---|---|")
    iterations = len(run.annecs)
    for first in range(0, iterations, args.block):
        last = min(first + args.block, iterations) - 1
        block = reproductions[(reproductions["iteration"] >= first) & (reproductions["iteration"] <= last)]
        if not len(block):
            continue
        latest = best = 0
        for t in block["iteration"]:
            seen = stats[stats["iteration"] == t - 1]
            latest += int((seen["score"] >= threshold).sum())
            best += int((seen["best_score"] >= threshold).sum())
        none = int((block["eligible"] == 0).sum())
        admitted = int(block["admitted"].fillna(0).sum())
        print(f"| {first}–{last} | {len(block)} | {none} | {admitted} | {latest / len(block):.1f} | "
              f"{best / len(block):.1f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
