#!/usr/bin/env python3
"""Runs every command a documentation page shows, in order, and fails when one no longer runs as the page says.

    check_page_commands.py --repo REPO --build BUILD PAGE.md...

The pages' fenced blocks are run in a scratch workspace that links the repository's `deploy/`, `data/`,
`examples/` and the build tree as `build/`, so the pages' relative paths work and nothing is written in the
repository. A ```sh block is a list of commands (a line ending in a backslash goes on); a ```python block is one
script, run by Debian's Python with the build's module on its path. An HTML comment just before a block tells how
to run it:

    <!-- test: skip REASON -->      not run (the reason is printed)
    <!-- test: background -->       started and left running; the blocks after it run beside it
    <!-- test: wait -->             first wait for the background command to end, with exit 0
    <!-- test: exit N -->           each command of the block must exit with N instead of 0

Every block without a comment must exit 0 within the time limit. The status socket's default address is replaced by
a free loopback port, so that the test runs beside others: in the commands and scripts (127.0.0.1:8580,
localhost:8580), for poetctl ($POET_STATUS), and for a poet-coordinator that names none (--status-address).
Every process it starts is killed, and the workspace removed, when it ends, also on failure or SIGTERM; a process
it started dies with it even when it is killed outright (the parent-death signal)."""

import argparse
import ctypes
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

COMMAND_TIMEOUT_S = 300
BLOCK = re.compile(r"(?:<!--\s*test:\s*(?P<directive>[^>]*?)\s*-->\s*\n)?```(?P<lang>[a-z]*)[^\n]*\n(?P<body>.*?)\n```",
                   re.S)


def _die_with_parent():
    # PR_SET_PDEATHSIG (1): SIGKILL when this test dies; kept across exec, so bash -c's single command has it too
    ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL, 0, 0, 0)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def commands_of(body):
    """The commands of a sh block: comments and blank lines dropped, continuation lines joined."""
    commands, current = [], ""
    for line in body.split("\n"):
        stripped = line.strip()
        if not current and (not stripped or stripped.startswith("#")):
            continue
        current += line.rstrip()[:-1] + " " if line.rstrip().endswith("\\") else line
        if not line.rstrip().endswith("\\"):
            commands.append(current.strip())
            current = ""
    return commands


def blocks_of(page):
    text = open(page, encoding="utf-8").read()
    for m in BLOCK.finditer(text):
        lang = m.group("lang")
        if lang not in ("sh", "python"):
            continue
        line = text.count("\n", 0, m.start("body"))
        yield lang, (m.group("directive") or "").strip(), m.group("body"), line


class Workspace:
    def __init__(self, repo, build):
        self.dir = tempfile.mkdtemp(prefix="poet-docs-")
        for name in ("deploy", "data", "examples"):
            os.symlink(os.path.join(repo, name), os.path.join(self.dir, name))
        os.symlink(build, os.path.join(self.dir, "build"))
        self.port = free_port()
        self.env = dict(os.environ, PYTHONPATH=os.path.join(build, "python"), POET_STATUS=f"127.0.0.1:{self.port}",
                        POET_COORDINATOR_BIN=os.path.join(build, "coordinator", "poet-coordinator"),
                        MPLBACKEND="Agg")
        self.background = None

    def localise(self, text):
        return re.sub(r"(127\.0\.0\.1|localhost):8580\b", f"127.0.0.1:{self.port}", text)

    def localise_command(self, command):
        command = self.localise(command)
        if re.match(r"\S*poet-coordinator\b", command) and "--status-address" not in command:
            command += f" --status-address 127.0.0.1:{self.port}"
        return command

    def start(self, argv, **kwargs):
        # a session of its own, so the whole group (a coordinator and its workers) can be killed
        return subprocess.Popen(argv, cwd=self.dir, env=self.env, start_new_session=True, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True, preexec_fn=_die_with_parent, **kwargs)

    def close(self):
        if self.background and self.background.poll() is None:
            os.killpg(self.background.pid, signal.SIGKILL)
            self.background.wait()
        self.kill_strays()
        shutil.rmtree(self.dir, ignore_errors=True)

    def kill_strays(self):
        """Coordinators that Python's poet.start left running (a session of their own, by design) name the
        workspace in their command line."""
        for pid in filter(str.isdigit, os.listdir("/proc")):
            try:
                with open(f"/proc/{pid}/cmdline", "rb") as f:
                    cmdline = f.read().decode(errors="replace")
            except OSError:
                continue
            if self.dir in cmdline and int(pid) != os.getpid():
                try:
                    os.kill(int(pid), signal.SIGKILL)
                except OSError:
                    pass


