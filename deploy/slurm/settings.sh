# shellcheck shell=bash
# POET on SLURM: the one place to edit. submit.sh and the batch scripts read this file (each job reads it again
# when it starts, so a change reaches the next job of a chain). Every value may also come from the environment of
# the `submit.sh` command, which wins.

# Where POET is: a checkout with its build (build/) or an unpacked bundle (bin/, `deploy/bundle.sh`), on a file
# system every node sees.
POET_HOME=${POET_HOME:-$HOME/poet}
# A checkout's build tree, when it is not POET_HOME/build.
POET_BUILD=${POET_BUILD:-$POET_HOME/build}
# The run directory, on the shared file system: the checkpoint, the logs, and coordinator.endpoint while a
# coordinator runs. One directory a run; the same directory resumes it.
POET_RUN_DIR=${POET_RUN_DIR:-$HOME/poet-runs/quick}
# The run config: a preset's name (deploy/configs/NAME.textproto, or configs/ in a bundle) or a file's path.
POET_PRESET=${POET_PRESET:-quick}
# A new run's first policy (the quick preset starts from the shipped walker); empty: random parameters.
POET_START_FROM=${POET_START_FROM-walkers/flat-walker.json}

# The cluster's share: worker nodes in the run's job, worker processes on each (one a core, one thread each), the
# limit of each job, and the partition (empty: the cluster's default).
POET_WORKER_NODES=${POET_WORKER_NODES:-3}
POET_WORKERS_PER_NODE=${POET_WORKERS_PER_NODE:-2}
POET_TIME=${POET_TIME:-24:00:00}
POET_PARTITION=${POET_PARTITION:-}
# Seconds before the time limit the coordinator is asked to stop at the next iteration boundary (SIGUSR1). It must
# cover the longest iteration (a transfer round: docs/slurm.md says how long) and the start-up; SLURM may send the
# warning up to a minute early, so POET_TIME must exceed it by more than a minute (submit.sh refuses less).
POET_STOP_LEAD=${POET_STOP_LEAD:-600}
# Anything else sbatch needs on this cluster (an account, a QOS), as words: POET_SBATCH_ARGS="--account=abc123".
POET_SBATCH_ARGS=${POET_SBATCH_ARGS:-}

# CURVE keys, made on first use (poetctl keygen), mode 0700: workers need the key pair in it to be let in. On the
# shared file system, beside the run directory rather than in it.
POET_KEYS=${POET_KEYS:-$POET_RUN_DIR.keys}
# The coordinator's status socket (port 0: any free port; its log says which). On a login node:
# ssh -L 8580:NODE:PORT, then poetctl status.
POET_STATUS_ADDRESS=${POET_STATUS_ADDRESS:-127.0.0.1:0}
# The job socket's port on the coordinator's node (*: any free one, which coordinator.endpoint tells the workers),
# and the name workers reach that node by (empty: its host name; give an address where host names do not resolve
# between nodes).
POET_JOB_PORT=${POET_JOB_PORT:-*}
POET_ADVERTISE_HOST=${POET_ADVERTISE_HOST:-}
