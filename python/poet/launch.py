"""poet.start: a poet-coordinator in a process of its own, and a handle on it (status, wait, stop).

The coordinator runs in its own session and writes to a file, not a pipe, so the Python process that started it
may end (a notebook's kernel dying or restarting) without disturbing the run.
"""

import datetime
import json
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import time
import urllib.request

LOG_NAME = "coordinator.log"
_CHECKPOINT = "checkpoint.pb"
_STATUS_LINE = re.compile(r"\] status: (http://\S+?)/status$", re.MULTILINE)  # coordinator/main.cpp's serve()
_LOG_PREFIX = re.compile(r"^\[[^]]*\] \[poet-coordinator\] \[(\w+)\] ")  # spdlog: [time] [name] [level]
_INTERRUPTED = (128 + signal.SIGINT, 128 + signal.SIGTERM)  # a stop, not a failure (README: exit codes)
_TAIL_BYTES = 64 * 1024  # what is read of a long run's log for its error: the error is at its end


class CoordinatorError(RuntimeError):
    """The coordinator failed: it exited nonzero (other than stopped by SIGINT or SIGTERM) or was killed.

    Raised by start and Coordinator.wait. The message is the coordinator's own, from its log.

    Args:
        message (str): what the coordinator said.
        returncode (int): its exit code (negative: killed by that signal).
        log_path (str): its log.

    Attributes:
        returncode (int): the coordinator's exit code (negative: killed by that signal).
        log_path (str): the coordinator's log, run_dir/coordinator.log.

    Example:
        >>> import pathlib, tempfile
        >>> work = tempfile.TemporaryDirectory()
        >>> config = pathlib.Path(work.name, "bad.textproto")
        >>> _ = config.write_text("no_such_field: 1")
        >>> try:
        ...     poet.start(config, pathlib.Path(work.name, "run"))
        ... except poet.CoordinatorError as error:
        ...     print(error.returncode)
        2
        >>> work.cleanup()
    """

    def __init__(self, message, returncode, log_path):
        super().__init__(message)
        self.returncode = returncode
        self.log_path = log_path


def _exit_text(code):
    if code < 0:
        return f"was killed by {signal.Signals(-code).name}"
    return {0: "finished (exit 0)", 130: "stopped by SIGINT (exit 130)", 143: "stopped by SIGTERM (exit 143)"}.get(
        code, f"exited with {code}")


def _whole(value, name, least):
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    if value < least:
        raise ValueError(f"{name} must be at least {least}, got {value}")
    return value


def _seconds(value, name):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TypeError(f"{name} must be a number of seconds, got {type(value).__name__}")
    if not value > 0:
        raise ValueError(f"{name} must be a positive number of seconds, got {value}")
    return value


def _path(value, name):
    if not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{name} must be a path, got {type(value).__name__}")
    return os.path.abspath(os.fspath(value))


def _existing_file(value, name):
    path = _path(value, name)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{name}: {path} is not a file")
    return path


def _executable(path):
    return os.path.isfile(path) and os.access(path, os.X_OK)


def find_coordinator(coordinator=None):
    """The poet-coordinator to run: `coordinator` if given, else $POET_COORDINATOR_BIN if set (either must be an
    executable file), else the build tree's beside this module, else poet-coordinator on PATH."""
    if coordinator is not None:
        path = _path(coordinator, "coordinator")
        if not _executable(path):
            raise FileNotFoundError(f"coordinator: {path} is not an executable file")
        return path
    from_env = os.environ.get("POET_COORDINATOR_BIN")
    if from_env:
        if not _executable(from_env):
            raise FileNotFoundError(f"POET_COORDINATOR_BIN: {from_env} is not an executable file")
        return os.path.abspath(from_env)
    # build/python/poet/launch.py -> build/coordinator/poet-coordinator
    in_build = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "coordinator",
                                             "poet-coordinator"))
    if _executable(in_build):
        return in_build
    on_path = shutil.which("poet-coordinator")
    if on_path:
        return on_path
    raise FileNotFoundError(f"poet-coordinator not found: POET_COORDINATOR_BIN is not set, {in_build} does not exist "
                            "and none is on PATH; pass coordinator= or set POET_COORDINATOR_BIN")


