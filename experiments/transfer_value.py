#!/usr/bin/env python3
"""Runs side by side at one budget of environment steps: POET against POET without transfer (spec §3), or any runs.

    python3 experiments/transfer_value.py "POET=runs/deep" "without transfer=runs/deep-no-transfer" \
        [--env-steps N] [--report build/tools/poet-report]

Each run as it stood at the end of the last iteration within N environment steps (poet-report --until-env-steps;
N defaults to the smallest of the runs' own totals, so every run gets the same): its iterations and environment
steps, the environments created, admitted and solved at each difficulty level, the hardest of each obstacle
solved (the frontier), ANNECS in both definitions and the paper's coverage (spec §7: the summed distance from 1,000
sampled environments per level to the closest solved one; with nothing solved at a level, none). Prints Markdown.
"""

import argparse
import json
import os
import subprocess
import sys

LEVELS = ["easy", "challenging", "very challenging", "extremely challenging"]
DEFAULT_REPORT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "tools", "poet-report")


def labelled_run(text):
    label, sep, path = text.partition("=")
    if not sep or not label or not path:
        raise argparse.ArgumentTypeError(f"expected LABEL=RUN_DIR, got {text!r}")
    return label, path


def report(report_bin, run_dir, env_steps):
    command = [report_bin, "--run-dir", run_dir, "--json", "-"]
    if env_steps is not None:
        command += ["--until-env-steps", str(env_steps)]
    try:
        printed = subprocess.run(command, check=True, capture_output=True, text=True, timeout=1800).stdout
    except (OSError, subprocess.CalledProcessError) as error:
        sys.exit(f"transfer_value.py: {run_dir}: {(getattr(error, 'stderr', '') or str(error)).strip()}")
    return json.loads(printed)


def rows_of(r):
    levels = {level["level"]: level for level in r["levels"]}
    solved_levels = [name for name in LEVELS if levels[name]["solved"] > 0]
    frontier = r["frontier"][-1]["solved"] if r["frontier"] else {}
    rows = {"iterations": f"{r['iterations_done']:,}", "environment steps": f"{r['env_steps'] / 1e6:.1f} M",
            "rollouts": f"{r['rollouts']:,}"}
    for name in LEVELS:
        level = levels[name]
        rows[f"{name}: created / admitted / solved"] = f"{level['created']} / {level['admitted']} / {level['solved']}"
    rows["highest level solved"] = solved_levels[-1] if solved_levels else "-"
    rows["frontier solved: roughness, gap top, stump top"] = (
        ", ".join(f"{frontier[k]:.1f}" for k in ("roughness", "gap_hi", "stump_hi")) if frontier else "-")
    rows["ANNECS at admission"] = str(r["annecs"]["at_admission"]["value"])
    rows["ANNECS at archiving"] = str(r["annecs"]["at_archiving"]["value"])
    for name in LEVELS[1:]:
        value = r["coverage"]["sum"][name]
        rows[f"coverage at {name} (summed distance; lower is better)"] = "-" if value is None else f"{value:.1f}"
    return rows


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", type=labelled_run, help="LABEL=RUN_DIR (two or more)")
    parser.add_argument("--env-steps", type=int, help="the budget (default: the smallest run's total)")
    parser.add_argument("--report", default=DEFAULT_REPORT, help="poet-report (default: the build tree's)")
    args = parser.parse_args(argv)
    if len(args.runs) < 2:
        parser.error("give two runs or more")
    if args.env_steps is not None and args.env_steps < 1:
        parser.error("--env-steps must be positive")
    budget = args.env_steps
    if budget is None:
        budget = min(report(args.report, path, None)["env_steps"] for _, path in args.runs)
    reports = [(label, report(args.report, path, budget)) for label, path in args.runs]
    print(f"Within {budget:,} environment steps ({budget / 1e6:.1f} M)")
    print()
    print("| | " + " | ".join(label for label, _ in reports) + " |")
    print("|---|" + "---|" * len(reports))
    table = [rows_of(r) for _, r in reports]
    for key in table[0]:
        print(f"| {key} | " + " | ".join(rows[key] for rows in table) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
