#!/usr/bin/python3
"""crossmachine_arm64: the project built for arm64 computes the bits of the x86-64 build, and serves its runs.

The project is cross-built for arm64 (aarch64) with Debian's cross compiler against the arm64 builds of its
libraries (multiarch) — cmake/toolchains/aarch64-linux-gnu.cmake, into BUILD/crossmachine/arm64, only poet-worker,
poet-coordinator and poet_unit_tests — and its programs are run by qemu's user-mode emulator
(qemu-aarch64-static -L /: arm64's loader and libraries from /usr/lib/aarch64-linux-gnu). Then:

  - the arm64 poet-coordinator --fingerprint and poet-worker --fingerprint have the arithmetic: and digest: lines
    of the x86-64 build's (the float mode: and target: lines are told, not compared, and differ by design); when
    the arithmetic differs, the check names the parts that do: math, box2d or walker;
  - poet_unit_tests --gtest_filter='Golden.*' passes under qemu;
  - the small run of tests/integration/coordinator_run_fixture.h, by a native x86-64 poet-coordinator with every
    job verified (--verify-fraction 1, --liveness-ms 5000: qemu is slow) served by the arm64 poet-worker under
    qemu and one native poet-worker: the coordinator exits 0 and never refuses a worker, the arm64 worker is
    welcomed, answers jobs that are checked against the other's answers (the coordinator's /workers, polled during
    the run), and the run files (checkpoint.pb, events.jsonl, pair_stats.csv, annecs.csv) are those of the same
    config run natively on two threads, byte for byte.

Only with POET_TEST_CROSSMACHINE=1 and as root; otherwise it exits 77 saying why. Missing packages are installed
by deploy/install-deps.sh --crossmachine. The arm64 build directory is a cache (BUILD/crossmachine/arm64: the
first build takes minutes on two cores, later ones are incremental; the check says when it reuses it; remove it to
build from scratch). Everything else it starts or makes — processes, the work directory
BUILD/crossmachine/work/arm64-PID — is removed on success, failure, SIGTERM and its own deadline.

  check_arm64.py --build-dir BUILD --source REPOSITORY
"""

import http.client
import json
import os
import re
import shutil
import sys
import time

sys.dont_write_bytecode = True  # no __pycache__ in the source tree

from crossmachine_support import (CacheLock, Children, Cleanup, Failed, checked, compare_fingerprints, compare_golden,
                                  compare_runs, ensure_installed, fingerprint_lines, free_port,
                                  gtest_summary, install_deps_list, log, main, native_binaries, report,
                                  read_text, remove_tree, require_opt_in, set_deadline, stale_native_build, tail,
                                  tiny_config, work_dir)

NAME = "crossmachine_arm64"
DEADLINE_S = 3300  # inside ctest's TIMEOUT of 3600
TARGETS = ["poet-worker", "poet-coordinator", "poet_unit_tests"]
TOOLS = ["qemu-aarch64-static", "aarch64-linux-gnu-g++", "cmake", "protoc", "pkg-config"]
EM_AARCH64 = 183


def elf_machine(path):
    with open(path, "rb") as f:
        header = f.read(20)
    if header[:4] != b"\x7fELF":
        raise Failed(f"{path} is not an ELF file")
    return int.from_bytes(header[18:20], "little")