def _read_since(path, offset):
    """The log's text from offset on (at most its last _TAIL_BYTES)."""
    with open(path, "rb") as file:
        size = os.fstat(file.fileno()).st_size
        file.seek(max(offset, size - _TAIL_BYTES))
        return file.read().decode("utf-8", errors="replace")


def _error_message(text):
    """The coordinator's own words for why it failed: its error lines, else (a command-line error, printed
    without spdlog's prefix) its last lines."""
    errors = []
    for line in text.splitlines():
        prefix = _LOG_PREFIX.match(line)
        if prefix and prefix.group(1) in ("error", "critical"):
            errors.append(line[prefix.end():])
    if errors:
        return "\n".join(errors)
    return "\n".join(text.strip().splitlines()[-5:]) or "(nothing in its log)"


class Coordinator:
    """A poet-coordinator process started by poet.start: its status, its end, and the run it writes.

    The handle does not own the run: losing it (or the Python process) leaves the coordinator running; stop() or
    leaving a `with` block stops it. Made by start, not by hand.

    Args:
        process (subprocess.Popen): the coordinator's process.
        run_dir (str): its run directory, absolute.
        log_path (str): its log.
        log_offset (int): where this process's lines begin in the log.

    Attributes:
        run_dir (str): the run directory, absolute.
        log_path (str): the coordinator's output, run_dir/coordinator.log.
        url (str or None): its status socket and dashboard, http://127.0.0.1:PORT/, once it answers.

    Example:
        >>> import pathlib, tempfile
        >>> work = tempfile.TemporaryDirectory()
        >>> config = pathlib.Path(work.name, "tiny.textproto")
        >>> _ = config.write_text("seed: 5 iterations: 1000000 es { perturbations: 3 } walker { max_steps: 100 }")
        >>> run_dir = pathlib.Path(work.name, "run")
        >>> coordinator = poet.start(config, run_dir, threads=1)
        >>> coordinator.running, coordinator.status()["iterations"]
        (True, 1000000)
        >>> coordinator.stop()
        130
        >>> stopped_at = coordinator.run.next_iteration
        >>> coordinator = poet.start(None, run_dir, iterations=stopped_at + 2, threads=1)
        >>> coordinator.wait(progress=False), coordinator.run.next_iteration == stopped_at + 2
        (0, True)
        >>> work.cleanup()
    """

    def __init__(self, process, run_dir, log_path, log_offset):
        self._process = process
        self.run_dir = run_dir
        self.log_path = log_path
        self._log_offset = log_offset  # where this process's lines begin in the log
        self.url = None  # the status socket's, http://127.0.0.1:PORT/ (the dashboard), once it answers

    @property
    def pid(self):
        """int: the coordinator's process id (its session's and process group's too)."""
        return self._process.pid

    @property
    def running(self):
        """bool: whether the process is still running."""
        return self._process.poll() is None

    @property
    def returncode(self):
        """int or None: the exit code once the process has ended (negative: killed by that signal), else None."""
        return self._process.poll()

    @property
    def run(self):
        """Run: the run directory as a poet.Run (as of its last checkpoint)."""
        from . import Run  # here: the package imports this module before it defines Run

        return Run(self.run_dir)

    def _ended(self):
        return RuntimeError(f"the coordinator {_exit_text(self._process.returncode)}: it serves no status; "
                            "the run as it ended is in .run")

    def status(self):
        """The status socket's /status.

        Returns:
            dict: the run's status (iteration, iterations, pairs, rollouts, state, ...).

        Raises:
            RuntimeError: the process has ended (the run's final state is then .run).
            ConnectionError: the status socket does not answer.
        """
        if self._process.poll() is not None:
            raise self._ended()
        try:
            with urllib.request.urlopen(self.url + "status", timeout=10) as answer:
                return json.loads(answer.read())
        except OSError as error:
            if self._process.poll() is not None:
                raise self._ended() from None
            raise ConnectionError(f"{self.url}status does not answer: {error}") from error

    def wait(self, *, progress=True, timeout=None):
        """Waits for the process to end. Interrupting wait() leaves the run going.

        Args:
            progress (bool): show the iterations done, with tqdm (a widget in a notebook, a bar in a terminal) when
                it is installed, else a line of text on stderr.
            timeout (float, optional): seconds to wait at most; None: until the process ends.

        Returns:
            int: the exit code: 0 (the run is finished), 130 or 143 (stopped; the last checkpoint is the state).

        Raises:
            CoordinatorError: the coordinator failed or was killed (its message).
            TimeoutError: it was still running after `timeout` seconds (the run goes on).
            TypeError: timeout is not a number.
            ValueError: timeout is not positive.
        """
        deadline = None if timeout is None else time.monotonic() + _seconds(timeout, "timeout")
        bar = _Progress() if progress else None
        try:
            while self._process.poll() is None:
                if bar is not None:
                    try:
                        status = self.status()
                        bar.show(status["iteration"], status["iterations"])
                    except (OSError, RuntimeError):
                        pass  # ending between the poll and the request: the loop's test sees it next
                left = None if deadline is None else deadline - time.monotonic()
                if left is not None and left <= 0:
                    raise TimeoutError(f"the coordinator (pid {self.pid}) is still running after {timeout} s")
                try:
                    self._process.wait(0.5 if left is None else min(0.5, left))
                except subprocess.TimeoutExpired:
                    pass
            code = self._process.returncode
            if bar is not None and code == 0:
                bar.finish()
        finally:
            if bar is not None:
                bar.close()
        if code != 0 and code not in _INTERRUPTED:
            raise self._failure()
        return code

    def stop(self, *, timeout=60):
        """Stops the run with SIGINT, as Ctrl-C does.

        The iteration in flight is dropped; the last checkpoint is the state, which poet.start on the same
        directory resumes. If the process has not ended after `timeout` seconds it is killed with SIGKILL (the
        last checkpoint stays the state; its local workers watch its pid and end with it).

        Args:
            timeout (float): seconds to wait for the process to end before killing it.

        Returns:
            int: the exit code: 130, -9 if it was killed, or the code of a process that had already ended.
        """
        if self._process.poll() is None:
            self._process.send_signal(signal.SIGINT)
            try:
                self._process.wait(timeout)
            except subprocess.TimeoutExpired:
                self._process.kill()
                self._process.wait()
        return self._process.returncode

    def _failure(self):
        message = _error_message(_read_since(self.log_path, self._log_offset))
        return CoordinatorError(f"poet-coordinator {_exit_text(self._process.returncode)}: {message}\n"
                                f"(its log: {self.log_path})", self._process.returncode, self.log_path)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()

    def __repr__(self):
        state = "running" if self.running else _exit_text(self.returncode)
        return f"<poet.Coordinator pid {self.pid}, {state}, {self.run_dir}, status {self.url}>"