def run(ws, argv, label, expected_exit):
    process = ws.start(argv)
    try:
        output, _ = process.communicate(timeout=COMMAND_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        output, _ = process.communicate()
        return f"{label}: still running after {COMMAND_TIMEOUT_S} s\n{output[-2000:]}"
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
    if process.returncode != expected_exit:
        return f"{label}: exit {process.returncode}, expected {expected_exit}\n{output[-3000:]}"
    return None


def wait_background(ws, page, line):
    if not ws.background:
        return f"{page}:{line}: `wait` with nothing in the background"
    try:
        output, _ = ws.background.communicate(timeout=COMMAND_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return f"{page}:{line}: the background command still runs after {COMMAND_TIMEOUT_S} s"
    code = ws.background.returncode
    ws.background = None
    return None if code == 0 else f"{page}:{line}: the background command ended with exit {code}\n{output[-3000:]}"


def wait_for_status(ws, timeout_s=60):
    """A background coordinator answers on its status socket before the blocks beside it ask."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if ws.background.poll() is not None:
            return
        try:
            with socket.create_connection(("127.0.0.1", ws.port), timeout=1):
                return
        except OSError:
            time.sleep(0.2)


def check_page(ws, page):
    problems = []
    ran = 0
    for lang, directive, body, line in blocks_of(page):
        where = f"{os.path.basename(page)}:{line + 1}"
        if directive.startswith("skip"):
            print(f"{where}: not run ({directive[4:].strip() or 'skip'})")
            continue
        if directive == "wait":
            problem = wait_background(ws, page, line + 1)
            if problem:
                return problems + [problem]
        expected_exit = int(directive.split()[1]) if directive.startswith("exit") else 0
        if lang == "python":
            script = os.path.join(ws.dir, f"block-{line + 1}.py")
            with open(script, "w", encoding="utf-8") as f:
                f.write(ws.localise(body) + "\n")
            print(f"{where}: python ({len(body.splitlines())} lines)", flush=True)
            problem = run(ws, ["/usr/bin/python3", script], where, expected_exit)
            ran += 1
            if problem:
                problems.append(problem)
            continue
        for command in commands_of(body):
            command = ws.localise_command(command)
            print(f"{where}: {command}", flush=True)
            if directive == "background":
                if ws.background:
                    return problems + [f"{where}: a second background command"]
                ws.background = ws.start(["bash", "-c", command])
                wait_for_status(ws)
            else:
                problem = run(ws, ["bash", "-c", command], where, expected_exit)
                if problem:
                    problems.append(problem)
            ran += 1
    if ws.background:
        problem = wait_background(ws, page, "end")
        if problem:
            problems.append(problem)
    if ran == 0:
        problems.append(f"{page}: no command found (a page this test checks shows commands)")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repo", required=True)
    parser.add_argument("--build", required=True)
    parser.add_argument("pages", nargs="+")
    args = parser.parse_args()
    # SIGTERM (ctest's timeout, a user) ends the test through its cleanup
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    ws = Workspace(os.path.abspath(args.repo), os.path.abspath(args.build))
    problems = []
    try:
        for page in args.pages:
            problems += check_page(ws, os.path.join(args.repo, page))
    finally:
        ws.close()
    for problem in problems:
        print("FAILED " + problem, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