def build_arm64(children, source, arm_dir, cache_root, deadline):
    """Configures (once) and builds the three targets; returns what it did, for the summary."""
    toolchain = os.path.join(source, "cmake", "toolchains", "aarch64-linux-gnu.cmake")
    cache = os.path.join(arm_dir, "CMakeCache.txt")
    reused = False
    if os.path.isfile(cache):
        text = read_text(cache)
        if f"CMAKE_TOOLCHAIN_FILE:FILEPATH={toolchain}" in text or f"CMAKE_TOOLCHAIN_FILE:UNINITIALIZED={toolchain}" \
                in text:
            reused = True
            log(f"reusing the arm64 build directory {arm_dir} (an incremental build; remove it to build from "
                f"scratch)")
        else:
            log(f"{arm_dir} was configured with another toolchain: configuring it again")
            remove_tree(arm_dir)
    started = time.monotonic()
    if not reused:
        os.makedirs(arm_dir, exist_ok=True)
        code, out, err = children.run(
            ["cmake", "-S", source, "-B", arm_dir, f"-DCMAKE_TOOLCHAIN_FILE={toolchain}",
             "-DCMAKE_BUILD_TYPE=Release", "-DPOET_BUILD_PYTHON=OFF", "-DPOET_BUILD_BENCH=OFF"],
            cache_root, "arm64-configure", deadline)
        if code != 0:
            remove_tree(arm_dir)
            raise Failed(f"configuring the arm64 build failed ({cache_root}/arm64-configure.out, .err):\n"
                         f"{tail(out)}\n{tail(err)}")
        log(f"configured {arm_dir} in {time.monotonic() - started:.0f} s")
    configured = time.monotonic()
    jobs = str(os.cpu_count() or 2)
    code, out, err = children.run(["cmake", "--build", arm_dir, "-j", jobs, "--target"] + TARGETS, cache_root,
                                  "arm64-build", deadline - 900)
    if code != 0:
        errors = [line for line in (out + err).splitlines() if re.search(r"\berror\b|Error \d", line)]
        own = [line for line in errors if line.startswith(source + "/") and "/third_party/" not in line]
        raise Failed(f"the arm64 build failed ({cache_root}/arm64-build.out, .err); "
                     f"{'in the project' + chr(39) + 's own code' if own else 'errors'}:\n"
                     + "\n".join((own or errors)[:40]) + f"\n{tail(err, 40)}")
    built = time.monotonic() - configured
    compiled = len(re.findall(r"Building CXX object", out))
    log(f"built {', '.join(TARGETS)} for arm64 in {built:.0f} s ({compiled} files compiled)")
    return (f"reused, {compiled} files compiled in {built:.0f} s" if reused else
            f"configured and built in {time.monotonic() - started:.0f} s ({compiled} files)")


def get_json(port, path):
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=3)
    try:
        connection.request("GET", path)
        response = connection.getresponse()
        body = response.read()
        return json.loads(body) if response.status == 200 else None
    finally:
        connection.close()


def field(worker, name):
    """A field of the status socket's JSON, by its proto name or its JSON (lowerCamel) name."""
    camel = re.sub(r"_(\w)", lambda m: m.group(1).upper(), name)
    return worker.get(name, worker.get(camel))


def await_log(path, pattern, deadline, process, what):
    """The first match of `pattern` (group 1, or the whole) in the file, once it appears."""
    while time.monotonic() < deadline:
        m = re.search(pattern, read_text(path)) if os.path.exists(path) else None
        if m:
            return m.group(1) if m.groups() else m.group(0)
        if process.poll() is not None:
            raise Failed(f"{what} ended ({process.returncode}) before its log said {pattern!r}:\n"
                         f"{tail(read_text(path))}")
        time.sleep(0.1)
    raise Failed(f"{what}: no log line matching {pattern!r} in time")


