#!/usr/bin/env python3
"""Steps per second of poet.VectorWalkerEnv with random actions, beside the C++ walker_bench's per-core figure
for the same work (BM_RandomActions/env_flat: the environment alone on course r1), measured in one run.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_vector_env.py --build-dir build [--num-envs 64]

Prints each figure and the Python module's steps per second per thread as a fraction of the C++ figure."""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np


def cpp_steps_per_second(build_dir):
    bench = os.path.join(build_dir, "bench", "walker_bench")
    out = subprocess.run([bench, "--benchmark_filter=BM_RandomActions/env_flat$", "--benchmark_format=json",
                          "--benchmark_repetitions=3", "--benchmark_report_aggregates_only=true"],
                         check=True, capture_output=True, text=True).stdout
    rows = json.loads(out)["benchmarks"]
    return next(r["items_per_second"] for r in rows if r.get("aggregate_name") == "median")


def python_steps_per_second(num_envs, threads, steps):
    import poet

    env = poet.VectorWalkerEnv("r1", num_envs, threads=threads)
    env.reset(seed=0)
    rng = np.random.default_rng(5)
    batches = steps // num_envs
    actions = rng.uniform(-1, 1, (batches, num_envs, poet.ACT_DIM)).astype(np.float32)
    start = time.perf_counter()
    for batch in actions:
        env.step(batch)
    return batches * num_envs / (time.perf_counter() - start)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build-dir", default="build")
    parser.add_argument("--steps", type=int, default=80000)
    parser.add_argument("--num-envs", type=int, default=64)
    args = parser.parse_args()
    cpp = cpp_steps_per_second(args.build_dir)
    print(f"C++ walker_bench BM_RandomActions/env_flat: {cpp:,.0f} steps/s (one core)")
    for threads in (1, 2):
        py = python_steps_per_second(args.num_envs, threads, args.steps)
        print(f"poet.VectorWalkerEnv({args.num_envs} envs, threads={threads}): {py:,.0f} steps/s, "
              f"{py / threads / cpp:.2f} of the C++ figure per thread")
    return 0


if __name__ == "__main__":
    sys.exit(main())
