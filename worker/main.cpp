// poet-worker: the stateless worker. Connects to a coordinator and runs the rollouts it is sent, until the
// coordinator shuts it down or a signal stops it.
//   poet-worker --connect tcp://HOST:PORT | --coordinator-file RUN_DIR/coordinator.endpoint
//               [--threads N] [--name NAME] [--curve-keys DIR] [--log-level L]
// It says Hello (protocol version, build fingerprint, threads) every second until welcomed, runs Jobs on its
// threads and answers each with a Result, heartbeats, and reconnects (Hello again) when the coordinator falls
// silent for its liveness window. SIGINT/SIGTERM abandon the job in hand, send Goodbye and exit 0 within a
// second. Exit codes: 0 shut down or stopped, 1 runtime error, 2 bad command line or refused by the coordinator.
// The command line and the run are worker_main (worker_command.h).

#include "worker/worker_command.h"

int main(int argc, char** argv) { return poet::worker::worker_main(argc, argv); }
