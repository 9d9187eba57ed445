#!/usr/bin/env python3
"""Captures the example answers of docs/reference/http.md from a live coordinator's status socket.

    python3 docs/reference/examples/capture.py 127.0.0.1:8580 --at-iteration 4

Waits until the run's iteration reaches --at-iteration, takes each JSON route's answer (the route table's example
path, coordinator/status/status_route_table.h), cuts its lists to a few entries and writes it, indented, to
<slug>.json beside this script. poet-reference http embeds them; the unit tests parse each strictly into its
route's message of proto/status.proto.
"""

import argparse
import json
import pathlib
import sys
import time
import urllib.request

# file → the path asked, as the route table's example_path
ROUTES = {
    "status.json": "/status",
    "pairs.json": "/pairs",
    "pair.json": "/pairs/1",
    "archive.json": "/archive",
    "workers.json": "/workers",
    "events.json": "/events?since=0&limit=3",
    "health.json": "/healthz",
}
KEEP = 3  # entries kept of each list


def get(address, path):
    with urllib.request.urlopen(f"http://{address}{path}", timeout=10) as answer:
        return json.loads(answer.read())


def trimmed(value):
    """The answer with each of its lists cut to KEEP entries; an event, a line of events.jsonl, is kept whole."""
    if isinstance(value, list):
        return [trimmed(v) for v in value[:KEEP]]
    if isinstance(value, dict):
        return {k: v[:KEEP] if k == "events" else trimmed(v) for k, v in value.items()}
    return value


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("address", help="HOST:PORT of the status socket")
    parser.add_argument("--at-iteration", type=int, default=4, help="wait until the run's iteration reaches this")
    parser.add_argument("--timeout", type=float, default=600, help="seconds to wait for it")
    args = parser.parse_args()

    deadline = time.monotonic() + args.timeout
    while get(args.address, "/status")["iteration"] < args.at_iteration:
        if time.monotonic() > deadline:
            sys.exit(f"capture.py: the run did not reach iteration {args.at_iteration} in {args.timeout} s")
        time.sleep(0.2)
    here = pathlib.Path(__file__).resolve().parent
    for name, path in ROUTES.items():
        answer = trimmed(get(args.address, path))
        (here / name).write_text(json.dumps(answer, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
        print(f"{name}: GET {path}")


if __name__ == "__main__":
    main()