class _Progress:
    """Iterations done of the run's limit: a tqdm bar when tqdm is installed (tqdm.auto: a widget in a notebook,
    text in a terminal), else one line of text on stderr, rewritten in place."""

    def __init__(self):
        try:
            from tqdm.auto import tqdm
        except ImportError:
            tqdm = None
        self._tqdm = tqdm
        self._bar = None
        self._shown = None  # (iteration, total) last shown

    def show(self, iteration, total):
        if (iteration, total) == self._shown:
            return
        if self._tqdm is None:
            sys.stderr.write(f"\riteration {iteration}/{total}")
            sys.stderr.flush()
        elif self._bar is None:  # made at the first status: a resumed run starts part-way
            self._bar = self._tqdm(total=total, initial=iteration, desc="iterations", unit="it")
        else:
            self._bar.total = total
            self._bar.update(iteration - self._bar.n)
        self._shown = (iteration, total)

    def finish(self):
        """The run is finished: its last iterations may have come after the last status asked."""
        if self._shown is not None:
            self.show(self._shown[1], self._shown[1])

    def close(self):
        if self._bar is not None:
            self._bar.close()
        elif self._tqdm is None and self._shown is not None:
            sys.stderr.write("\n")


def _command(config, run_dir, iterations, threads, local_workers, start_from, coordinator):
    """poet-coordinator's command line on run_dir (an absolute path), every argument checked."""
    if config is not None:
        config = _existing_file(config, "config")
    elif not os.path.exists(os.path.join(run_dir, _CHECKPOINT)):
        raise ValueError(f"config is required for a new run: {run_dir} holds no run (no {_CHECKPOINT})")
    options = ["--config", config] if config is not None else ["--resume"]
    for flag, value, least in (("--iterations", iterations, 0), ("--threads", threads, 1),
                               ("--local-workers", local_workers, 0)):
        if value is not None:
            options += [flag, str(_whole(value, flag[2:].replace("-", "_"), least))]
    if start_from is not None:
        if config is None:
            raise ValueError("start_from is a new run's first policy: it needs a config")
        options += ["--start-from", _existing_file(start_from, "start_from")]
    return [find_coordinator(coordinator), "--run-dir", run_dir, "--status-address", "127.0.0.1:0", *options]


