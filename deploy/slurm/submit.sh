#!/bin/bash
# POET on SLURM, from a login node. Edit settings.sh (beside this script) first.
#   bash deploy/slurm/submit.sh run          the run as one heterogeneous job (coordinator + workers), which
#                                            submits the next link at each time limit until the run is finished
#   bash deploy/slurm/submit.sh workers N    N extra workers as a job array, joining the run whenever it runs
#   bash deploy/slurm/submit.sh stop         the coordinator stops at its next iteration boundary, and the chain
#                                            ends there (poetctl stop --at-boundary); `run` resumes it later
# Prints the job id (sbatch --parsable). Any further arguments go to sbatch (before the first component's options
# for `run`).
set -u
POET_SLURM_DIR=$(cd "$(dirname "$0")" && pwd)
export POET_SLURM_DIR
# shellcheck source=common.sh
. "$POET_SLURM_DIR/common.sh"

usage() {
  sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}
[ $# -ge 1 ] || usage
what=$1
shift
# shellcheck disable=SC2206  # words, as settings.sh says
extra=($POET_SBATCH_ARGS)
partition=()
[ -n "$POET_PARTITION" ] && partition=(--partition "$POET_PARTITION")
mkdir -p "$(dirname "$POET_RUN_DIR")"
logs="$(dirname "$POET_RUN_DIR")/slurm-logs"
mkdir -p "$logs"

case $what in
run)
  # SLURM checks limits about every 30 s, so its warning may come up to a minute before the lead: a limit within a
  # minute of the lead could see it as the job starts, before the batch script can take it (the job then fails
  # to launch).
  limit=$(poet_time_seconds "$POET_TIME") ||
    die "POET_TIME=$POET_TIME is no SLURM time limit (minutes, M:S, H:M:S, D-H, D-H:M or D-H:M:S)"
  [[ $POET_STOP_LEAD =~ ^[0-9]+$ ]] || die "POET_STOP_LEAD=$POET_STOP_LEAD is no number of seconds"
  if [ -n "$limit" ] && [ "$limit" -le $((10#$POET_STOP_LEAD + 60)) ]; then
    die "POET_TIME=$POET_TIME ($limit s) leaves no minute beyond POET_STOP_LEAD=$POET_STOP_LEAD s: SLURM may send its warning up to a minute early, as the job starts; give a longer limit or a shorter lead"
  fi
  # component 0: the coordinator (one task; its threads run the dispatch and the checkpoint); component 1: the
  # workers, a process a core. Options before the first `:` are the job's as a whole (SLURM takes --time,
  # --signal and --requeue from there).
  exec sbatch --parsable --job-name "poet-$(basename "$POET_RUN_DIR")" --requeue --time "$POET_TIME" \
    --signal "B:USR1@$POET_STOP_LEAD" --output "$logs/run-%j.out" "${partition[@]}" "${extra[@]}" "$@" \
    --nodes 1 --ntasks 1 --cpus-per-task 1 \
    : "${partition[@]}" --time "$POET_TIME" --nodes "$POET_WORKER_NODES" --ntasks-per-node "$POET_WORKERS_PER_NODE" --cpus-per-task 1 \
    "$POET_SLURM_DIR/poet-run.sbatch"
  ;;
workers)
  if [ $# -lt 1 ] || ! [[ $1 =~ ^[1-9][0-9]*$ ]]; then usage; fi
  n=$1
  shift
  exec sbatch --parsable --job-name "poet-workers-$(basename "$POET_RUN_DIR")" --array "0-$((n - 1))" \
    --time "$POET_TIME" --ntasks 1 --cpus-per-task 1 --output "$logs/workers-%A_%a.out" "${partition[@]}" \
    "${extra[@]}" "$@" "$POET_SLURM_DIR/poet-workers.sbatch"
  ;;
stop)
  exec "$(poet_bin poetctl)" stop "$POET_RUN_DIR" --at-boundary
  ;;
*) usage ;;
esac
