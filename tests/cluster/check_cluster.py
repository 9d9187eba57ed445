#!/usr/bin/python3
"""A coordinator and its workers on hosts of their own, with the network between them broken.

Each host is a network namespace with one veth link to a Linux bridge, which lives in a namespace of its own (the
switch), on a private /24 (10.231.N.0/24, N from this process's id). The coordinator and the workers are the
built binaries, started by `ip netns exec`: the coordinator host runs poet-coordinator, worker host w1 two
poet-worker processes and w2 one, each of one thread. Every scenario runs a small POET config on them and on local
threads, and the two runs must end in the same run files, byte for byte.

  partition        w1's link goes down for 8 s (its switch port), then up: its workers must be back within
                   1.5 s of the heal (the coordinator's log, confirmed by its status socket's /workers)
  coordinator_cut  the coordinator host's link goes down for 20 s, cutting every worker off, then up: the same
  round_trip       the run with the workers connected directly, then through tests/support/delay_relay.py at a
                   100 ms round trip (the kernel may lack netem): both identical; the slowdown is printed
  bandwidth        tbf at 10 Mbit/s on both ends of w1's and w2's links: identical, and no worker lost (the
                   coordinator's /metrics and log)

Needs root, ip and tc (iproute2), and the kernel's network namespaces, bridge, veth and tbf; without them the check
is skipped (exit 77) saying why. Namespaces are named poetcl<PID>-<host>, so parallel runs cannot collide, and are
deleted with every process and file the check started or made, also on failure, SIGTERM or its own deadline. A
run killed outright (SIGKILL) still ends its processes, which die with it; the next run deletes the namespaces and
the directory it left.
"""

import argparse
import contextlib
import ctypes
import datetime
import glob
import hashlib
import http.client
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

REPOSITORY = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RELAY = os.path.join(REPOSITORY, "tests", "support", "delay_relay.py")  # shared with bench/rtt_cost.sh
sys.path.insert(0, os.path.join(REPOSITORY, "tests"))
from check_support import Failed, Skipped, run_check  # noqa: E402

DEADLINE_S = 170  # the whole check, inside ctest's TIMEOUT
JOB_PORT = 5555  # fixed ports: each namespace is a host of its own, nothing else binds there
RELAY_PORT = 5556
STATUS = ("127.0.0.1", 8580)  # on the coordinator host's loopback, which a cut of its link leaves up
PREFIX = "poetcl"
RUN_FILES = ("checkpoint.pb", "events.jsonl", "pair_stats.csv", "annecs.csv")

# A small POET run: short episodes from random θ, a child admitted at every reproduction and transfers every
# other iteration, so the run's batches are of every kind; an iteration takes about a second on two cores.
CONFIG = """mode: POET
seed: 7
iterations: 1000
es { perturbations: 4 }
walker { max_steps: 200 }
poet { mutation_interval: 2 transfer_interval: 2 repro_threshold: -1000 mc_low: -1000 mc_high: 1000
       max_children: 4 max_admitted: 1 active_cap: 3 }
"""

# The round trip's workload: real episodes (up to 2,000 steps) from the shipped walker, so that a job outlasts a round
# trip as in a real run; ES steps of 32 rollouts on one pair (the schema's intervals make no child this early).
REAL_EPISODES_CONFIG = """mode: POET
seed: 1
iterations: 1000
es { perturbations: 16 init_lr: 0.01 }
"""

# The worker hosts and the workers each runs; the partition cuts w1, which has more of them, so that the run is
# slowed while it is away and is still going when it comes back.
WORKERS = {"w1": ["w1a", "w1b"], "w2": ["w2a"]}

STARTED = time.monotonic()


def log(message):
    print(f"[{time.monotonic() - STARTED:6.1f} s] {message}", flush=True)


def run_tool(argv, what):
    r = subprocess.run(argv, capture_output=True, text=True, timeout=30)
    if r.returncode != 0:
        raise Failed(f"{what}: {' '.join(argv)} exited {r.returncode}: {r.stderr.strip()}")
    return r.stdout


def wall_time(run_dir):
    """The run's wall time as it recorded it (the last line of wall_times.csv)."""
    with open(os.path.join(run_dir, "wall_times.csv")) as f:
        return float(f.read().splitlines()[-1].split(",")[1])


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


# ---------------------------------------------------------------------------------------------------------
# hosts


_libc = ctypes.CDLL(None, use_errno=True)
_CLONE_NEWNET = 0x40000000


