#!/usr/bin/env python3
"""Latency of a real poet-coordinator's status socket: requests on one kept-alive connection, and /status on the
status port and /healthz on the probes' port while CONNECTIONS slowloris clients each send one header line every
LINE_EVERY seconds to the port(s) HOLD names.

Usage: python3 bench/status_latency.py BUILD_DIR [--connections 200] [--line-every 1.5] [--seconds 20]
                                                 [--hold status|health|both]

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


def probe(port, path="/healthz"):
    """Seconds for one GET on a fresh connection, or None when it failed or took over PROBE_TIMEOUT."""
    started = time.monotonic()
    try:
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=PROBE_TIMEOUT)
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
    return (f"{name}: {len(answered)} of {attempts} answered; p50 {statistics.median(ms):.1f} ms, p95 {p95:.1f} ms, "
            f"max {ms[-1]:.1f} ms; {late} over {KUBELET_TIMEOUT:.0f} s (failed probes)")


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
    """Connections that each send a request line, then one header line every `every` seconds, never ending it."""

    def __init__(self, port, count, every):
        self.sockets = []
        for _ in range(count):
            s = socket.create_connection(("127.0.0.1", port), timeout=5)
            s.sendall(b"GET /status HTTP/1.1\r\nHost: x\r\n")
            self.sockets.append(s)
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.trickle, args=(every,), daemon=True)
        self.thread.start()

    def trickle(self, every):
        n = 0
        while not self.stop.wait(every):
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
    args = parser.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    binary = os.path.join(args.build_dir, "coordinator", "poet-coordinator")
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
        with open(log, "w") as err:
            coordinator = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=err)
        status_port = int(wait_for_log(log, r"status: http://127\.0\.0\.1:(\d+)/status"))
        health_port = int(wait_for_log(log, r"health: http://127\.0\.0\.1:(\d+)/healthz")) if has_health else None
        print(f"load average at start: {' '.join(f'{x:.2f}' for x in os.getloadavg())} ({os.cpu_count()} cores)")

        ms = kept_alive(status_port)
        print(f"kept-alive connection, 20 x GET /healthz: first {ms[0]:.1f} ms, the rest median "
              f"{statistics.median(ms[1:]):.1f} ms, max {max(ms[1:]):.1f} ms")
        idle = [probe(status_port) for _ in range(10)]
        print(summary("idle, status port /healthz", idle, len(idle)))

        held = {"status": [status_port], "health": [health_port], "both": [status_port, health_port]}[args.hold]
        slow = [Slowloris(port, args.connections, args.line_every) for port in held if port]
        time.sleep(2)  # the pool is taken
        targets = {"status port /status": (status_port, "/status")}
        if health_port:
            targets["health port /healthz"] = (health_port, "/healthz")
        times = {name: [] for name in targets}
        deadline = time.monotonic() + args.seconds

        def probe_until_deadline(name, target):  # one thread per target: a stuck port does not slow the other's
            port, path = target
            while time.monotonic() < deadline:
                times[name].append(probe(port, path))
                time.sleep(0.5)

        probers = [threading.Thread(target=probe_until_deadline, args=item) for item in targets.items()]
        for t in probers:
            t.start()
        for t in probers:
            t.join()
        print(f"under {args.connections} slowloris connections on the {args.hold} port(s) (a header line every "
              f"{args.line_every} s), {args.seconds:.0f} s of probes:")
        for name in targets:
            print("  " + summary(name, times[name], len(times[name])))
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
