#!/usr/bin/env bash
# What each worker costs the coordinator: one fixed POET workload run with --local-workers K for several K, and
# for each run the coordinator's resident memory (VmRSS at the end, VmHWM), its threads, its CPU seconds (utime +
# stime of all its threads, from /proc/PID/stat, read once it has exited and before it is reaped, so nothing is
# missed) per result, and the workers' resident memory. Every run must end in the same checkpoint (a run is a
# function of its config and seed, however many workers run it), which the script checks. Prints a Markdown table.
#   bash bench/coordinator_per_worker.sh BUILD_DIR [ITERATIONS] [K ...]     defaults: 8 iterations; K = 2 16 64 256
# The workload is the quick preset (deploy/configs/quick.textproto) from the shipped walker. The status socket is
# on a free port (127.0.0.1:0) and read for poet_workers, to check that all K workers joined. --local-workers
# takes at most 256; the workers get one thread each (the machine's cores / K, at least 1).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

usage_error() {
  echo "coordinator_per_worker.sh: $*" >&2
  echo "usage: bash bench/coordinator_per_worker.sh BUILD_DIR [ITERATIONS] [K ...]" >&2
  exit 2
}
[ $# -ge 1 ] || usage_error "expected BUILD_DIR"
build=$(cd "$1" 2>/dev/null && pwd) || usage_error "$1 is not a directory"
iterations=${2:-8}
shift $(($# >= 2 ? 2 : 1))
counts=("$@")
[ ${#counts[@]} -gt 0 ] || counts=(2 16 64 256)
[[ $iterations =~ ^[1-9][0-9]*$ ]] || usage_error "ITERATIONS must be a positive integer, got $iterations"
for k in "${counts[@]}"; do
  [[ $k =~ ^[1-9][0-9]*$ ]] && ((k <= 256)) || usage_error "each K must be an integer in 1..256, got $k"
done
coordinator=$build/coordinator/poet-coordinator
[ -x "$coordinator" ] && [ -x "$build/worker/poet-worker" ] ||
  usage_error "$build has no poet-coordinator and poet-worker (build first)"

scratch=$(mktemp -d /tmp/poet-per-worker.XXXXXX)
measurer=
cleanup() {
  # the measurer stops its coordinator (SIGTERM, then SIGKILL) and any worker left behind, on any signal
  if [ -n "$measurer" ] && kill -0 "$measurer" 2>/dev/null; then
    kill -TERM "$measurer" 2>/dev/null || true
    wait "$measurer" 2>/dev/null || true
  fi
  rm -rf "$scratch"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# measure.py OUT LOG -- COMMAND...: runs COMMAND, samples it and its children every 0.2 s, writes OUT (JSON)
cat >"$scratch/measure.py" <<'EOF'
import json, os, re, signal, statistics, subprocess, sys, time, urllib.request

out, log = sys.argv[1], sys.argv[2]
command = sys.argv[4:]
tick = os.sysconf("SC_CLK_TCK")
page_kb = os.sysconf("SC_PAGE_SIZE") // 1024

def status(pid):
    try:
        text = open(f"/proc/{pid}/status").read()
    except OSError:
        return {}
    return {k: int(v.split()[0]) for k, v in re.findall(r"^(VmRSS|VmHWM|Threads):\s+(.*)$", text, re.M)}

def cpu_seconds(pid):
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / tick  # utime + stime of the whole thread group

def children(pid):
    found = set()
    try:
        for task in os.listdir(f"/proc/{pid}/task"):
            found.update(int(c) for c in open(f"/proc/{pid}/task/{task}/children").read().split())
    except OSError:
        pass
    return found

def rss_kb(pid):
    try:
        return int(open(f"/proc/{pid}/statm").read().split()[1]) * page_kb
    except OSError:
        return 0

process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=open(log, "w"), start_new_session=True)
pid = process.pid
workers_seen = set()

def stop(*_):
    # the coordinator stops its workers on SIGTERM; whatever outlives it is killed
    try:
        process.terminate()
        process.wait(timeout=10)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
    except OSError:
        pass
    for w in workers_seen:
        try:
            os.kill(w, signal.SIGKILL)
        except OSError:
            pass
    sys.exit(130)

signal.signal(signal.SIGTERM, stop)
signal.signal(signal.SIGINT, stop)

peak = {"VmRSS": 0, "VmHWM": 0, "Threads": 0}
last = {}
worker_rss = []       # each sample's workers' RSS (kB each), taken once a second
workers_joined = 0
address = None
start = time.monotonic()
next_slow = start
while not os.waitid(os.P_PID, pid, os.WEXITED | os.WNOHANG | os.WNOWAIT):
    s = status(pid)
    if s:
        last = s
        for k in peak:
            peak[k] = max(peak[k], s.get(k, 0))
    now = time.monotonic()
    if now >= next_slow:
        next_slow = now + 1
        kids = children(pid)
        workers_seen |= kids
        sample = [r for r in (rss_kb(w) for w in kids) if r > 0]
        if sample:
            worker_rss.append(sample)
        if address is None:
            m = re.search(r"status: http://([0-9.:]+)", open(log).read())
            address = m.group(1) if m else None
        if address:
            try:
                metrics = urllib.request.urlopen(f"http://{address}/metrics", timeout=1).read().decode()
                m = re.search(r"^poet_workers(?:\{[^}]*\})? ([0-9.e+]+)$", metrics, re.M)
                if m:
                    workers_joined = max(workers_joined, int(float(m.group(1))))
            except OSError:
                pass
    time.sleep(0.2)
wall = time.monotonic() - start
cpu = cpu_seconds(pid)  # a zombie still has its threads' times, until reaped
code = process.wait()
every = [r for sample in worker_rss for r in sample]
json.dump({"exit": code, "wall_s": wall, "cpu_s": cpu, "rss_end_kb": last.get("VmRSS", 0),
           "hwm_kb": peak["VmHWM"], "threads_max": peak["Threads"], "workers_joined": workers_joined,
           "worker_rss_median_kb": statistics.median(every) if every else 0,
           "worker_rss_max_kb": max(every) if every else 0}, open(out, "w"))
sys.exit(0 if code == 0 else 1)
EOF

uptime_before=$(cut -d' ' -f1-3 /proc/loadavg)
for k in "${counts[@]}"; do
  dir=$scratch/run-$k
  python3 "$scratch/measure.py" "$dir.json" "$dir.log" -- "$coordinator" \
    --config "$root/deploy/configs/quick.textproto" --start-from "$root/data/walkers/flat-walker.json" \
    --iterations "$iterations" --run-dir "$dir" --local-workers "$k" --status-address 127.0.0.1:0 --quiet &
  measurer=$!
  wait "$measurer" || { echo "coordinator_per_worker.sh: the run on $k workers failed, see its log:" >&2; tail -5 "$dir.log" >&2; exit 1; }
  measurer=
  echo "$k $dir" >>"$scratch/runs"
done
uptime_after=$(cut -d' ' -f1-3 /proc/loadavg)

python3 - "$scratch/runs" "$iterations" "$(nproc)" "$uptime_before" "$uptime_after" <<'EOF'
import csv, hashlib, json, sys

runs_file, iterations, cores, before, after = sys.argv[1:]
rows = []
for line in open(runs_file):
    k, path = line.split()
    m = json.load(open(f"{path}.json"))
    stats = list(csv.DictReader(open(f"{path}/pair_stats.csv")))
    rollouts = int(stats[-1]["run_rollouts"])
    digest = hashlib.sha256(open(f"{path}/checkpoint.pb", "rb").read()).hexdigest()
    rows.append((int(k), m, rollouts, digest))

if len({r[3] for r in rows}) != 1:
    sys.exit("coordinator_per_worker.sh: the runs ended in different checkpoints: "
             + ", ".join(f"{r[0]} workers: {r[3][:12]}" for r in rows))
short = [r[0] for r in rows if r[1]["workers_joined"] < r[0]]
print(f"{iterations} iterations of the quick preset from the shipped walker, {rows[0][2]:,} rollouts each run, all "
      f"ending in one checkpoint ({rows[0][3][:12]}); {cores} cores; load average (1, 5, 15 min) {before} before, "
      f"{after} after")
if short:
    print(f"(fewer workers joined than started in the runs on {short}: see poet_workers)")
print()
print("| workers | joined | wall time | coordinator CPU | CPU per 1,000 results | coordinator RSS at the end | VmHWM "
      "| threads | worker RSS (median, max) |")
print("|---|---|---|---|---|---|---|---|---|")
for k, m, rollouts, _ in rows:
    print(f"| {k} | {m['workers_joined']} | {m['wall_s']:.1f} s | {m['cpu_s']:.2f} s | "
          f"{1000 * m['cpu_s'] / rollouts:.3f} s | {m['rss_end_kb'] / 1024:.1f} MB | {m['hwm_kb'] / 1024:.1f} MB | "
          f"{m['threads_max']} | {m['worker_rss_median_kb'] / 1024:.1f}, {m['worker_rss_max_kb'] / 1024:.1f} MB |")
if len(rows) >= 2:
    a, b = min(rows, key=lambda r: r[0]), max(rows, key=lambda r: r[0])
    extra = b[0] - a[0]
    print()
    print(f"per worker added ({a[0]} -> {b[0]}): RSS {(b[1]['rss_end_kb'] - a[1]['rss_end_kb']) / extra:.0f} kB, "
          f"VmHWM {(b[1]['hwm_kb'] - a[1]['hwm_kb']) / extra:.0f} kB, "
          f"CPU {(b[1]['cpu_s'] - a[1]['cpu_s']) / extra * 1000:.1f} ms over the run "
          f"({(b[1]['cpu_s'] / b[1]['wall_s'] - a[1]['cpu_s'] / a[1]['wall_s']) / extra * 1000:.2f} ms per wall second), "
          f"threads {(b[1]['threads_max'] - a[1]['threads_max']) / extra:.2f}")
EOF
