#!/usr/bin/env python3
"""Two or more runs over their first iterations, side by side: what each iteration cost and what the loop did.

    python3 experiments/loop_compare.py --until-iteration 39 "fixed=runs/general/fixed" "stochastic=runs/stoch"

For each run, as it stood at the end of iteration T (poet-report --until-iteration): rollouts and environment steps
(per iteration too), the coordinator's seconds per iteration in each phase (wall_times.csv, which depend on the
machine and its load), the children created, passing the minimal criterion, admitted and solved, the transfer
rounds' rollouts, their replacement attempts and accepted transfers, and with poet.confirm_transfers the choices
that did not hold on fresh courses. The last column is the last run's figure over the first's. Prints Markdown.
"""

import argparse
import csv
import json
import os
import subprocess
import sys

PHASES = ["reproduction_s", "es_steps_s", "evaluations_s", "transfer_s"]


def figures(run_dir, until, report_bin):
    try:
        printed = subprocess.run([report_bin, "--run-dir", run_dir, "--json", "-", "--coverage-per-level", "5",
                                  "--until-iteration", str(until)], check=True, capture_output=True, text=True,
                                 timeout=600).stdout
    except (OSError, subprocess.CalledProcessError) as error:
        sys.exit(f"loop_compare.py: {run_dir}: {getattr(error, 'stderr', '') or error}")
    report = json.loads(printed)
    done = report["iterations_done"]
    if done < until + 1:
        sys.exit(f"loop_compare.py: {run_dir} has done {done} iterations, fewer than {until + 1}")
    f = {"iterations": done, "rollouts": report["rollouts"], "environment steps (M)": report["env_steps"] / 1e6,
         "environment steps per iteration (k)": report["env_steps"] / done / 1e3}
    for key in ("created", "passed_mc", "admitted", "solved"):
        f[f"environments {key.replace('_', ' ')}"] = sum(level[key] for level in report["levels"])
    f["transfer attempts"] = report["transfers"]["replacement_attempts"]
    f["transfers accepted"] = report["transfers"]["accepted"]
    rounds = {"rollouts": 0, "unconfirmed": 0, "proposals": 0}
    with open(os.path.join(run_dir, "events.jsonl"), encoding="utf-8") as lines:
        for line in lines:
            event = json.loads(line)
            if event["iteration"] > until:
                break
            if event["event"] == "transfer_round":
                for key in rounds:
                    rounds[key] += event.get(key, 0)
    f["transfer rounds' rollouts"] = rounds["rollouts"]
    f["transfer proposals"] = rounds["proposals"]
    f["choices not confirmed"] = rounds["unconfirmed"]
    seconds = {phase: 0.0 for phase in PHASES}
    with open(os.path.join(run_dir, "wall_times.csv"), encoding="utf-8") as rows:
        for row in csv.DictReader(rows):
            if int(row["iteration"]) <= until:
                for phase in PHASES:
                    seconds[phase] += float(row[phase])
    for phase in PHASES:
        f[f"{phase[:-2].replace('_', ' ')}: s per iteration"] = seconds[phase] / done
    return f


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--until-iteration", type=int, required=True, help="compare iterations 0..T")
    parser.add_argument("--report", default="build/tools/poet-report", help="the poet-report binary")
    parser.add_argument("runs", nargs="+", metavar="LABEL=RUN_DIR")
    args = parser.parse_args()
    columns = []
    for item in args.runs:
        label, sep, path = item.partition("=")
        if not sep or not label or not path:
            sys.exit(f"loop_compare.py: expected LABEL=RUN_DIR, got {item!r}")
        columns.append((label, figures(path, args.until_iteration, args.report)))
    first, last = columns[0][1], columns[-1][1]
    print("| | " + " | ".join(label for label, _ in columns) + " | ratio |")
    print("|---|" + "---|" * len(columns) + "---|")
    for key in first:
        cells = [f"{f[key]:.2f}" if isinstance(f[key], float) else str(f[key]) for _, f in columns]
        ratio = f"{last[key] / first[key]:.2f}" if first[key] else "—"
        print(f"| {key} | " + " | ".join(cells) + f" | {ratio} |")


if __name__ == "__main__":
    main()
