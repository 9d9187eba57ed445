"""What the crossmachine checks share (tests/crossmachine/README.md): the opt-in, the deadline, the children they
start (killed with everything they started, also when the check fails, is interrupted or runs out of time), mounts
and directories removed the same way, the caches under BUILD/crossmachine/ and the lock that guards each, the
packages of deploy/install-deps.sh --crossmachine, the tiny config of tests/integration/coordinator_run_fixture.h,
and the comparisons: fingerprints part by part, run files byte for byte."""

import ctypes
import difflib
import fcntl
import hashlib
import os
import re
import shutil
import signal
import subprocess
import sys
import time

REPOSITORY = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPOSITORY, "tests"))
from check_support import Failed, Skipped, free_port, run_check  # noqa: E402,F401

OPT_IN = "POET_TEST_CROSSMACHINE"
RUN_FILES = ("checkpoint.pb", "events.jsonl", "pair_stats.csv", "annecs.csv")
STARTED = time.monotonic()

# glibc's own objects: the machine's (or the root's) C library, never bundled (deploy/bundle.sh's list)
GLIBC_FAMILY = re.compile(r"^(ld-linux-x86-64\.so\.2|ld-linux-aarch64\.so\.1|libnsl\.so\.1|libc_malloc_debug\.so\.0|"
                          r"lib(c|m|mvec|pthread|dl|rt|resolv|util|anl|BrokenLocale|thread_db)\.so\.[0-9]+)$")


def log(message):
    print(f"[{time.monotonic() - STARTED:7.1f} s] {message}", flush=True)


def elapsed():
    return time.monotonic() - STARTED


def load_average():
    return "load average " + " ".join(f"{x:.1f}" for x in os.getloadavg()) + " (1, 5, 15 min)"


def require_opt_in(what):
    """Skips (exit 77, saying why) unless POET_TEST_CROSSMACHINE=1 and root."""
    if os.environ.get(OPT_IN, "") != "1":
        raise Skipped(f"{what}: not part of the default run; set {OPT_IN}=1 to run it "
                      f"(cd build && {OPT_IN}=1 ctest -R crossmachine --output-on-failure)")
    if os.geteuid() != 0:
        raise Skipped(f"{what} needs root (debootstrap, chroot, mount, apt-get); this is uid {os.geteuid()}")


# ---------------------------------------------------------------------------------------------------------
# the deadline and the cleanup


class Cleanup:
    """Undo actions, run last first whatever happened, after the ones pushed with first=True (the processes are
    killed before their mounts and directories go): with SIGTERM, SIGINT and the deadline's alarm held off, so
    that a second signal cannot cut them short. Each runs once; an error in one is printed and the rest still run."""

    def __init__(self):
        self._actions = []
        self._first = []

    def push(self, what, action, first=False):
        (self._first if first else self._actions).append((what, action))

    def run(self):
        signal.alarm(0)
        previous = {s: signal.signal(s, signal.SIG_IGN) for s in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP)}
        try:
            while self._first or self._actions:
                what, action = (self._first or self._actions).pop()
                try:
                    action()
                except Exception as e:  # noqa: BLE001 - every undo runs, and says what failed
                    print(f"cleanup: {what}: {e}", flush=True)
        finally:
            for s, handler in previous.items():
                signal.signal(s, handler)


def set_deadline(seconds, what):
    """Fails the check (its cleanup runs) when `seconds` have passed: inside ctest's TIMEOUT, which kills outright.
    POET_TEST_CROSSMACHINE_DEADLINE_S=N sets another (to try the cleanup on a deadline)."""
    seconds = int(os.environ.get("POET_TEST_CROSSMACHINE_DEADLINE_S", seconds))

    def expired(_signum, _frame):
        raise Failed(f"its own deadline of {seconds} s passed ({what} cleaned up before ctest's TIMEOUT)")

    def hung_up(signum, _frame):
        raise Failed(f"interrupted by signal {signum}")

    signal.signal(signal.SIGALRM, expired)
    signal.signal(signal.SIGHUP, hung_up)  # run_check makes SIGTERM and SIGINT failures
    signal.alarm(seconds)
    return time.monotonic() + seconds