def _die_with_parent():
    # the children end with this process even if it is killed outright (a ctest timeout); `ip netns exec`
    # execs the command, which keeps this
    _libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


def _setns(fd):
    if _libc.setns(fd, _CLONE_NEWNET) != 0:
        raise OSError(ctypes.get_errno(), "setns")


def left_by_a_dead_run(pid):
    """Whether a namespace or directory named with `pid` is left by a run that is gone (killed outright, its
    clean-up never ran): no check_cluster process has that id."""
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            return b"check_cluster" not in f.read()
    except OSError:
        return True


def sweep_stale():
    """Deletes the namespaces and directories of earlier runs that are gone."""
    for line in run_tool(["ip", "netns", "list"], "listing namespaces").splitlines():
        name = line.split()[0] if line.strip() else ""
        m = re.fullmatch(PREFIX + r"(\d+)-\w+", name)
        if m and left_by_a_dead_run(m.group(1)):
            log(f"deleting {name}, left by a run that is gone")
            subprocess.run(["ip", "netns", "del", name], capture_output=True, timeout=30)
    for path in glob.glob(os.path.join(tempfile.gettempdir(), "poet_cluster_*_*")):
        m = re.fullmatch(r"poet_cluster_(\d+)_.*", os.path.basename(path))
        if m and left_by_a_dead_run(m.group(1)):
            log(f"deleting {path}, left by a run that is gone")
            shutil.rmtree(path, ignore_errors=True)


class Cluster:
    """The hosts, the switch and the links between them. Host `c` is the coordinator's; its address is .1."""

    def __init__(self, hosts):
        self.tag = f"{PREFIX}{os.getpid()}"
        self.subnet = f"10.231.{os.getpid() % 256}"  # clear of Docker's 10.213.0.0/16 and 10.214.0.0/24
        self.hosts = hosts
        self.made = []  # namespaces made, deleted in reverse order

    def ns(self, host):
        return f"{self.tag}-{host}"

    def address(self, host):
        return f"{self.subnet}.{1 if host == 'c' else 10 + self.hosts.index(host)}"

    def port(self, host):
        """The host's link as the switch sees it: its port on the bridge."""
        return f"port-{host}"

    def _add_namespace(self, host):
        name = self.ns(host)
        r = subprocess.run(["ip", "netns", "add", name], capture_output=True, text=True, timeout=30)
        if r.returncode != 0:
            raise Skipped(f"no network namespaces here: ip netns add: {r.stderr.strip()}")
        self.made.append(name)

    def build(self):
        self._add_namespace("sw")
        r = subprocess.run(["ip", "-n", self.ns("sw"), "link", "add", "br0", "type", "bridge"],
                           capture_output=True, text=True, timeout=30)
        if r.returncode != 0:
            raise Skipped(f"no Linux bridge in this kernel: ip link add type bridge: {r.stderr.strip()}")
        run_tool(["ip", "-n", self.ns("sw"), "link", "set", "br0", "up"], "the bridge")
        for host in self.hosts:
            self._add_namespace(host)
            ns = self.ns(host)
            r = subprocess.run(["ip", "-n", self.ns("sw"), "link", "add", self.port(host), "type", "veth", "peer",
                                "name", "eth0", "netns", ns], capture_output=True, text=True, timeout=30)
            if r.returncode != 0:
                raise Skipped(f"no veth pairs in this kernel: ip link add type veth: {r.stderr.strip()}")
            run_tool(["ip", "-n", self.ns("sw"), "link", "set", self.port(host), "master", "br0", "up"], host)
            run_tool(["ip", "-n", ns, "addr", "add", self.address(host) + "/24", "dev", "eth0"], host)
            run_tool(["ip", "-n", ns, "link", "set", "eth0", "up"], host)
            run_tool(["ip", "-n", ns, "link", "set", "lo", "up"], host)
        log(f"hosts {', '.join(f'{h} {self.address(h)}' for h in self.hosts)} on a bridge in {self.ns('sw')}")

    def set_link(self, host, up):
        run_tool(["ip", "-n", self.ns("sw"), "link", "set", self.port(host), "up" if up else "down"],
                 f"{host}'s link {'up' if up else 'down'}")

    def shape(self, host, qdisc):
        """`qdisc` (tc's words) on both ends of the host's link: what reaches it and what it sends."""
        for ns, dev in ((self.ns("sw"), self.port(host)), (self.ns(host), "eth0")):
            r = subprocess.run(["tc", "-n", ns, "qdisc", "add", "dev", dev, "root"] + qdisc,
                               capture_output=True, text=True, timeout=30)
            if r.returncode != 0:
                raise Skipped(f"tc qdisc add {' '.join(qdisc)}: {r.stderr.strip()} (no tbf in this kernel?)")

    def qdisc_stats(self, host):
        out = run_tool(["tc", "-s", "-n", self.ns("sw"), "qdisc", "show", "dev", self.port(host)], "tc -s")
        m = re.search(r"Sent (\d+) bytes (\d+) pkt \(dropped (\d+), overlimits (\d+)", out)
        return {"bytes": int(m.group(1)), "dropped": int(m.group(3)), "overlimits": int(m.group(4))} if m else {}

    def exec_argv(self, host, argv):
        return ["ip", "netns", "exec", self.ns(host)] + argv

    def http_get(self, host, address, path, timeout=2):
        """GET on a socket made inside the host's namespace (a socket keeps the namespace it was made in): the
        answer's status and body."""
        with open(f"/run/netns/{self.ns(host)}") as there, open("/proc/thread-self/ns/net") as here:
            _setns(there.fileno())
            try:
                sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            finally:
                _setns(here.fileno())
        try:
            sock.settimeout(timeout)
            sock.connect(address)
            connection = http.client.HTTPConnection(*address, timeout=timeout)
            connection.sock = sock
            connection.request("GET", path)
            response = connection.getresponse()
            return response.status, response.read().decode()
        finally:
            sock.close()

    def destroy(self):
        for name in reversed(self.made):
            subprocess.run(["ip", "netns", "del", name], capture_output=True, timeout=30)
        self.made = []


