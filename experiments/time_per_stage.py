#!/usr/bin/env python3
"""Where a run's time goes, stage by stage: iterations per hour and the share of each phase of an iteration.

    PYTHONPATH=build/python python3 experiments/time_per_stage.py RUN_DIR [--stage-iterations 100]

A stage is a block of iterations (100 by default). For each: the iterations it holds, its wall time (the
coordinator's running time, wall_times.csv), iterations per hour, the environment steps it ran and their rate,
the mean number of active pairs (pair_stats.csv: one row per pair per ES step), the highest difficulty level
solved by its end, and the share of its time in each phase of an iteration as the coordinator measured it
(wall_times.csv's per-phase seconds: reproduction — the children's minimal-criterion evaluations, novelty and the
admission walk —, ES steps, evaluations of the new θs, transfer rounds; "other" is what falls between iterations:
saving the checkpoint and the logs). Lines of builds that did not time the phases count in the wall time only;
the "timed" column says how many of a stage's iterations have phases. Prints a Markdown table.
"""

import os
import sys

import pandas as pd

from run_cli import open_run, run_parser

PHASES = ["reproduction_s", "es_steps_s", "evaluations_s", "transfer_s"]
LEVELS = ["easy", "challenging", "very challenging", "extremely challenging"]


def main(argv):
    parser = run_parser(__doc__)
    parser.add_argument("--stage-iterations", type=int, default=100, help="iterations per stage (default 100)")
    args = parser.parse_args(argv)
    if args.stage_iterations < 1:
        parser.error("--stage-iterations must be at least 1")
    run = open_run(parser, args.run_dir)
    wall_path = os.path.join(args.run_dir, "wall_times.csv")
    if not os.path.exists(wall_path):
        parser.error(f"{wall_path}: no wall times (the run was restored without them)")
    walls = pd.read_csv(wall_path)
    for column in PHASES:
        if column not in walls:
            walls[column] = float("nan")
    walls = walls[walls["iteration"] < len(run.annecs)]  # the iterations the checkpoint has seen
    # each line's own time: the clock's step since the line before
    walls["step_s"] = walls["wall_s"].diff().fillna(walls["wall_s"])
    stats = run.pair_stats
    steps_by_iteration = stats.groupby("iteration")["run_env_steps"].max()
    pairs_by_iteration = stats.groupby("iteration").size()
    solved = run.pairs[run.pairs["solved"].notna()]

    print(f"Run {args.run_dir}: {len(run.annecs)} iterations, {walls['wall_s'].iloc[-1] / 3600:.2f} h of wall time")
    print()
    print("| iterations | wall time | iterations per hour | environment steps | steps per second | active pairs "
          "| highest level solved | timed | reproduction | ES steps | evaluations | transfer | other |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    previous_steps = 0
    for first in range(0, len(run.annecs), args.stage_iterations):
        last = min(first + args.stage_iterations, len(run.annecs)) - 1
        stage = walls[(walls["iteration"] >= first) & (walls["iteration"] <= last)]
        seconds = stage["step_s"].sum()
        steps = int(steps_by_iteration.loc[:last].iloc[-1]) if len(steps_by_iteration.loc[:last]) else 0
        stage_steps = steps - previous_steps
        previous_steps = steps
        reached = solved[solved["solved"] <= last]["level"]
        highest = max((LEVELS.index(level) for level in reached if level in LEVELS), default=None)
        timed = stage.dropna(subset=PHASES)
        shares = ["-"] * 5
        if len(timed) and timed["step_s"].sum() > 0:
            total = timed["step_s"].sum()
            parts = [timed[c].sum() / total for c in PHASES]
            shares = [f"{100 * p:.0f} %" for p in parts] + [f"{100 * max(0.0, 1 - sum(parts)):.0f} %"]
        print(f"| {first}–{last} | {seconds / 60:.1f} min | {(last - first + 1) / (seconds / 3600):.0f} "
              f"| {stage_steps / 1e6:.1f} M | {stage_steps / seconds:,.0f} "
              f"| {pairs_by_iteration.loc[first:last].mean():.1f} "
              f"| {LEVELS[highest] if highest is not None else '-'} | {len(timed)} of {last - first + 1} | "
              + " | ".join(shares) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
