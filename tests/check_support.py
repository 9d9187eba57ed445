"""What the Python checks of tests/ share (tests/deploy, tests/dashboard): their outcomes, the CI rule for a
missing tool, and free loopback ports."""

import os
import socket

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
