# Sourced by the scripts that compare two benchmark programs (math_cost.sh, dispatch_compare.sh): each program run
# in turn, ROUNDS times, so that a change in the machine's load falls on both.
#   alternate_rounds ROUNDS SCRATCH NAME=PROGRAM... -- BENCHMARK_ARGS...
# writes SCRATCH/NAME-ROUND.json (Google Benchmark's JSON) for each, and sets load_before and load_after (the
# machine's load averages around the runs).
alternate_rounds() {
  local rounds=$1 scratch=$2
  shift 2
  local programs=()
  while [ $# -gt 0 ] && [ "$1" != -- ]; do
    programs+=("$1")
    shift
  done
  shift  # the --
  load_before=$(cut -d' ' -f1-3 /proc/loadavg)
  local round pair
  for ((round = 1; round <= rounds; round++)); do
    for pair in "${programs[@]}"; do
      "${pair#*=}" "$@" --benchmark_format=json >"$scratch/${pair%%=*}-$round.json"
    done
  done
  load_after=$(cut -d' ' -f1-3 /proc/loadavg)
}