# ---------------------------------------------------------------------------------------------------------
# processes


class Processes:
    """Children in their own process groups, output in files; every group killed at the end."""

    def __init__(self, root):
        self.root = root
        self.children = {}

    def start(self, name, argv):
        with open(os.path.join(self.root, name + ".log"), "wb") as out:
            p = subprocess.Popen(argv, stdout=out, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                 start_new_session=True, preexec_fn=_die_with_parent)
        self.children[name] = p
        return p

    def log_text(self, name):
        with contextlib.suppress(FileNotFoundError), \
                open(os.path.join(self.root, name + ".log"), encoding="utf-8", errors="replace") as f:
            return f.read()
        return ""

    def wait(self, name, timeout):
        """The exit code, or None when it did not end within `timeout` s."""
        with contextlib.suppress(subprocess.TimeoutExpired):
            return self.children[name].wait(timeout=max(0.1, timeout))
        return None

    def kill_all(self):
        for p in self.children.values():
            with contextlib.suppress(ProcessLookupError):
                os.killpg(p.pid, signal.SIGKILL)
        for p in self.children.values():
            with contextlib.suppress(subprocess.TimeoutExpired):
                p.wait(timeout=10)

    def tails(self):
        return "".join(f"\n--- {name} (last lines) ---\n{self.log_text(name)[-1500:]}" for name in self.children)


# ---------------------------------------------------------------------------------------------------------
# a run


def log_time(line):
    """The wall-clock time (s since the epoch) of a spdlog line "[2026-11-28 11:40:23.904] ..."."""
    m = re.match(r"\[(\d{4}-\d\d-\d\d \d\d:\d\d:\d\d\.\d{3})\]", line)
    return datetime.datetime.strptime(m.group(1), "%Y-%m-%d %H:%M:%S.%f").timestamp() if m else None


