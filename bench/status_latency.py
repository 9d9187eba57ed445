#!/usr/bin/env python3
"""Latency of a real poet-coordinator's status socket: requests on one kept-alive connection, and /status on the
status port and /healthz on the probes' port while CONNECTIONS slowloris clients each send one header line every
LINE_EVERY seconds (or, with --silent, nothing) to the port(s) HOLD names.

Usage: python3 bench/status_latency.py BUILD_DIR [--connections 200] [--line-every 1.5] [--seconds 20]
                                                 [--hold status|health|both] [--addresses N] [--silent]
                                                 [--nofile SOFT[:HARD]] [--binary PATH]

With --addresses N the slow connections come from 127.0.0.2 ... 127.0.0.(N+1), spread evenly (Linux routes all
of 127.0.0.0/8 to the loopback interface), and each port is probed both from 127.0.0.1, an address with no slow
connection, and from 127.0.0.2, one of the crowd's; without it everything comes from 127.0.0.1. --nofile starts the
coordinator with that soft RLIMIT_NOFILE (a systemd service's and a login shell's default is 1024), and with :HARD
that hard one too (else it stays); this script raises its own to its hard limit.

The coordinator runs the quick preset with --listen and no worker, so it waits for workers and uses no CPU; with
--health-address (when this build has it) the probes' own listener is measured too. Probes open a fresh
connection each, every 0.5 s (each port on its own thread), and wait at most 5 s; over 1 s is a failed probe for
kubelet's default timeoutSeconds. Prints the machine's load average at the start and the end. Stops the
coordinator, closes every socket and removes its directory on exit, Ctrl-C included.
"""

import argparse
import http.client
import os
import re
import resource
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time

PROBE_TIMEOUT = 5.0  # seconds a probe may wait
KUBELET_TIMEOUT = 1.0  # kubelet's default timeoutSeconds
PROMPT = 0.1  # seconds: the bound the status server keeps under a crowd


