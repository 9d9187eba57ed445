#!/usr/bin/env python3
"""A projection, not a measurement: the core-hours and wall time of a POET run at the paper's sizes on W workers of
one core each, from figures measured elsewhere (steps per second per core, mean episode length, the coordinator's
results per CPU-second, θ copies per result, round-trip time), and the loop's batches as the engine runs them
(docs/cluster.md lists the assumptions). Prints Markdown tables.

    python3 bench/cluster_projection.py --steps-per-core-s 21000 --episode-steps 1330 \
        --results-per-coordinator-cpu-s 450000 --workers 64 256 1024
    python3 bench/cluster_projection.py ... --reach-iterations 3380 25200   # also the run cut at 3,380 and 25,200

The model, iteration by iteration (spec §3; the paper's preset deploy/configs/paper.textproto):
- active pairs N(t) = min(pairs, 1 + t // mutation_interval): one child admitted at every reproduction;
- every iteration: one batch of N ES steps (N × rollouts_per_step tasks), then one of N evaluations;
- every mutation_interval: a batch of max_children minimal-criterion evaluations, then one admission walk
  (N evaluations, N proposal ES steps, N evaluations: three batches);
- every transfer_interval with N > 1: the N(N−1) direct evaluations with the proposal ES steps of the candidates that
  take the proposal (all with the full test; --threshold-pass of them with the threshold test) in one batch, then the
  proposals' evaluations.
A batch's wall time is its makespan on W workers, tasks laid in order and each worker taking the next when free
(simulated with episode lengths drawn so that their mean is --episode-steps: a share at the 2,000-step limit, the rest
uniform in [50, 2,000), as bench/coordinator_bench.cpp's PacedEvaluator draws them), plus --round-trips-per-batch
round trips, plus the time the batch's first jobs take to leave the coordinator on its link (a θ for each of the
min(tasks, W) workers that start at once: bench/theta_bytes.sh checks that each worker of a step receives its θ).
"""
import argparse
import heapq
import random

MAX_STEPS = 2000
SHORT = 50


def draw_lengths(rng, n, mean):
    """n episode lengths with the given mean: a share at the limit, the rest uniform in [SHORT, MAX_STEPS)."""
    uniform_mean = (SHORT + MAX_STEPS) / 2
    at_limit = min(1.0, max(0.0, (mean - uniform_mean) / (MAX_STEPS - uniform_mean)))
    return [MAX_STEPS if rng.random() < at_limit else rng.uniform(SHORT, MAX_STEPS) for _ in range(n)]


class Makespans:
    """Makespan in environment steps of a batch of n tasks on w workers, simulated and remembered by (n, w)."""

    def __init__(self, mean, seed=1, samples=3):
        self.mean, self.samples, self.rng, self.cache = mean, samples, random.Random(seed), {}

    def __call__(self, n, w):
        if n == 0:
            return 0.0
        key = (n, w)
        if key not in self.cache:
            total = 0.0
            for _ in range(self.samples):
                lengths = draw_lengths(self.rng, n, self.mean)
                if n <= w:
                    total += max(lengths)
                    continue
                free = [0.0] * w  # when each worker is next free
                for length in lengths:
                    heapq.heappush(free, heapq.heappop(free) + length)
                total += max(free)
            self.cache[key] = total / self.samples
        return self.cache[key]