class Run:
    """A poet-coordinator on host c with its workers on w1 and w2, watched through its status socket."""

    def __init__(self, args, cluster, processes, root, label, workload, relay=False):
        self.cluster, self.processes, self.label = cluster, processes, label
        self.run_dir = os.path.join(root, label)
        self.name = f"coordinator-{label}"
        self.metrics = {}  # the last /metrics read: family -> value
        listen = ("127.0.0.1" if relay else cluster.address("c"), JOB_PORT)
        argv = [args.coordinator] + workload + ["--run-dir", self.run_dir, "--quiet", "--listen",
                                                f"tcp://{listen[0]}:{listen[1]}", "--status-address",
                                                f"{STATUS[0]}:{STATUS[1]}"]
        if not relay:
            argv.append("--open-port")  # the bridge's address, without CURVE
        self.coordinator = processes.start(self.name, cluster.exec_argv("c", argv))
        endpoint = f"tcp://{cluster.address('c')}:{JOB_PORT}"
        self.relay = None
        if relay:
            self.relay = f"relay-{label}"
            processes.start(self.relay, cluster.exec_argv("c", [
                sys.executable, RELAY, "--listen", f"{cluster.address('c')}:{RELAY_PORT}",
                "--target", f"{listen[0]}:{listen[1]}", "--rtt-ms", str(args.rtt_ms)]))
            self.wait_for("the relay", lambda: "listening" in processes.log_text(self.relay), 10)
            endpoint = f"tcp://{cluster.address('c')}:{RELAY_PORT}"
        self.wait_for("the status socket", lambda: self.get("/healthz") is not None, 30)
        self.workers = {}  # worker name -> host
        for host, names in WORKERS.items():
            for worker in names:
                self.workers[worker] = host
                processes.start(f"{worker}-{label}", cluster.exec_argv(host, [
                    args.worker, "--connect", endpoint, "--threads", "1", "--name", worker]))
        self.started = time.monotonic()

    def get(self, path):
        """The status socket's answer, or None while it cannot answer (starting, or the run over)."""
        try:
            status, body = self.cluster.http_get("c", STATUS, path)
        except (OSError, http.client.HTTPException):
            return None
        return body if status == 200 else None

    def alive(self):
        return self.coordinator.poll() is None

    def wait_for(self, what, probe, timeout):
        deadline = time.monotonic() + timeout
        while True:
            if probe():
                return
            if not self.alive():
                raise Failed(f"{self.label}: the coordinator exited {self.coordinator.returncode} while waiting for "
                             f"{what}")
            if time.monotonic() > deadline:
                raise Failed(f"{self.label}: no {what} within {timeout} s")
            time.sleep(0.05)

    def iteration(self):
        """The iteration the run does next, as /status says (JSON leaves out a 0), or None."""
        body = self.get("/status")
        return json.loads(body).get("iteration", 0) if body else None

    def listed_workers(self):
        """The names of the workers /workers lists (JSON leaves out an empty list)."""
        body = self.get("/workers")
        return [w["address"] for w in json.loads(body).get("workers", [])] if body else []

    def read_metrics(self):
        body = self.get("/metrics")
        if body:
            self.metrics = {m.group(1): float(m.group(2))
                            for m in re.finditer(r"^(poet_\w+) ([-0-9.e+]+)$", body, re.MULTILINE)}

    def wait_running(self, iteration):
        """Until every worker is listed and the run has reached `iteration`."""
        def probe():
            return (self.iteration() or 0) >= iteration and set(self.listed_workers()) >= set(self.workers)
        self.wait_for(f"every worker listed at iteration {iteration}", probe, 60)

    def sleep(self, seconds):
        """Waits, reading /metrics twice a second; the run must not end meanwhile."""
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            if not self.alive():
                raise Failed(f"{self.label}: the run ended before the network was healed; give it more iterations")
            self.read_metrics()
            time.sleep(min(0.5, max(0.0, end - time.monotonic())))

    def joined_since(self, wall_time):
        """Worker name -> the log's time of its first "joined" at or after `wall_time`."""
        joined = {}
        for line in self.processes.log_text(self.name).splitlines():
            m = re.search(r"worker (\S+) \(\d+ threads\) joined", line)
            t = log_time(line)
            if m and t is not None and t >= wall_time - 0.001 and m.group(1) not in joined:
                joined[m.group(1)] = t
        return joined

    def wait_back(self, names, healed_at, timeout=15):
        """Seconds from the heal until each of `names` joined again (the coordinator's log), once /workers lists
        them all."""
        def probe():
            self.read_metrics()
            return set(names) <= set(self.joined_since(healed_at)) and set(names) <= set(self.listed_workers())
        self.wait_for(f"{', '.join(names)} back after the heal", probe, timeout)
        joined = self.joined_since(healed_at)
        return {n: joined[n] - healed_at for n in names}

    def finish(self):
        """Waits for the run's end; checks the coordinator and every worker exited 0. Returns the run's wall time."""
        while self.alive() and time.monotonic() - self.started < DEADLINE_S:
            self.read_metrics()
            time.sleep(0.5)
        code = self.processes.wait(self.name, 5)
        if code != 0:
            raise Failed(f"{self.label}: the coordinator exited {code}, not 0")
        for worker in self.workers:
            code = self.processes.wait(f"{worker}-{self.label}", 15)
            if code != 0:
                raise Failed(f"{self.label}: worker {worker} exited {code}, not 0, after the run")
        return wall_time(self.run_dir)

    def stop_relay(self):
        """Stops the relay; what it carried: (connections, bytes to the coordinator, bytes from it)."""
        p = self.processes.children[self.relay]
        p.send_signal(signal.SIGTERM)
        self.processes.wait(self.relay, 10)
        m = re.search(r"relayed (\d+) connections, (\d+) bytes to the target, (\d+) bytes from it",
                      self.processes.log_text(self.relay))
        if not m:
            raise Failed(f"{self.label}: the relay did not say what it carried:\n{self.processes.log_text(self.relay)}")
        return tuple(int(g) for g in m.groups())

    def log_lines(self, pattern):
        return re.findall(pattern, self.processes.log_text(self.name), re.MULTILINE)