def mixed_run(children, native, qemu, arm_worker, config, scratch, deadline):
    """The native coordinator, every job verified, served by the arm64 worker under qemu and a native worker.
    Returns (problems, seconds)."""
    problems = []
    port = free_port()
    endpoint = f"tcp://127.0.0.1:{port}"
    run_dir = os.path.join(scratch, "mixed-run")
    started = time.monotonic()
    coordinator = children.start([native["coordinator"], "--config", config, "--run-dir", run_dir, "--quiet",
                                  "--listen", endpoint, "--verify-fraction", "1", "--status-address", "127.0.0.1:0",
                                  "--liveness-ms", "5000"], scratch, "coordinator")
    coordinator_log = os.path.join(scratch, "coordinator.err")
    await_log(coordinator_log, r"workers connect to", min(deadline, time.monotonic() + 60), coordinator,
              "the coordinator")
    status_port = int(await_log(coordinator_log, r"status: http://[^:]+:(\d+)/", min(deadline, time.monotonic() + 60),
                                coordinator, "the coordinator"))
    arm = children.start([qemu, "-L", "/", arm_worker, "--connect", endpoint, "--threads", "1", "--name",
                          "arm64-qemu"], scratch, "worker_arm64")
    # the arm64 worker is welcomed first, so that it takes jobs from the first batch on
    await_log(os.path.join(scratch, "worker_arm64.err"), r"welcomed by the coordinator|refused",
              min(deadline, time.monotonic() + 120), arm, "the arm64 worker")
    x86 = children.start([native["worker"], "--connect", endpoint, "--threads", "1", "--name", "x86-64"], scratch,
                         "worker_x86")
    last = {}
    while coordinator.poll() is None:
        if time.monotonic() > deadline:
            raise Failed("the run with the arm64 worker did not end in time")
        try:
            listing = get_json(status_port, "/workers")
        except (OSError, ValueError, http.client.HTTPException):
            listing = None
        for w in (listing or {}).get("workers", []):
            last[field(w, "address") or field(w, "id")] = w
        time.sleep(1)
    seconds = time.monotonic() - started
    code = coordinator.returncode
    worker_codes = [Children.wait(p, min(deadline, time.monotonic() + 120), what) for p, what in
                    ((arm, "the arm64 worker"), (x86, "the native worker"))]
    log_text = read_text(coordinator_log)
    arm_log = read_text(os.path.join(scratch, "worker_arm64.err"))
    refusals = [line.strip() for line in log_text.splitlines() if "refused" in line and "0 worker(s) refused" not in
                line]
    if code != 0:
        problems.append(f"the coordinator exited {code}:\n{tail(log_text)}")
    if refusals:
        problems.append("the coordinator refused a worker:\n  " + "\n  ".join(refusals))
    elif "welcomed by the coordinator" not in arm_log or "efused" in arm_log:
        problems.append(f"the arm64 worker was not welcomed, or was refused:\n{tail(arm_log)}")
    if worker_codes != [0, 0] and not (refusals and worker_codes == [2, 0]):  # 2: a worker refused (worker/main.cpp)
        problems.append(f"the workers exited {worker_codes} (arm64, native):\narm64:\n{tail(arm_log)}\nnative:\n"
                        f"{tail(read_text(os.path.join(scratch, 'worker_x86.err')))}")
    for line in log_text.splitlines():
        if re.search(r"joined|verification:|demoted|silent|held far longer", line):
            log("  coordinator: " + line.strip())
    arm_entry = next((w for name, w in last.items() if "arm64-qemu" in str(name)), None)
    if arm_entry is None and not refusals:
        problems.append(f"the arm64 worker never appeared in the coordinator's /workers (seen: {list(last)})")
    elif arm_entry is not None:
        jobs, checks = field(arm_entry, "jobs_done") or 0, field(arm_entry, "checks_passed") or 0
        trust = field(arm_entry, "trust")
        log(f"  the arm64 worker, last seen in /workers: {jobs} jobs answered, {checks} answers checked alike, "
            f"trust {trust}, {field(arm_entry, 'results_done')} results, arithmetic "
            f"{field(arm_entry, 'arithmetic_digest')}")
        if int(jobs) == 0 or int(checks) == 0 or trust == "refused":
            problems.append(f"the arm64 worker answered {jobs} jobs, {checks} checked alike, trust {trust}: its "
                            f"answers were not compared with the native worker's: {arm_entry}")
    for name, w in last.items():
        if "arm64-qemu" not in str(name):
            log(f"  the native worker, last seen in /workers: {field(w, 'jobs_done')} jobs answered, "
                f"{field(w, 'checks_passed')} checked alike, trust {field(w, 'trust')}")
    return problems, seconds


def check(args):
    require_opt_in("the arm64 build under qemu")
    cleanup = Cleanup()
    try:
        run(args, cleanup)
    finally:
        cleanup.run()