def batches(args, t):
    """The batches of iteration t as task counts, and how many of their tasks are ES tasks, in order."""
    n = min(args.pairs, 1 + t // args.mutation_interval)
    step = args.rollouts_per_step
    out = []
    if t > 0 and t % args.mutation_interval == 0:
        out += [args.max_children, n, n * step, n]
    out += [n * step, n]
    if t % args.transfer_interval == 0 and n > 1:
        candidates = n * (n - 1)
        proposals = round(candidates * args.threshold_pass)
        out += [candidates + proposals * step, proposals]
    return out


def batch_wall(args, n, workers, makespans):
    """Seconds of one batch of n tasks on `workers` workers: episodes, round trips, the first jobs' θs on the link."""
    first_wave = min(n, workers) * args.theta_bytes * 8 / (args.link_gbit * 1e9) if args.link_gbit > 0 else 0
    return makespans(n, workers) / args.steps_per_core_s + args.round_trips_per_batch * args.rtt_ms / 1000 + first_wave


def project(args, workers, first, last, makespans):
    """(rollouts, wall seconds, batches) of iterations first .. last − 1 on `workers` workers."""
    rollouts = wall = 0.0
    count = 0
    for t in range(first, last):
        for n in batches(args, t):
            rollouts += n
            wall += batch_wall(args, n, workers, makespans)
            count += 1
    return rollouts, wall, count


def hours(seconds):
    return f"{seconds / 3600:,.1f} h" if seconds < 72 * 3600 else f"{seconds / 86400:,.1f} days"


def main():
    p = argparse.ArgumentParser(description="Project a POET run at the paper's sizes onto W one-core workers.")
    p.add_argument("--steps-per-core-s", type=float, required=True, help="walker steps per second on one core")
    p.add_argument("--episode-steps", type=float, required=True, help="mean environment steps per rollout")
    p.add_argument("--results-per-coordinator-cpu-s", type=float, required=True,
                   help="results one coordinator core hands out per CPU-second (dispatch_bench)")
    p.add_argument("--gradient-ms", type=float, default=0,
                   help="the coordinator's CPU time for one ES step's gradient at --rollouts-per-step (es_bench)")
    p.add_argument("--theta-copies-per-result", type=float, nargs="+", default=[0.1],
                   help="θ copies sent per result in the loop's batches (dispatch_bench's thetas/job ÷ tasks/job): "
                        "one value, or one for each of --workers")
    p.add_argument("--theta-bytes", type=int, default=22449, help="bytes of one θ on the wire")
    p.add_argument("--task-bytes", type=float, default=0, help="bytes sent per task besides θ (theta_bytes.sh)")
    p.add_argument("--rtt-ms", type=float, default=0, help="round trip between coordinator and workers")
    p.add_argument("--round-trips-per-batch", type=float, default=1.0, help="round trips a batch waits (rtt_cost.sh)")
    p.add_argument("--link-gbit", type=float, default=0, help="the coordinator's link, Gbit/s (0: not counted)")
    p.add_argument("--workers", type=int, nargs="+", default=[64, 256, 1024])
    p.add_argument("--pairs", type=int, default=20)
    p.add_argument("--rollouts-per-step", type=int, default=512)
    p.add_argument("--iterations", type=int, default=25200)
    p.add_argument("--mutation-interval", type=int, default=200)
    p.add_argument("--transfer-interval", type=int, default=25)
    p.add_argument("--max-children", type=int, default=512)
    p.add_argument("--threshold-pass", type=float, default=1.0,
                   help="share of transfer candidates that get a proposal ES step: 1 = the full test")
    p.add_argument("--stage-iterations", type=int, nargs="+", default=[837, 1180, 1523],
                   help="iterations to cost at the run's steady state (very challenging: 1,180 ± 343)")
    p.add_argument("--reach-iterations", type=int, nargs="+", default=[],
                   help="also cost the run from its start, cut at each of these iterations (a bound on reaching a "
                        "level: docs/cluster.md derives 2,200 + 1,180 = 3,380 for very challenging)")
    args = p.parse_args()
    if len(args.theta_copies_per_result) not in (1, len(args.workers)):
        p.error("--theta-copies-per-result takes one value or one for each of --workers")
    copies = dict(zip(args.workers, args.theta_copies_per_result * len(args.workers)
                      if len(args.theta_copies_per_result) == 1 else args.theta_copies_per_result))

    makespans = Makespans(args.episode_steps)
    steady_from = args.mutation_interval * (args.pairs - 1)  # the iteration N reaches `pairs`
    print(f"Inputs: {args.steps_per_core_s:,.0f} steps/s a core, {args.episode_steps:,.0f} steps an episode, "
          f"{args.results_per_coordinator_cpu_s:,.0f} results a coordinator CPU-second and {args.gradient_ms:g} ms a "
          f"gradient, {args.pairs} pairs, {args.rollouts_per_step} rollouts an ES step, transfer every {args.transfer_interval} "
          f"iterations ({'full test' if args.threshold_pass >= 1 else f'threshold test, {args.threshold_pass:.0%} of candidates proposed'}), "
          f"RTT {args.rtt_ms:g} ms ({args.round_trips_per_batch:g} a batch), "
          f"link {f'{args.link_gbit:g} Gbit/s' if args.link_gbit > 0 else 'not counted'}; "
          f"all {args.pairs} pairs active from iteration {steady_from}")
    print()
    print("| workers | rollouts | environment steps | core-hours of episodes | wall time | batch efficiency "
          "| results/s (mean) | coordinator cores busy (mean) | link, mean |")
    print("|---|---|---|---|---|---|---|---|---|")
    for w in args.workers:
        rollouts, wall, _ = project(args, w, 0, args.iterations, makespans)
        steps = rollouts * args.episode_steps
        core_s = steps / args.steps_per_core_s
        efficiency = core_s / (wall * w)
        rate = rollouts / wall
        link = rate * (copies[w] * args.theta_bytes + args.task_bytes) * 8 / 1e9
        # the coordinator's cores: dispatching every result, and a gradient for every ES step's results
        coordinator = rate / args.results_per_coordinator_cpu_s + rate / args.rollouts_per_step * args.gradient_ms / 1000
        print(f"| {w:,} | {rollouts / 1e6:,.0f} M | {steps / 1e9:,.0f} G | {core_s / 3600:,.0f} | {hours(wall)} "
              f"| {efficiency:.2f} | {rate:,.0f} | {coordinator:.2f} | {link:.2f} Gbit/s |")
    print()
    print(f"At the steady state ({args.pairs} pairs, from iteration {steady_from}): the cost of a stage of so many "
          "iterations")
    print()
    print("| workers | " + " | ".join(f"{k:,} iterations" for k in args.stage_iterations) + " |")
    print("|---|" + "---|" * len(args.stage_iterations))
    period = args.mutation_interval  # a whole number of both cycles (200 = 8 × 25 at the paper's sizes)
    if period % args.transfer_interval:
        period *= args.transfer_interval
    for w in args.workers:
        # iterations steady_from .. steady_from + period, scaled: both cycles are periodic there
        rollouts, wall, _ = project(args, w, steady_from, steady_from + period, makespans)
        cells = []
        for k in args.stage_iterations:
            core_h = rollouts * args.episode_steps / args.steps_per_core_s / 3600 * k / period
            cells.append(f"{hours(wall * k / period)} ({core_h:,.0f} core-h)")
        print(f"| {w:,} | " + " | ".join(cells) + " |")
    if args.reach_iterations:
        print_reach(args, makespans)


def print_reach(args, makespans):
    """The run from iteration 0 cut at each of --reach-iterations: pairs grow as in the whole run's table."""
    print()
    print("From the start of the run, cut at so many iterations")
    print()
    print("| workers | " + " | ".join(f"{k:,} iterations" for k in args.reach_iterations) + " |")
    print("|---|" + "---|" * len(args.reach_iterations))
    for w in args.workers:
        cells = []
        for k in args.reach_iterations:
            rollouts, wall, _ = project(args, w, 0, k, makespans)
            core_h = rollouts * args.episode_steps / args.steps_per_core_s / 3600
            cells.append(f"{hours(wall)} ({core_h:,.0f} core-h)")
        print(f"| {w:,} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
