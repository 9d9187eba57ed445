"""What the Python checks of tests/ share (tests/deploy, tests/dashboard, tests/cluster): their outcomes, the CI
rule for a missing tool, free loopback ports, and the deploy checks' command line and outcome."""

import os
import signal
import socket
import time

EXIT_SKIP = 77  # ctest's SKIP_RETURN_CODE for these checks


class Failed(Exception):
    pass


class Skipped(Exception):
    pass


def in_ci():
    return os.environ.get("CI", "").strip().lower() in ("1", "true", "yes")


def missing_tool(message):
    """A tool a check needs is absent: a failure under CI (deploy/install-deps.sh installs it), a skip elsewhere."""
    if in_ci():
        raise Failed(message + " (CI=true: deploy/install-deps.sh installs it)")
    raise Skipped(message + " (run deploy/install-deps.sh)")


def free_port():
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def add_build_arguments(parser):
    """The deploy checks' arguments: the repository, the build tree and every executable the build produces."""
    parser.add_argument("--source", required=True, help="the repository root")
    parser.add_argument("--build-dir", required=True, help="the CMake build directory")
    parser.add_argument("--binary", action="append", default=[], metavar="NAME=PATH",
                        help="an executable the build produces (every one of them)")


def run_check(name, check):
    """Runs check() with SIGTERM and SIGINT as failures (cleanup still runs); prints the outcome under `name` and
    returns the exit code: 0 passed, 1 failed, EXIT_SKIP skipped."""

    def interrupted(signum, _frame):
        raise Failed(f"interrupted by signal {signum}")

    signal.signal(signal.SIGTERM, interrupted)
    signal.signal(signal.SIGINT, interrupted)
    started = time.monotonic()
    try:
        check()
    except Skipped as e:
        print(f"SKIPPED {name}: {e}")
        return EXIT_SKIP
    except Failed as e:
        print(f"FAILED {name}: {e}")
        return 1
    print(f"{name}: passed in {time.monotonic() - started:.1f} s")
    return 0