def _until_running(handle, timeout):
    """Waits until the handle's coordinator answers on its status socket, learning its address from the log."""
    deadline = time.monotonic() + timeout
    while True:
        code = handle.returncode
        if code is not None:
            if code == 0:
                return  # the run was already finished: nothing to run
            raise handle._failure()
        found = _STATUS_LINE.search(_read_since(handle.log_path, handle._log_offset))
        if found:
            handle.url = found.group(1) + "/"
            try:
                handle.status()
                return
            except (OSError, RuntimeError):
                pass  # bound a moment before it answers, or ended: the next round tells
        if time.monotonic() > deadline:
            handle.stop(timeout=10)
            raise TimeoutError(f"poet-coordinator was not running after {timeout} s; stopped it "
                               f"(its log: {handle.log_path})")
        time.sleep(0.05)


def start(config, run_dir, *, iterations=None, threads=None, local_workers=None, start_from=None, coordinator=None,
          timeout=60):
    """Starts poet-coordinator on run_dir in a process of its own session.

    The coordinator's output is appended to run_dir/coordinator.log. The Python process may end, a notebook's
    kernel die or restart: the run goes on. A run already finished ends at once (the handle's returncode is 0).

    Args:
        config (str, os.PathLike or None): a config file (protobuf text format) for a new run; on a directory that
            holds a run of the same config, the coordinator resumes it (and refuses another config). None resumes
            the run in run_dir (--resume).
        run_dir (str or os.PathLike): the run directory, made if missing.
        iterations (int, optional): overrides the iteration limit (a resume may extend it).
        threads (int, optional): poet-coordinator's --threads.
        local_workers (int, optional): poet-coordinator's --local-workers.
        start_from (str or os.PathLike, optional): a new run's first policy file.
        coordinator (str or os.PathLike, optional): the poet-coordinator to run; default $POET_COORDINATOR_BIN,
            else the build tree's beside this module, else poet-coordinator on PATH.
        timeout (float): seconds to wait for the status socket to answer.

    Returns:
        Coordinator: the handle, once the status socket answers (on 127.0.0.1, a free port: .url).

    Raises:
        CoordinatorError: the coordinator exited before it was running (a bad config, a directory another process
            owns: exit 2), with its message.
        TimeoutError: it was not running after `timeout` seconds (it is then stopped).
        TypeError: an argument of the wrong type, before anything is started.
        ValueError: an argument out of range, or no config for a directory without a run.
        FileNotFoundError: config, start_from or the coordinator is not a file.

    Example:
        >>> import pathlib, tempfile
        >>> work = tempfile.TemporaryDirectory()
        >>> config = pathlib.Path(work.name, "tiny.textproto")
        >>> _ = config.write_text("seed: 5 iterations: 2 es { perturbations: 3 } walker { max_steps: 100 }")
        >>> with poet.start(config, pathlib.Path(work.name, "run"), threads=1) as coordinator:
        ...     code = coordinator.wait(progress=False)
        >>> code, coordinator.log_path.endswith("coordinator.log")
        (0, True)
        >>> work.cleanup()
    """
    run_dir = _path(run_dir, "run_dir")
    command = _command(config, run_dir, iterations, threads, local_workers, start_from, coordinator)
    _seconds(timeout, "timeout")
    os.makedirs(run_dir, exist_ok=True)  # the coordinator accepts a new run in a directory that holds only its log
    log_path = os.path.join(run_dir, LOG_NAME)
    with open(log_path, "ab") as log:
        stamp = datetime.datetime.now().isoformat(sep=" ", timespec="seconds")
        log.write(f"# {stamp} poet.start: {shlex.join(command)}\n".encode())
        log.flush()
        offset = os.fstat(log.fileno()).st_size
        # its own session: no signal meant for this process (a notebook's interrupt, a terminal's hangup) reaches it
        process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=log, stderr=log, start_new_session=True)
    handle = Coordinator(process, run_dir, log_path, offset)
    _until_running(handle, timeout)
    return handle
