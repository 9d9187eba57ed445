# Sourced by the benchmarks that time one ES-alone workload on poet-worker processes (rtt_cost.sh, theta_bytes.sh):
# a scratch directory removed at exit, the processes they start (append to `pids`) stopped and reaped at exit or on
# a signal, a free loopback port, and the workload's config. Needs `set -euo pipefail` in the caller.

# make_scratch NAME: sets `scratch` to a new directory /tmp/poet-NAME.XXXXXX and `pids` to none; both go at exit.
make_scratch() {
  scratch=$(mktemp -d "/tmp/poet-$1.XXXXXX")
  pids=()
  trap cleanup_scratch EXIT
  trap 'exit 130' INT TERM
}
cleanup_scratch() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  rm -rf "$scratch"
}

free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

# write_es_config FILE STEPS PERTURBATIONS [MAX_STEPS]: ES alone on the flat course (seed 5, terrain seed 0), STEPS
# ES steps of PERTURBATIONS mirrored pairs, one checkpoint at the end; episodes of at most MAX_STEPS (default 2000).
write_es_config() {
  cat >"$1" <<CONFIG
# proto-file: proto/poet.proto
# proto-message: poet.pb.RunConfig
mode: ES_ALONE
seed: 5
iterations: $2
checkpoint_interval: $2
es { perturbations: $3 }
es_alone { target { encoding { name: "flat" } seed: 0 } }
walker { max_steps: ${4:-2000} }
CONFIG
}
