#!/usr/bin/env python3
"""Captures the example answers of docs/reference/http.md from a live coordinator's status socket.

    python3 docs/reference/examples/capture.py 127.0.0.1:8580 --at-iteration 4

Waits until the run's iteration reaches --at-iteration, then asks each route for its example path (the route
table's example_path, coordinator/status/status_route_table.h) and writes beside this script, one file a route:
a JSON answer cut to a few entries a list and indented (<slug>.json), a few lines of /metrics (metrics.txt), and
for the dashboard and the pictures the status, content type and size of the answer (<slug>.txt). It is the one way
to refresh them: poet-reference http embeds them; the unit tests parse each JSON answer strictly into its route's
message of proto/status.proto (or, for the episode, check its keys), check each line of metrics.txt names a
declared family, and each size line the route's content type.
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
EPISODE = ("pair-episode.json", "/pairs/1/episode")
# file → the path asked, for the answers shown by their status line, content type and size
SIZES = {
    "dashboard.txt": "/",
    "run-pictures.txt": "/pictures/scores.svg",
    "pair-pictures.txt": "/pictures/pairs/1/course.svg",
}
# the families whose lines metrics.txt shows (HELP, TYPE and samples)
METRIC_FAMILIES = ["poet_iteration", "poet_env_steps_total", "poet_annecs"]
KEEP = 3  # entries kept of each list


def fetch(address, path):
    """The answer's status, content type and body."""
    with urllib.request.urlopen(f"http://{address}{path}", timeout=60) as answer:
        return answer.status, answer.headers["Content-Type"], answer.read()


def get(address, path):
    return json.loads(fetch(address, path)[2])


def episode_trimmed(episode):
    """The episode with its ground points, boxes and frames cut to KEEP, each entry whole."""
    return {k: v[:KEEP] if k in ("ground", "boxes", "frames") else v for k, v in episode.items()}


def dumped(value, indent=""):
    """JSON indented by two spaces a level, with a list that holds no list or object on one line."""
    inner = indent + "  "
    if isinstance(value, dict) and value:
        items = [f"{inner}{json.dumps(k)}: {dumped(v, inner)}" for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + indent + "}"
    if isinstance(value, list) and any(isinstance(v, (list, dict)) for v in value):
        return "[\n" + ",\n".join(inner + dumped(v, inner) for v in value) + "\n" + indent + "]"
    return json.dumps(value, ensure_ascii=False)


def metric_lines(text, families):
    """The exposition's lines of these families (HELP, TYPE, samples), in the order /metrics writes them."""
    def family(line):
        if line.startswith("# "):
            return line.split(" ")[2]
        return line.split("{")[0].split(" ")[0]
    return [line for line in text.splitlines() if line and family(line) in families]


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
    name, path = EPISODE
    (here / name).write_text(dumped(episode_trimmed(get(args.address, path))) + "\n", encoding="utf-8")
    print(f"{name}: GET {path}")
    status, _, body = fetch(args.address, "/metrics")
    lines = metric_lines(body.decode("utf-8"), METRIC_FAMILIES)
    (here / "metrics.txt").write_text("\n".join(lines) + "\n", encoding="utf-8")
    print("metrics.txt: GET /metrics")
    for name, path in SIZES.items():
        status, content_type, body = fetch(args.address, path)
        (here / name).write_text(f"{status} {content_type}, {len(body):,} bytes\n", encoding="utf-8")
        print(f"{name}: GET {path}")


if __name__ == "__main__":
    main()
