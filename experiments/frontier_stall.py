#!/usr/bin/env python3
"""Why a run's frontier stalls, from its files: the challenging children per block of iterations and where the
active pairs' genes went, how long the pairs at the frontier lived and bred, the pairs that retired unsolved and whether ES was still improving them, and the
evaluations that scored ≥ 230 without finishing (the time limit) — with what the best θs of the pairs that never
finished do when given more steps.

    PYTHONPATH=build/python python3 experiments/frontier_stall.py RUN_DIR [--block 50] [--since 200]

Blocks: challenging children (at least one of Table 1's conditions), those passing the minimal criterion and
admitted; the active pairs' mean roughness, gap top and stump top at the block's last reproduction. Frontier
pairs: each admitted challenging environment's creation, first solve and retirement, and the children made from it
(attempts, those passing the minimal criterion, those admitted). Retired unsolved: each pair's best evaluation in its first 30 ES steps and in its last 10. Time limit: the evaluations
≥ 230 of the pairs active from iteration SINCE on, and before iteration SINCE − 50, that ran 2,000 steps without
finishing; then each pair with such an evaluation and no solve, its best θ on its own course at 2,000, 2,500 and
3,000 steps. Prints Markdown tables.
"""

import json
import os
import sys
import tempfile

import poet

from run_cli import open_run, run_parser


def conditions(e):
    roughness, _, gap_top, _, stump_top = e
    return (stump_top >= 2.4) + (gap_top >= 6.0) + (roughness >= 4.5)


def genes_by_env(events):
    """Each environment's 5-vector (spec §1.4), from the child events that made it."""
    return {e["env"]: e["e"] for e in events if e["event"] == "child"}


def blocks(run, block):
    events = run._events
    genes = {0: [0.0] * 5}
    genes_of_env = genes_by_env(events)
    active = {0}
    rows = {}
    for e in events:
        row = rows.setdefault(e["iteration"] // block, {"children": 0, "passed": 0, "admitted": 0, "genes": None})
        if e["event"] == "child" and conditions(e["e"]) >= 1:
            row["children"] += 1
            row["passed"] += bool(e.get("passed_mc"))
        elif e["event"] == "pair_created":
            genes[e["pair"]] = genes_of_env.get(e["env"], [0.0] * 5)
            active.add(e["pair"])
            row["admitted"] += conditions(genes[e["pair"]]) >= 1
        elif e["event"] == "pair_retired":
            active.discard(e["pair"])
        elif e["event"] == "reproduction":
            now = [genes[p] for p in active]
            row["genes"] = [sum(g[i] for g in now) / len(now) for i in (0, 2, 4)]
    print("| iterations | challenging children | passed MC | admitted | active pairs' mean roughness | mean gap top "
          "| mean stump top |")
    print("|---|---|---|---|---|---|---|")
    for b in sorted(rows):
        r = rows[b]
        g = " | ".join(f"{x:.2f}" for x in r["genes"]) if r["genes"] else "- | - | -"
        last = min(b * block + block, run.next_iteration) - 1
        print(f"| {b * block}–{last} | {r['children']} | {r['passed']} | {r['admitted']} | {g} |")


def frontier_pairs(run):
    events = run._events
    genes_of_env = genes_by_env(events)
    happened = {}
    for e in events:
        if e["event"] in ("solved", "pair_retired"):
            happened.setdefault((e["event"], e["pair"]), e["iteration"])
    children = {}
    for e in events:
        if e["event"] == "child":
            row = children.setdefault(e["parent"], [0, 0, 0])
            row[0] += 1
            row[1] += bool(e.get("passed_mc"))
        elif e["event"] == "pair_created" and e["pair"] > 0:
            children.setdefault(e["parent"], [0, 0, 0])[2] += 1
    print("\n| pair | environment | created | solved | retired | children | passed MC | admitted |")
    print("|---|---|---|---|---|---|---|---|")
    for e in events:
        if e["event"] != "pair_created" or conditions(genes_of_env.get(e["env"], [0.0] * 5)) < 1:
            continue
        pair = e["pair"]
        cells = [str(happened.get((event, pair), "-")) for event in ("solved", "pair_retired")]
        made = " | ".join(str(n) for n in children.get(pair, [0, 0, 0]))
        print(f"| {pair} | {e['env']} | {e['iteration']} | {' | '.join(cells)} | {made} |")


def retired_unsolved(run, stats):
    print("\n| pair | environment | retired at | best, first 30 ES steps | best, last 10 |")
    print("|---|---|---|---|---|")
    for e in run._events:
        if e["event"] == "pair_retired" and not e["solved"]:
            s = stats[stats.pair == e["pair"]]
            print(f"| {e['pair']} | {e['env']} | {e['iteration']} | {s.head(30).score.max():.1f} | "
                  f"{s.tail(10).score.max():.1f} |")


def time_limit(run, stats, since):
    late = stats[stats.pair.isin(stats[stats.iteration >= since].pair.unique())]
    early = stats[stats.iteration < since - 50]
    print("\n| evaluations ≥ 230 | of them finished | ran out of time (2,000 steps) |")
    print("|---|---|---|")
    for label, frame in ((f"pairs active from iteration {since}", late), (f"before iteration {since - 50}", early)):
        high = frame[frame.score >= 230]
        print(f"| {label}: {len(high)} | {int(high.finished.sum())} | {int((high.eval_steps >= 2000).sum())} |")
    print("\n| pair | environment | 2,000 steps | 2,500 | 3,000 |")
    print("|---|---|---|---|---|")
    for pair, frame in late.groupby("pair"):
        if not (frame.score >= 230).any() or frame.solved.any():
            continue
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as file:
            json.dump([run.theta(pair, best=True).tolist()], file)
        try:
            policy = poet.Policy.load(file.name)
        finally:
            os.unlink(file.name)
        env = run.encoding(pair)
        cells = []
        for steps in (2000, 2500, 3000):
            r = poet.evaluate(policy, env, [env["seed"]], max_steps=steps)
            how = "finished" if r["finished"][0] else ("fell" if r["fell"][0] else "out of time")
            cells.append(f"{r['return'][0]:.1f} in {r['steps'][0]} steps, {how}")
        print(f"| {pair} | {env['config']['name']} | " + " | ".join(cells) + " |")


def main(argv):
    parser = run_parser(__doc__)
    parser.add_argument("--block", type=int, default=50, help="iterations per row (default 50)")
    parser.add_argument("--since", type=int, default=200, help="the frontier's first iteration (default 200)")
    args = parser.parse_args(argv)
    if args.block < 1 or args.since < 50:
        parser.error("--block must be at least 1 and --since at least 50")
    run = open_run(parser, args.run_dir)
    stats = run.pair_stats
    blocks(run, args.block)
    frontier_pairs(run)
    retired_unsolved(run, stats)
    time_limit(run, stats, args.since)


if __name__ == "__main__":
    main(sys.argv[1:])