def threads_run(args, processes, root, workload):
    """The reference: the same workload (the coordinator's config arguments) on two local threads. Its directory."""
    run_dir = os.path.join(root, "threads")
    processes.start("threads", [args.coordinator] + workload + ["--run-dir", run_dir, "--threads", "2", "--quiet",
                                                                "--status-address", ""])
    code = processes.wait("threads", DEADLINE_S)
    if code != 0:
        raise Failed(f"the run on threads exited {code}")
    log(f"on 2 threads: {wall_time(run_dir):.1f} s, checkpoint {sha256(os.path.join(run_dir, 'checkpoint.pb'))[:16]}")
    return run_dir


def expect_identical(reference, run):
    for name in RUN_FILES:
        with open(os.path.join(reference, name), "rb") as a, open(os.path.join(run.run_dir, name), "rb") as b:
            if a.read() != b.read():
                raise Failed(f"{run.label}: {name} differs from the run on threads")
    log(f"{run.label}: {', '.join(RUN_FILES)} identical to the run on threads (checkpoint "
        f"{sha256(os.path.join(run.run_dir, 'checkpoint.pb'))[:16]})")


def counters(run):
    return (f"workers joined {run.metrics.get('poet_workers_joined_total', float('nan')):.0f}, "
            f"lost {run.metrics.get('poet_workers_lost_total', float('nan')):.0f}")


# ---------------------------------------------------------------------------------------------------------
# the scenarios


def cut_and_heal(args, cluster, processes, root, workload, host, seconds):
    """`host`'s link down for `seconds` once the run is under way, then up; its workers (every worker when the
    host is the coordinator's) must be back within args.back_s, and the run must end as on threads."""
    reference = threads_run(args, processes, root, workload)
    run = Run(args, cluster, processes, root, f"cut-{host}", workload)
    run.wait_running(1)
    cut_off = [w for w, h in run.workers.items() if host == "c" or h == host]
    cluster.set_link(host, False)
    log(f"{host}'s link down at iteration {run.iteration()}: {', '.join(cut_off)} cut off")
    run.sleep(seconds)
    cluster.set_link(host, True)
    healed_at = time.time()
    log(f"{host}'s link up after {seconds} s, at iteration {run.iteration()}")
    back = run.wait_back(cut_off, healed_at)
    each = ", ".join(f"{w} {s:.2f} s" for w, s in sorted(back.items()))
    log(f"back after the heal: {each}")
    wall = run.finish()
    removed = len(run.log_lines(r"silent for \d+ ms: removed"))
    log(f"{run.label}: {wall:.1f} s; {counters(run)}; {removed} removed as silent")
    expect_identical(reference, run)
    slowest = max(back.values())
    if slowest > args.back_s:
        raise Failed(f"a worker came back {slowest:.2f} s after the heal, more than {args.back_s} s")
    return f"cut {seconds} s, back within {slowest:.2f} s of the heal ({each}), run {wall:.1f} s, {counters(run)}"


def round_trip(args, cluster, processes, root, workload):
    """The run with the workers connected directly, then through the relay: both as on threads."""
    reference = threads_run(args, processes, root, workload)
    direct = Run(args, cluster, processes, root, "direct", workload)
    direct_wall = direct.finish()
    expect_identical(reference, direct)
    relayed = Run(args, cluster, processes, root, "relay", workload, relay=True)
    relayed_wall = relayed.finish()
    connections, up, down = relayed.stop_relay()
    expect_identical(reference, relayed)
    if connections < len(relayed.workers) or up == 0 or down == 0:
        raise Failed(f"the relay carried {connections} connections, {up} and {down} bytes: not every worker's")
    return (f"{direct_wall:.1f} s directly, {relayed_wall:.1f} s through the relay at {args.rtt_ms:g} ms round "
            f"trip: {relayed_wall / direct_wall - 1:+.0%}; the relay carried {connections} connections, {up} bytes to "
            f"the coordinator, {down} from it")