def run(args, cleanup):
    deadline = set_deadline(DEADLINE_S, NAME)
    build_dir, source = os.path.realpath(args.build_dir), os.path.realpath(args.source)
    native = native_binaries(build_dir)
    stale = stale_native_build(source, build_dir, native.values())
    if stale:
        log("WARNING: " + stale)
    arm64_packages = [p for p in install_deps_list(source) if p.endswith(":arm64")]
    ensure_installed(source, TOOLS, arm64_packages, deadline)
    qemu = shutil.which("qemu-aarch64-static")
    times = {}

    cache_root = os.path.join(build_dir, "crossmachine")
    CacheLock(cache_root, "arm64", cleanup)
    scratch = work_dir(build_dir, "arm64", cleanup)
    children = Children(cleanup)
    arm_dir = os.path.join(cache_root, "arm64")
    times["build"] = build_arm64(children, source, arm_dir, cache_root, deadline)
    arm = {"coordinator": os.path.join(arm_dir, "coordinator", "poet-coordinator"),
           "worker": os.path.join(arm_dir, "worker", "poet-worker"),
           "unit_tests": os.path.join(arm_dir, "tests", "poet_unit_tests")}
    for path in arm.values():
        if elf_machine(path) != EM_AARCH64:
            raise Failed(f"{path} is not an aarch64 program (ELF machine {elf_machine(path)})")

    def emulated(binary):
        return [qemu, "-L", "/", binary]

    problems = []
    seen = {}
    # the fingerprints
    for name in ("coordinator", "worker"):
        here = checked(*children.run([native[name], "--fingerprint"], scratch, f"fp_native_{name}", deadline),
                       f"{native[name]} --fingerprint")
        there = checked(*children.run(emulated(arm[name]) + ["--fingerprint"], scratch, f"fp_arm64_{name}",
                                      deadline), f"the arm64 poet-{name} --fingerprint")
        a, b = fingerprint_lines(here), fingerprint_lines(there)
        told = [f"{k}: x86-64 {a.get(k)!r}, arm64 {b.get(k)!r}" for k in sorted(set(a) | set(b))
                if a.get(k) != b.get(k) and k not in ("arithmetic", "digest")]
        differences = compare_fingerprints(here, there, "arm64")
        if differences and name == "worker" and (here, there) == seen.get("coordinator"):
            problems.append("poet-worker --fingerprint: the same difference as poet-coordinator's (the same lines)")
        elif differences:
            problems.append(f"poet-{name} --fingerprint: the arm64 build's differs from the x86-64 build's:\n"
                            + "\n".join(differences))
        else:
            log(f"poet-{name} --fingerprint: arm64's arithmetic: and digest: lines are x86-64's (arithmetic: "
                f"{a.get('arithmetic')}; digest: {a.get('digest')})")
        if name == "coordinator":  # the worker's are the same lines
            for line in told:
                log(f"  told, not compared: {line}")
        seen[name] = (here, there)

    # the golden digests under qemu, and (to tell a pin awaiting its update from a difference) natively
    golden = ["--gtest_filter=Golden.*", "--gtest_brief=1"]
    native_golden = children.run([native["unit_tests"]] + golden, scratch, "golden_native", deadline)
    started = time.monotonic()
    code, out, err = children.run(emulated(arm["unit_tests"]) + golden, scratch, "golden_arm64", deadline)
    times["golden"] = time.monotonic() - started
    golden_problems = compare_golden(native_golden[:2], (code, out), "the arm64 build under qemu")
    problems += golden_problems
    if not golden_problems:
        log(f"arm64 poet_unit_tests --gtest_filter=Golden.* under qemu: {gtest_summary(out)} in "
            f"{times['golden']:.0f} s")

    # the small run: natively on two threads, then on the arm64 worker and a native one
    config = os.path.join(scratch, "tiny.textproto")
    with open(config, "w") as f:
        f.write(tiny_config(source))
    started = time.monotonic()
    checked(*children.run([native["coordinator"], "--config", config, "--run-dir", os.path.join(scratch, "threads"),
                           "--quiet", "--status-address", "127.0.0.1:0", "--threads", "2"], scratch, "threads",
                          deadline), "the native run on threads")
    times["threads"] = time.monotonic() - started
    log(f"the small run natively on 2 threads: {times['threads']:.1f} s")
    # the arm64 build's own numbers, whatever the handshake says: the same run by the arm64 coordinator on threads
    started = time.monotonic()
    checked(*children.run(emulated(arm["coordinator"]) + ["--config", config, "--run-dir",
                                                          os.path.join(scratch, "arm64-threads"), "--quiet",
                                                          "--status-address", "127.0.0.1:0", "--threads", "2"],
                          scratch, "arm64_threads", deadline), "the arm64 run on threads under qemu")
    times["arm64_threads"] = time.monotonic() - started
    log(f"the small run by the arm64 coordinator on 2 threads under qemu: {times['arm64_threads']:.1f} s; its files:")
    differences = compare_runs(os.path.join(scratch, "threads"), os.path.join(scratch, "arm64-threads"),
                               "the arm64 run on threads", source=source)
    if differences:
        problems.append("the run by the arm64 coordinator on threads differs from the native one:\n  "
                        + "\n  ".join(differences))
    run_problems, times["mixed"] = mixed_run(children, native, qemu, arm["worker"], config, scratch, deadline)
    log(f"the small run on the arm64 worker (qemu) and a native worker, every job verified: {times['mixed']:.1f} s; "
        f"its files:")
    problems += run_problems
    differences = compare_runs(os.path.join(scratch, "threads"), os.path.join(scratch, "mixed-run"),
                               "the run with the arm64 worker", source=source)
    if differences:
        problems.append("the run with the arm64 worker differs from the run on threads:\n  " + "\n  ".join(differences))

    report(NAME, problems, stale, f"arm64 build {times['build']}",
           f"arm64 build {times['build']}; fingerprints' arithmetic and digest identical; golden digests pass under "
           f"qemu ({times['golden']:.0f} s); the run on arm64 threads identical ({times['arm64_threads']:.1f} s under "
           f"qemu); the run with the arm64 worker identical to threads ({times['mixed']:.1f} s, threads "
           f"{times['threads']:.1f} s)")


if __name__ == "__main__":
    main(NAME, check, __doc__)
