#!/usr/bin/env python3
"""Mean episode length of runs, from their pair_stats.csv: environment steps per rollout over the whole run and per
block of iterations (run_env_steps and run_rollouts are the run's totals after each iteration's ES steps), so that
the cost of an episode can be read off real runs and its growth seen. Prints a Markdown table.

    python3 bench/episode_lengths.py RUN_DIR [RUN_DIR ...] [--block 100]

A run packed with `poetctl pack` is read after `build/tools/poetctl unpack PACK DIR`.
"""
import argparse
import csv
import os
import sys


def totals_by_iteration(run_dir):
    """{iteration: (run_rollouts, run_env_steps)}, the last row of each iteration."""
    totals = {}
    with open(os.path.join(run_dir, "pair_stats.csv")) as f:
        for row in csv.DictReader(f):
            totals[int(row["iteration"])] = (int(row["run_rollouts"]), int(row["run_env_steps"]))
    return totals


def main():
    parser = argparse.ArgumentParser(description="Environment steps per rollout of runs, whole and per block.")
    parser.add_argument("runs", nargs="+", help="run directories")
    parser.add_argument("--block", type=int, default=100, help="iterations a block (default 100)")
    args = parser.parse_args()
    if args.block < 1:
        parser.error("--block must be at least 1")

    rows = []
    for run in args.runs:
        try:
            totals = totals_by_iteration(run)
        except (OSError, KeyError, ValueError) as e:
            sys.exit(f"episode_lengths.py: {run}: {e}")
        if not totals:
            sys.exit(f"episode_lengths.py: {run}: no rows in pair_stats.csv")
        last = max(totals)
        rollouts, steps = totals[last]
        blocks = []
        before = (0, 0)
        for start in range(0, last + 1, args.block):
            end = min(start + args.block, last + 1) - 1
            at_end = next((totals[i] for i in range(end, start - 1, -1) if i in totals), before)
            r, s = at_end[0] - before[0], at_end[1] - before[1]
            if r > 0:
                blocks.append(f"{s / r:,.0f}")
            before = at_end
        rows.append(f"| {os.path.basename(os.path.normpath(run))} | {last + 1} | {rollouts:,} | {steps / 1e6:,.1f} M "
                    f"| {steps / rollouts:,.0f} | {' · '.join(blocks)} |")
    print("| run | iterations | rollouts | environment steps | steps per rollout | per block of "
          f"{args.block} iterations |")
    print("|---|---|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