def bandwidth(args, cluster, processes, root, workload):
    """Both worker hosts' links shaped to 10 Mbit/s: the run as on threads, and no worker lost."""
    reference = threads_run(args, processes, root, workload)
    for host in WORKERS:
        cluster.shape(host, ["tbf", "rate", "10mbit", "burst", "32kbit", "latency", "400ms"])
    log(f"tbf 10 Mbit/s on both ends of {', '.join(WORKERS)}'s links")
    run = Run(args, cluster, processes, root, "shaped", workload)
    wall = run.finish()
    expect_identical(reference, run)
    lost = run.metrics.get("poet_workers_lost_total")
    joined = run.metrics.get("poet_workers_joined_total")
    gone = run.log_lines(r"^.*(?:silent for|left:).*$")
    if lost != 0 or joined != len(run.workers) or gone:
        raise Failed(f"workers lost: {counters(run)}; the coordinator's log: {gone}")
    for w in run.workers:
        if "it is gone" in processes.log_text(f"{w}-{run.label}"):
            raise Failed(f"worker {w} lost the coordinator")
    shaped = ", ".join(f"{h} {s['bytes']} bytes ({s['overlimits']} overlimits, {s['dropped']} dropped)"
                       for h, s in ((h, cluster.qdisc_stats(h)) for h in WORKERS))
    return f"{wall:.1f} s at 10 Mbit/s, {counters(run)}; towards the workers {shaped}"


# name: (the check, its config, iterations, whether the first pair starts from the shipped walker)
SCENARIOS = {
    "partition": (lambda *a: cut_and_heal(*a, "w1", 8), CONFIG, 16, False),
    "coordinator_cut": (lambda *a: cut_and_heal(*a, "c", 20), CONFIG, 8, False),
    "round_trip": (round_trip, REAL_EPISODES_CONFIG, 4, True),
    "bandwidth": (bandwidth, CONFIG, 8, False),
}


def check(args):
    if os.geteuid() != 0:
        raise Skipped("needs root, to make network namespaces")
    for tool in ("ip", "tc"):
        if not shutil.which(tool):
            raise Skipped(f"{tool} is not on PATH (Debian package iproute2)")
    for binary in (args.coordinator, args.worker):
        if not os.access(binary, os.X_OK):
            raise Failed(f"not built: {binary}")
    sweep_stale()
    scenario, config, iterations, from_walker = SCENARIOS[args.scenario]
    root = tempfile.mkdtemp(prefix=f"poet_cluster_{os.getpid()}_")
    workload = ["--config", os.path.join(root, "run.textproto"), "--iterations", str(args.iterations or iterations)]
    if from_walker:
        workload += ["--start-from", os.path.join(REPOSITORY, "data", "walkers", "flat-walker.json")]
    with open(workload[1], "w") as f:
        f.write(config)
    cluster = Cluster(["c"] + list(WORKERS))
    processes = Processes(root)
    load = open("/proc/loadavg").read().split()[0]
    try:
        cluster.build()
        result = scenario(args, cluster, processes, root, workload)
        print(f"RESULT {args.scenario}: {result}; load {load} -> {open('/proc/loadavg').read().split()[0]}")
    except Failed as e:
        raise Failed(f"{e}{processes.tails()}") from None
    finally:
        # a second signal must not cut the clean-up short
        for s in (signal.SIGTERM, signal.SIGINT, signal.SIGALRM):
            signal.signal(s, signal.SIG_IGN)
        processes.kill_all()
        cluster.destroy()
        shutil.rmtree(root, ignore_errors=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenario", choices=list(SCENARIOS))
    parser.add_argument("--coordinator", required=True, help="poet-coordinator")
    parser.add_argument("--worker", required=True, help="poet-worker")
    parser.add_argument("--iterations", type=int, help="the runs' iterations (default: the scenario's)")
    parser.add_argument("--rtt-ms", type=float, default=100, help="round_trip: the relay's round trip")
    parser.add_argument("--back-s", type=float, default=1.5,
                        help="partition, coordinator_cut: the most a worker may take to come back after the heal")
    args = parser.parse_args()

    def overdue(_signum, _frame):
        raise Failed(f"not done within {DEADLINE_S} s")

    signal.signal(signal.SIGALRM, overdue)
    signal.alarm(DEADLINE_S)
    return run_check(f"cluster_{args.scenario}", lambda: check(args))


if __name__ == "__main__":
    sys.exit(main())
