#!/usr/bin/env python3
"""A run's solved environments ranked by how hard they are for the walker the run started from.

    PYTHONPATH=build/python python3 experiments/hardest_solved.py runs/enhanced data/walkers/flat-walker.json

Hardness here is the starting walker's mean return on the course over --seeds terrain seeds (on a CPPN course the
seed changes only the initial push): the lower, the further the run had to go from where it began. Works for either
kind of environment; Table 1's levels describe only obstacle courses. Prints the solved pairs, hardest first.
"""

import argparse
import sys

import poet


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir")
    parser.add_argument("start_walker", help="the policy file the run started from (--start-from)")
    parser.add_argument("--seeds", type=int, default=5, help="terrain seeds 0..N-1 (default 5)")
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args(argv)
    try:
        run = poet.Run(args.run_dir)
        walker = poet.Policy.load(args.start_walker)
    except ValueError as error:
        parser.error(str(error))
    solved = run.pairs[run.pairs["solved"].notna()]
    rows = []
    for pair, row in solved.iterrows():
        result = poet.evaluate(walker, run.encoding(pair), list(range(args.seeds)), threads=args.threads)
        rows.append((result["return"].mean(), int(result["finished"].sum()), pair, row))
    rows.sort(key=lambda r: r[0])
    print(f"{'pair':>4} {'environment':<16} {'created':>7} {'solved':>6} {'start walker: mean return':>26} {'finished':>8}")
    for mean, finished, pair, row in rows:
        print(f"{pair:>4} {row['env']:<16} {row['created']:>7} {int(row['solved']):>6} {mean:>26.1f} "
              f"{finished:>5}/{args.seeds}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