# ---------------------------------------------------------------------------------------------------------
# children

_libc = ctypes.CDLL(None, use_errno=True)


def _child_setup():
    # the child dies with this process even when it is killed outright (ctest's TIMEOUT sends SIGKILL); chroot and
    # qemu exec the program, which keeps this
    _libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


def _sessions():
    """pid -> session id of every process."""
    out = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        fields = stat[stat.rfind(")") + 2:].split()
        out[int(entry)] = int(fields[3])  # state ppid pgrp session
    return out


def _zombie(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            stat = f.read()
        return stat[stat.rfind(")") + 2] == "Z"
    except OSError:
        return True


class Children:
    """Processes this check starts, each in a session of its own with its output in DIR/NAME.out and NAME.err; at
    the end every process of those sessions is killed (what they started with them)."""

    def __init__(self, cleanup):
        self._procs = []
        cleanup.push("the processes this check started", self.kill_all, first=True)

    def start(self, argv, directory, name, env=None, cwd=None):
        out = open(os.path.join(directory, name + ".out"), "wb")
        err = open(os.path.join(directory, name + ".err"), "wb")
        try:
            p = subprocess.Popen(argv, stdout=out, stderr=err, stdin=subprocess.DEVNULL, env=env, cwd=cwd,
                                 start_new_session=True, preexec_fn=_child_setup)
        finally:
            out.close()
            err.close()
        p.poet_files = (os.path.join(directory, name + ".out"), os.path.join(directory, name + ".err"))
        self._procs.append(p)
        return p

    @staticmethod
    def wait(p, deadline, what):
        remaining = deadline - time.monotonic()
        try:
            return p.wait(timeout=max(1.0, remaining))
        except subprocess.TimeoutExpired:
            raise Failed(f"{what} did not end in time ({max(1.0, remaining):.0f} s)") from None

    def run(self, argv, directory, name, deadline, env=None, cwd=None):
        """Runs argv to its end (at most until `deadline`): (exit code, stdout, stderr) as text."""
        p = self.start(argv, directory, name, env=env, cwd=cwd)
        code = self.wait(p, deadline, f"{name} ({' '.join(argv)})")
        return code, read_text(p.poet_files[0]), read_text(p.poet_files[1])

    def kill_all(self):
        sessions = {p.pid for p in self._procs}
        # SIGTERM first (make deletes the target it was writing), then SIGKILL for what is left after 5 s
        for pid in [pid for pid, sid in _sessions().items() if sid in sessions and pid != os.getpid()]:
            try:
                os.kill(pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
        until = time.monotonic() + 5
        while time.monotonic() < until and any(sid in sessions for pid, sid in _sessions().items()
                                               if pid != os.getpid() and not _zombie(pid)):
            for p in self._procs:
                p.poll()
            time.sleep(0.1)
        for _ in range(50):
            alive = [pid for pid, sid in _sessions().items() if sid in sessions and pid != os.getpid()]
            if not alive:
                break
            for pid in alive:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            for p in self._procs:
                try:
                    p.wait(timeout=0.1)
                except subprocess.TimeoutExpired:
                    pass
            time.sleep(0.1)
        for p in self._procs:
            if p.poll() is None:
                p.kill()
                p.wait(timeout=10)
        self._procs = []


def read_text(path):
    with open(path, "rb") as f:
        return f.read().decode("utf-8", "replace")


def tail(text, lines=30):
    return "\n".join(text.rstrip().splitlines()[-lines:])


def checked(code, out, err, what):
    if code != 0:
        raise Failed(f"{what} exited {code}:\n{tail(out)}\n{tail(err)}")
    return out


# ---------------------------------------------------------------------------------------------------------
# mounts and directories


def _unescape(path):
    return re.sub(r"\\([0-7]{3})", lambda m: chr(int(m.group(1), 8)), path)


def mounts_under(path):
    """Mount points at or below `path`, deepest first."""
    path = os.path.realpath(path)
    found = []
    with open("/proc/self/mountinfo") as f:
        for line in f:
            point = _unescape(line.split()[4])
            if point == path or point.startswith(path + "/"):
                found.append(point)
    return sorted(set(found), key=lambda p: p.count("/"), reverse=True)


def unmount_all_under(path, why):
    for point in mounts_under(path):
        log(f"unmounting {point} ({why})")
        if subprocess.run(["umount", point], capture_output=True).returncode != 0:
            subprocess.run(["umount", "-l", point], capture_output=True)  # busy: detached now, freed when idle
    left = mounts_under(path)
    if left:
        raise Failed(f"could not unmount {', '.join(left)}")


def remove_tree(path):
    """rm -rf that first unmounts what is mounted below `path` and never crosses into another filesystem."""
    if not os.path.lexists(path):
        return
    unmount_all_under(path, "before removing " + path)
    subprocess.run(["rm", "-rf", "--one-file-system", path], check=False)
    if os.path.lexists(path):
        raise Failed(f"could not remove {path}")


def pid_alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def remove_stale(directory, prefix):
    """Removes DIRECTORY/PREFIX-<pid>... entries whose pid is not alive: what a run killed outright (SIGKILL) left."""
    if not os.path.isdir(directory):
        return
    for entry in sorted(os.listdir(directory)):
        m = re.match(re.escape(prefix) + r"-(\d+)\b", entry)
        if m and not pid_alive(int(m.group(1))):
            log(f"removing {os.path.join(directory, entry)}, left by a run that was killed (pid {m.group(1)})")
            remove_tree(os.path.join(directory, entry))


class CacheLock:
    """An exclusive flock on BUILD/crossmachine/NAME.lock: one run at a time uses a cache."""

    def __init__(self, cache_root, name, cleanup):
        os.makedirs(cache_root, exist_ok=True)
        self._file = open(os.path.join(cache_root, name + ".lock"), "w")
        try:
            fcntl.flock(self._file, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            log(f"another run holds {self._file.name}: waiting for it")
            fcntl.flock(self._file, fcntl.LOCK_EX)
        cleanup.push("the cache lock", self._file.close)


def work_dir(build_dir, name, cleanup):
    """BUILD/crossmachine/work/NAME-<pid>: this run's files, removed at the end (a killed run's, by the next)."""
    parent = os.path.join(build_dir, "crossmachine", "work")
    os.makedirs(parent, exist_ok=True)
    remove_stale(parent, name)
    path = os.path.join(parent, f"{name}-{os.getpid()}")
    remove_tree(path)
    os.makedirs(path)
    cleanup.push("removing " + path, lambda: remove_tree(path) if os.environ.get("POET_TEST_KEEP") != "1" else
                 log(f"POET_TEST_KEEP=1: kept {path}"))
    return path


# ---------------------------------------------------------------------------------------------------------
# packages


def install_deps_list(source):
    r = subprocess.run(["bash", os.path.join(source, "deploy", "install-deps.sh"), "--crossmachine", "--list"],
                       capture_output=True, text=True, timeout=60)
    if r.returncode != 0:
        raise Failed(f"deploy/install-deps.sh --crossmachine --list failed: {r.stderr}")
    return r.stdout.split()


def package_installed(name):
    r = subprocess.run(["dpkg-query", "-W", "-f=${Status}", name], capture_output=True, text=True)
    return r.returncode == 0 and "install ok installed" in r.stdout


def ensure_installed(source, tools, packages, deadline):
    """Runs deploy/install-deps.sh --crossmachine when a tool or package is missing (it says which); fails saying
    to run it by hand when that does not help."""
    missing = [t for t in tools if shutil.which(t) is None] + [p for p in packages if not package_installed(p)]
    if not missing:
        return
    command = ["bash", os.path.join(source, "deploy", "install-deps.sh"), "--crossmachine"]
    log(f"missing: {' '.join(missing)}; running {' '.join(command)}")
    started = time.monotonic()
    r = subprocess.run(command, capture_output=True, text=True, timeout=max(60, deadline - time.monotonic()))
    log(f"install-deps.sh --crossmachine exited {r.returncode} after {time.monotonic() - started:.0f} s")
    still = [t for t in tools if shutil.which(t) is None] + [p for p in packages if not package_installed(p)]
    if r.returncode != 0 or still:
        raise Failed(f"still missing after deploy/install-deps.sh --crossmachine: {' '.join(still) or '-'}; run "
                     f"`sudo bash deploy/install-deps.sh --crossmachine` by hand:\n{tail(r.stdout)}\n{tail(r.stderr)}")


# ---------------------------------------------------------------------------------------------------------
# the run and its comparisons


def tiny_config(source):
    """The small POET config of tests/integration/coordinator_run_fixture.h (kConfig), as the integration tests
    run it: 6 iterations of 4 perturbations, 120-step episodes, reproduction and transfer every other iteration."""
    path = os.path.join(source, "tests", "integration", "coordinator_run_fixture.h")
    with open(path) as f:
        m = re.search(r'constexpr char kConfig\[\] = R"\((.*?)\)";', f.read(), re.S)
    if not m:
        raise Failed(f"{path}: no kConfig raw string found")
    return m.group(1)


def native_binaries(build_dir):
    paths = {
        "coordinator": os.path.join(build_dir, "coordinator", "poet-coordinator"),
        "worker": os.path.join(build_dir, "worker", "poet-worker"),
        "unit_tests": os.path.join(build_dir, "tests", "poet_unit_tests"),
    }
    missing = [p for p in paths.values() if not os.access(p, os.X_OK)]
    if missing:
        raise Failed(f"not built: {', '.join(missing)} (cmake --build {build_dir})")
    return paths


SOURCE_SUFFIXES = (".cpp", ".h", ".proto", ".cmake", "CMakeLists.txt", ".patch", ".html")
# what none of poet-coordinator, poet-worker and poet_unit_tests is compiled from
NOT_IN_THE_BINARIES = ("bench", "docs", "examples", "experiments", "python", "deploy", "site", "out", "runs",
                       "__pycache__")


def stale_native_build(source, build_dir, binaries):
    """A warning (None when none) when a source file of the project is newer than a native binary: that build is
    not of the tree the other machine's build is made from, and their comparison would be of two trees."""
    oldest = min(os.path.getmtime(p) for p in binaries)
    newer = []
    for directory, subdirs, files in os.walk(source):
        subdirs[:] = [d for d in subdirs if not d.startswith(".") and d not in NOT_IN_THE_BINARIES
                      and os.path.realpath(os.path.join(directory, d)) != os.path.realpath(build_dir)
                      and not d.startswith("build")]
        for f in files:
            path = os.path.join(directory, f)
            if f.endswith(SOURCE_SUFFIXES) and os.path.getmtime(path) > oldest:
                newer.append(os.path.relpath(path, source))
    if not newer:
        return None
    return (f"the native build in {build_dir} is older than {len(newer)} source file(s) ({', '.join(sorted(newer)[:4])}"
            f"{', ...' if len(newer) > 4 else ''}): build it again (cmake --build {build_dir}), or a difference may "
            f"be between two trees, not two machines")


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


CHECKPOINT_HEADER_BYTES = 24  # run_directory/files/checkpoint_file.h: magic, version, length, CRC-32; then the body


def checkpoint_difference(source, a, b, lines=40):
    """The fields in which two checkpoint files differ: their bodies decoded by protoc as poet.pb.Checkpoint
    (proto/poet.proto), as a unified diff of the text form."""
    protoc = shutil.which("protoc")
    if protoc is None:
        return "(protoc is not installed: no field-by-field comparison)"
    texts = []
    for path in (a, b):
        with open(path, "rb") as f:
            body = f.read()[CHECKPOINT_HEADER_BYTES:]
        r = subprocess.run([protoc, "--decode=poet.pb.Checkpoint", "-I", os.path.join(source, "proto"),
                            os.path.join(source, "proto", "poet.proto")], input=body, capture_output=True,
                           timeout=300)
        if r.returncode != 0:
            return f"(protoc could not decode {path}: {r.stderr.decode(errors='replace').strip()})"
        texts.append(r.stdout.decode(errors="replace").splitlines())
    diff = list(difflib.unified_diff(texts[0], texts[1], "reference", "other", n=0, lineterm=""))
    changed = sum(1 for line in diff if line.startswith("-") and not line.startswith("---"))
    shown = diff[2:2 + lines] + (["..."] if len(diff) > lines + 2 else [])
    return (f"their bodies decoded (protoc --decode=poet.pb.Checkpoint): {changed} of {len(texts[0])} lines differ:\n"
            + "\n".join("    " + line for line in shown))


def compare_runs(reference, other, what, files=RUN_FILES, source=None):
    """Every run file byte for byte; a list of the differences (empty when identical). With `source`, a checkpoint
    that differs is also compared field by field."""
    problems = []
    for name in files:
        a, b = os.path.join(reference, name), os.path.join(other, name)
        if not os.path.isfile(a) or os.path.getsize(a) == 0:
            problems.append(f"{name}: missing or empty in the reference run {reference}")
        elif not os.path.isfile(b):
            problems.append(f"{name}: missing in {what} ({other})")
        elif sha256(a) != sha256(b):
            with open(a, "rb") as fa, open(b, "rb") as fb:
                x, y = fa.read(), fb.read()
            apart = sum(1 for i in range(min(len(x), len(y))) if x[i] != y[i]) + abs(len(x) - len(y))
            text = (f"{name} differs: reference {len(x)} bytes sha256 {sha256(a)[:16]}, {what} {len(y)} bytes "
                    f"sha256 {sha256(b)[:16]}; {apart} bytes apart")
            if name == "checkpoint.pb" and source:
                text += "; " + checkpoint_difference(source, a, b)
            problems.append(text)
            log("  " + text)
        else:
            log(f"  {name}: identical ({os.path.getsize(a)} bytes, sha256 {sha256(a)[:16]})")
    return problems


def fingerprint_lines(text):
    lines = {}
    for line in text.splitlines():
        key, sep, value = line.partition(": ")
        if sep:
            lines[key] = value
    return lines


def arithmetic_parts(value):
    """'D (math M, box2d B, walker W)' -> {'all': D, 'math': M, ...}"""
    m = re.match(r"(\w+) \(math (\w+), box2d (\w+), walker (\w+)\)", value or "")
    return dict(zip(("all", "math", "box2d", "walker"), m.groups())) if m else {}


def compare_fingerprints(native, other, what, whole=False):
    """The problems (empty when none): the arithmetic: and digest: lines must be equal, and with whole=True every
    line. Names the parts of the arithmetic that differ."""
    a, b = fingerprint_lines(native), fingerprint_lines(other)
    problems = []
    keys = sorted(set(a) | set(b)) if whole else ["arithmetic", "digest"]
    for key in keys:
        if a.get(key) != b.get(key):
            problems.append(f"{key}: native {a.get(key)!r}, {what} {b.get(key)!r}")
    pa, pb = arithmetic_parts(a.get("arithmetic")), arithmetic_parts(b.get("arithmetic"))
    differing = [k for k in ("math", "box2d", "walker") if pa.get(k) != pb.get(k)]
    if differing:
        problems.append(f"the arithmetic differs in: {', '.join(differing)} "
                        f"({'; '.join(f'{k}: native {pa.get(k)}, {what} {pb.get(k)}' for k in differing)})")
    if problems:
        problems.append(f"native fingerprint:\n{native.rstrip()}\n{what} fingerprint:\n{other.rstrip()}")
    return problems


def _golden_outcome(out):
    """The Golden tests that failed, and the digests they computed where they differ from the pinned ones."""
    failed = sorted(set(re.findall(r"^\[  FAILED  \] (Golden\.\w+) \(", out, re.M)))
    return failed, re.findall(r"digest (0x[0-9a-f]+), pinned (0x[0-9a-f]+)", out)


def compare_golden(native, other, what):
    """native and other: (exit code, output) of poet_unit_tests --gtest_filter=Golden.* here and on the other
    machine. The problems (empty when the other passes and so does this machine). When both fail, says whether they
    fail alike (the same tests, the same computed digests: the tree's pinned digests are not this build's, which
    is no difference between machines, but still no pass) or not."""
    (native_code, native_out), (other_code, other_out) = native, other
    if other_code == 0 and native_code == 0:
        return []
    n_failed, n_digests = _golden_outcome(native_out)
    o_failed, o_digests = _golden_outcome(other_out)
    if other_code == 0:
        return [f"Golden.* passes in {what} but fails natively ({', '.join(n_failed)}): the machines differ"]
    if native_code != 0 and n_failed == o_failed and n_digests == o_digests:
        computed = ", ".join(sorted({d for d, _ in o_digests}))
        return [f"Golden.* fails in {what} exactly as natively: the same {len(o_failed)} tests fail "
                f"({', '.join(o_failed)}) with the same computed digests ({computed}), so {what} computes this "
                f"machine's bits; but the digests pinned in tests/unit/engine/golden_test.cpp are not this build's "
                f"(a change of behaviour awaiting new pins), so the golden digests do not pass here either"]

    def described(failed, digests):
        computed = ", ".join(f"{d} where {p} is pinned" for d, p in dict(digests).items())
        return f"{len(failed)} failing ({', '.join(failed) or 'none named'})" + (f"; computed {computed}"
                                                                                if computed else "")

    return [f"Golden.* in {what} is not as natively: in {what} it exited {other_code}, "
            f"{described(o_failed, o_digests)}; natively it exited {native_code}, {described(n_failed, n_digests)}"
            + ("" if o_digests else f"\n{tail(other_out, 30)}")]


def gtest_summary(out):
    m = re.search(r"\[  PASSED  \] (\d+) tests?", out)
    return f"{m.group(1)} tests passed" if m else "no PASSED line"


def report(name, problems, stale, failed_figures, passed_figures):
    """The check's RESULT line: FAILED with its figures and every problem numbered (Failed raised), or its figures."""
    if problems:
        log(f"RESULT {name}: FAILED, {len(problems)} problem(s); {failed_figures}; {elapsed():.0f} s in all; "
            f"{load_average()}")
        raise Failed(f"{len(problems)} problem(s):\n" + "\n".join(f"({i}) {p}" for i, p in enumerate(problems, 1))
                     + (f"\nWARNING: {stale}" if stale else ""))
    log(f"RESULT {name}: {passed_figures}; {elapsed():.0f} s in all; {load_average()}")


def main(name, check, description):
    """Runs check(arguments) on this command line (--build-dir, --source) and exits with its outcome."""
    import argparse
    parser = argparse.ArgumentParser(description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build-dir", required=True, help="the CMake build directory (native, x86-64)")
    parser.add_argument("--source", required=True, help="the repository root")
    arguments = parser.parse_args()
    sys.exit(run_check(name, lambda: check(arguments)))