def wait_for_log(path, pattern, timeout=30.0):
    """Group 1 of the first match of pattern in the file, once it appears."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with open(path, errors="replace") as f:
            m = re.search(pattern, f.read())
        if m:
            return m.group(1)
        time.sleep(0.05)
    sys.exit(f"no log line matching {pattern!r} in {path}")


def probe(port, path="/healthz", source="127.0.0.1"):
    """Seconds for one GET on a fresh connection from source, or None when it failed or took over PROBE_TIMEOUT."""
    started = time.monotonic()
    try:
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=PROBE_TIMEOUT, source_address=(source, 0))
        conn.request("GET", path)
        response = conn.getresponse()
        response.read()
        conn.close()
        return time.monotonic() - started if response.status == 200 else None
    except (OSError, http.client.HTTPException):
        return None


def summary(name, times, attempts):
    answered = [t for t in times if t is not None]
    if not answered:
        return f"{name}: 0 of {attempts} answered within {PROBE_TIMEOUT:.0f} s"
    ms = sorted(t * 1000 for t in answered)
    p95 = ms[min(len(ms) - 1, int(0.95 * len(ms)))]
    late = sum(1 for t in times if t is None or t > KUBELET_TIMEOUT)
    prompt = sum(1 for t in times if t is not None and t <= PROMPT)
    return (f"{name}: {len(answered)} of {attempts} answered, {prompt} within {PROMPT * 1000:.0f} ms; p50 "
            f"{statistics.median(ms):.1f} ms, p95 {p95:.1f} ms, max {ms[-1]:.1f} ms; {late} over "
            f"{KUBELET_TIMEOUT:.0f} s (failed probes)")


def kept_alive(port, requests=20):
    """Milliseconds of each GET /healthz on one kept-alive connection."""
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=PROBE_TIMEOUT)
    out = []
    for _ in range(requests):
        started = time.monotonic()
        conn.request("GET", "/healthz")
        conn.getresponse().read()
        out.append((time.monotonic() - started) * 1000)
    conn.close()
    return out


class Slowloris:
    """Connections from the sources in turn that each send a request line, then one header line every `every`
    seconds, never ending it; or, silent, nothing at all."""

    def __init__(self, port, count, every, sources, silent):
        self.sockets = []
        self.silent = silent
        for i in range(count):
            s = socket.create_connection(("127.0.0.1", port), timeout=5, source_address=(sources[i % len(sources)], 0))
            if not silent:
                s.sendall(b"GET /status HTTP/1.1\r\nHost: x\r\n")
            self.sockets.append(s)
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.trickle, args=(every,), daemon=True)
        self.thread.start()

    def closed(self):
        """How many of the connections the server has closed (or reset)."""
        n = 0
        for s in self.sockets:
            s.setblocking(False)
            try:
                n += s.recv(1, socket.MSG_PEEK | socket.MSG_DONTWAIT) == b""
            except BlockingIOError:
                pass
            except OSError:
                n += 1
        return n

    def trickle(self, every):
        n = 0
        while not self.silent and not self.stop.wait(every):
            n += 1
            for s in self.sockets:
                try:
                    s.send(f"X-Slow-{n}: x\r\n".encode())
                except OSError:
                    pass  # the server hung up on this one

    def close(self):
        self.stop.set()
        self.thread.join()
        for s in self.sockets:
            s.close()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("build_dir")
    parser.add_argument("--connections", type=int, default=200)
    parser.add_argument("--line-every", type=float, default=1.5)
    parser.add_argument("--seconds", type=float, default=20)
    parser.add_argument("--hold", choices=["status", "health", "both"], default="status",
                        help="the port(s) the slowloris connections go to (each gets CONNECTIONS)")
    parser.add_argument("--addresses", type=int, default=0,
                        help="the slow connections come from this many addresses, 127.0.0.2 on (0: 127.0.0.1)")
    parser.add_argument("--silent", action="store_true", help="the slow connections send nothing")
    parser.add_argument("--nofile", help="the coordinator's soft RLIMIT_NOFILE, and :HARD its hard one")
    parser.add_argument("--binary", help="the poet-coordinator to measure (default: BUILD_DIR's)")
    args = parser.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    binary = args.binary or os.path.join(args.build_dir, "coordinator", "poet-coordinator")
    _, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))  # the crowd's sockets are this process's
    sources = [f"127.0.0.{2 + i}" for i in range(args.addresses)] or ["127.0.0.1"]
    probe_sources = ["127.0.0.1", "127.0.0.2"] if args.addresses else ["127.0.0.1"]
    if not os.access(binary, os.X_OK):
        sys.exit(f"no {binary}: build first")
    has_health = "--health-address" in subprocess.run([binary, "--help"], capture_output=True, text=True).stdout

    work = tempfile.mkdtemp(prefix="poet-status-latency.")
    coordinator = None
    slow = []
    try:
        command = [binary, "--config", os.path.join(root, "deploy", "configs", "quick.textproto"), "--run-dir",
                   os.path.join(work, "run"), "--quiet", "--listen", "tcp://127.0.0.1:*", "--status-address",
                   "127.0.0.1:0"]
        if has_health:
            command += ["--health-address", "127.0.0.1:0"]
        log = os.path.join(work, "coordinator.err")
        def limit_descriptors():
            if args.nofile:
                soft, _, limit = args.nofile.partition(":")
                resource.setrlimit(resource.RLIMIT_NOFILE, (int(soft), int(limit or hard)))

        with open(log, "w") as err:
            coordinator = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=err,
                                           preexec_fn=limit_descriptors)
        status_port = int(wait_for_log(log, r"status: http://127\.0\.0\.1:(\d+)/status"))
        health_port = int(wait_for_log(log, r"health: http://127\.0\.0\.1:(\d+)/healthz")) if has_health else None
        print(f"load average at start: {' '.join(f'{x:.2f}' for x in os.getloadavg())} ({os.cpu_count()} cores)")

        ms = kept_alive(status_port)
        print(f"kept-alive connection, 20 x GET /healthz: first {ms[0]:.1f} ms, the rest median "
              f"{statistics.median(ms[1:]):.1f} ms, max {max(ms[1:]):.1f} ms")
        idle = [probe(status_port) for _ in range(10)]
        print(summary("idle, status port /healthz", idle, len(idle)))

        held = {"status": [status_port], "health": [health_port], "both": [status_port, health_port]}[args.hold]
        slow = [Slowloris(port, args.connections, args.line_every, sources, args.silent) for port in held if port]
        time.sleep(2)  # the pool is taken
        targets = {}
        for source in probe_sources:
            crowd = "" if len(probe_sources) == 1 else (" from " + source + (", one of the crowd's" if source in
                                                                              sources else ", no slow connection"))
            targets["status port /status" + crowd] = (status_port, "/status", source)
            if health_port:
                targets["health port /healthz" + crowd] = (health_port, "/healthz", source)
        times = {name: [] for name in targets}
        deadline = time.monotonic() + args.seconds

        def probe_until_deadline(name, target):  # one thread per target: a stuck port does not slow the other's
            port, path, source = target
            while time.monotonic() < deadline:
                times[name].append(probe(port, path, source))
                time.sleep(0.5)

        probers = [threading.Thread(target=probe_until_deadline, args=item) for item in targets.items()]
        for t in probers:
            t.start()
        for t in probers:
            t.join()
        kind = "silent connections" if args.silent else f"slowloris connections (a header line every {args.line_every} s)"
        print(f"under {args.connections} {kind} on the {args.hold} port(s) from {len(sources)} address(es), "
              f"{args.seconds:.0f} s of probes:")
        for name in targets:
            print("  " + summary(name, times[name], len(times[name])))
        for port, crowd in zip([p for p in held if p], slow):
            print(f"  closed by the server: {crowd.closed()} of the {len(crowd.sockets)} slow connections to port "
                  f"{port}")
        print(f"load average at the end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    finally:
        for s in slow:
            s.close()
        if coordinator and coordinator.poll() is None:
            coordinator.send_signal(signal.SIGTERM)
            try:
                coordinator.wait(10)
            except subprocess.TimeoutExpired:
                coordinator.kill()
                coordinator.wait()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
