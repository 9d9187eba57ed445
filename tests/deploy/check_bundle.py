#!/usr/bin/python3
"""Checks deploy/bundle.sh: the archive it writes runs POET from any directory, taking nothing but the C library
from the machine.

  1. bundle.sh writes the archive from the build tree; it is unpacked into a directory with an unusual name.
  2. The bundle holds every executable of the build (passed by CMake), no library of glibc and no Box2D (linked
     statically: third_party/box2d), the presets and the shipped walker, and a README naming the glibc it needs, which this machine's satisfies. Each binary starts
     from it (--fingerprint), all with one digest.
  3. bin/poet-coordinator, called by a relative path from another directory with no LD_* variable set, runs two
     iterations of the quick preset on two local workers (bin/poet-worker, found beside it) and exits 0 with a
     checkpoint.
  4. Every shared object the coordinator and its workers loaded is the bundle's or glibc's, as seen twice: in the
     loader's own record (LD_DEBUG=libs,files into LD_DEBUG_OUTPUT, one file per process, inherited by the
     workers; it names the file each library was found in) and in /proc/PID/maps of the coordinator and its
     children, sampled while they run (which also shows what was dlopen'ed).
  5. The bundle's libraries win over LD_LIBRARY_PATH too (DT_RPATH): poet-worker --fingerprint with
     LD_LIBRARY_PATH naming the system's library directory still loads lib/'s.

Exit codes: 0 passed, 1 failed, 77 skipped (patchelf is missing outside CI; under CI=true that is a failure).
"""

import argparse
import contextlib
import ctypes
import glob
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from check_support import Failed, add_build_arguments, missing_tool, run_check  # noqa: E402

BUNDLE_TIMEOUT_S = 120  # bundle.sh: about 4 s on 2 cores
RUN_TIMEOUT_S = 90  # 2 iterations of the quick preset: about 5 s on 2 busy cores
# The C library's objects, which stay the machine's: those bundle.sh leaves out, and what libc itself loads from
# the machine's configuration (NSS modules, iconv's gconv modules).
GLIBC = re.compile(r"(ld-linux-x86-64\.so\.2|lib(c|m|mvec|pthread|dl|rt|resolv|util|anl|BrokenLocale|thread_db)"
                   r"\.so\.[0-9]+|libnsl\.so\.1|libc_malloc_debug\.so\.0|libnss_\w+\.so\.2)")


def is_glibc(path):
    return GLIBC.fullmatch(os.path.basename(path)) is not None or os.path.basename(os.path.dirname(path)) == "gconv"


def die_with_parent():
    # the coordinator ends with this process even if it is killed outright (a ctest timeout); its workers end
    # with the coordinator (--parent-pid)
    ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


def clean_environment(**extra):
    env = {k: v for k, v in os.environ.items() if not k.startswith("LD_")}
    env.update(extra)
    return env


# ---------------------------------------------------------------------------------------------------------
# what a process loaded


def loader_record(path):
    """The files the loader mapped, from an LD_DEBUG=libs,files trace: a library searched by name is the last
    file tried before its link map is made; one opened by path is named by it."""
    loaded, tried = [], None
    for line in open(path, encoding="utf-8", errors="replace"):
        m = re.search(r"trying file=(\S+)", line)
        if m:
            tried = m.group(1)
            continue
        m = re.search(r"file=(\S+) \[\d+\];\s+generating link map", line)
        if m:
            loaded.append(os.path.realpath(m.group(1) if m.group(1).startswith("/") else tried or m.group(1)))
            tried = None
    return loaded


_elf = {}


def is_elf(path):
    if path not in _elf:
        try:
            with open(path, "rb") as f:
                _elf[path] = f.read(4) == b"\x7fELF"
        except OSError:
            _elf[path] = False
    return _elf[path]


def mapped_objects(pid):
    """The ELF files mapped into a live process (its executable and every shared object); empty once it ended."""
    objects = set()
    with contextlib.suppress(OSError):
        for line in open(f"/proc/{pid}/maps", encoding="utf-8", errors="replace"):
            parts = line.split(maxsplit=5)
            if len(parts) == 6 and parts[5].startswith("/"):
                path = parts[5].strip().removesuffix(" (deleted)")
                if is_elf(path):
                    objects.add(os.path.realpath(path))
    return objects


def children_of(pid):
    out = []
    for stat in glob.glob("/proc/[0-9]*/stat"):
        with contextlib.suppress(OSError, ValueError, IndexError):
            fields = open(stat, encoding="utf-8", errors="replace").read().rsplit(")", 1)[1].split()
            if int(fields[1]) == pid:
                out.append(int(stat.split("/")[2]))
    return out


def executable_of(pid):
    with contextlib.suppress(OSError):
        return os.path.realpath(os.readlink(f"/proc/{pid}/exe"))
    return None


# ---------------------------------------------------------------------------------------------------------


class Bundle:
    """The unpacked bundle: where its binaries and libraries are, and which loaded objects are neither."""

    def __init__(self, top):
        self.top = os.path.realpath(top)
        self.bin = os.path.join(self.top, "bin")
        self.lib = os.path.join(self.top, "lib")

    def owns(self, path):
        return path.startswith(self.bin + "/") or path.startswith(self.lib + "/")

    def strays(self, objects):
        """The objects neither the bundle's nor glibc's."""
        return sorted(p for p in objects if not self.owns(p) and not is_glibc(p))


def make_bundle(args, root):
    archive = os.path.join(root, "poet.tar.gz")
    r = subprocess.run(["bash", os.path.join(args.source, "deploy", "bundle.sh"), args.build_dir, archive],
                       capture_output=True, text=True, timeout=BUNDLE_TIMEOUT_S)
    if r.returncode != 0:
        raise Failed(f"deploy/bundle.sh exited {r.returncode}:\n{r.stdout}{r.stderr}")
    print(f"  {r.stdout.strip()}")
    # an unusual but legal place: punctuation the shell, URLs or the loader could each trip on (':' separates
    # the directories of an RPATH; the loader splits it before it puts the path in for $ORIGIN)
    unpacked = os.path.join(root, "un+usual,dir=@%~x:y", "deeper")
    os.makedirs(unpacked)
    r = subprocess.run(["tar", "-xzf", archive, "-C", unpacked], capture_output=True, text=True, timeout=60)
    if r.returncode != 0:
        raise Failed(f"tar -xzf {archive}: {r.stderr}")
    tops = os.listdir(unpacked)
    if len(tops) != 1 or not tops[0].startswith("poet-"):
        raise Failed(f"the archive holds {tops}, not one directory poet-VERSION")
    return Bundle(os.path.join(unpacked, tops[0]))


def check_contents(bundle, binaries, errors):
    for name in binaries:
        if not os.access(os.path.join(bundle.bin, name), os.X_OK):
            errors.append(f"bin/{name} is missing: bundle.sh does not ship every executable of the build")
    libraries = sorted(os.listdir(bundle.lib))
    errors += [f"lib/{n} is glibc's: the C library must stay the machine's" for n in libraries if is_glibc(n)]
    for needed in ("libstdc++.so.6", "libgcc_s.so.1", "libzmq.so.5", "libprotobuf.so.32"):
        if needed not in libraries:
            errors.append(f"lib/ lacks {needed}")
    # Box2D is linked statically (third_party/box2d), not Debian's shared libbox2d
    errors += [f"lib/{n}: Box2D must be in the binaries, not a shared library" for n in libraries if "box2d" in n]
    for path in ("configs/quick.textproto", "data/walkers/flat-walker.json", "README.md"):
        if not os.path.isfile(os.path.join(bundle.top, path)):
            errors.append(f"{path} is missing")
    readme_path = os.path.join(bundle.top, "README.md")
    readme = open(readme_path, encoding="utf-8").read() if os.path.isfile(readme_path) else ""
    m = re.search(r"needs glibc >= (\d+)\.(\d+)", readme, re.IGNORECASE)
    here = os.confstr("CS_GNU_LIBC_VERSION").split()[-1]  # "glibc 2.36"
    if not m:
        errors.append("README.md does not say which glibc it needs (needs glibc >= X.Y)")
    elif tuple(map(int, here.split("."))) < (int(m.group(1)), int(m.group(2))):
        errors.append(f"the bundle needs glibc >= {m.group(1)}.{m.group(2)}, newer than this machine's {here}")
    print(f"  {len(libraries)} libraries in lib/; {m.group(0) if m else 'no glibc named'} (this machine: {here})")


def run_from_bundle(bundle, root, errors):
    """The short run, with the loader's record and the processes' maps; the processes are reaped on every path."""
    elsewhere = os.path.join(root, "elsewhere")
    traces = os.path.join(root, "ld-debug")
    os.makedirs(elsewhere)
    os.makedirs(traces)

    def rel(*parts):  # relative to the run's working directory: the bundle is found from where it is called
        return os.path.relpath(os.path.join(bundle.top, *parts), elsewhere)

    argv = [rel("bin", "poet-coordinator"), "--config", rel("configs", "quick.textproto"), "--run-dir", "run",
            "--start-from", rel("data", "walkers", "flat-walker.json"), "--iterations", "2", "--local-workers", "2",
            "--status-address", "127.0.0.1:0", "--quiet"]
    env = clean_environment(LD_DEBUG="libs,files", LD_DEBUG_OUTPUT=os.path.join(traces, "ld"))
    print(f"  in {elsewhere}: {' '.join(argv)}")
    log_path = os.path.join(root, "coordinator.err")
    mapped = {}  # ELF path -> the processes that mapped it ("coordinator", "worker PID")
    workers = set()
    with open(log_path, "w") as log:
        coordinator = subprocess.Popen(argv, cwd=elsewhere, env=env, stdout=log, stderr=log, start_new_session=True,
                                       preexec_fn=die_with_parent)
    start = time.monotonic()
    try:
        while coordinator.poll() is None and time.monotonic() - start < RUN_TIMEOUT_S:
            for pid in [coordinator.pid] + children_of(coordinator.pid):
                label = "coordinator" if pid == coordinator.pid else f"worker {pid}"
                if pid != coordinator.pid and executable_of(pid) == os.path.join(bundle.bin, "poet-worker"):
                    workers.add(pid)
                for path in mapped_objects(pid):
                    mapped.setdefault(path, set()).add(label)
            time.sleep(0.1)
        code = coordinator.wait(timeout=max(1.0, RUN_TIMEOUT_S - (time.monotonic() - start)))
    except subprocess.TimeoutExpired:
        code = None
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(coordinator.pid, signal.SIGKILL)
        coordinator.wait()
        for pid in workers:  # in process groups of their own; ended by now unless the coordinator was killed
            if executable_of(pid) == os.path.join(bundle.bin, "poet-worker"):
                with contextlib.suppress(ProcessLookupError):
                    os.kill(pid, signal.SIGKILL)
    log = open(log_path, encoding="utf-8", errors="replace").read()
    print(f"  the run took {time.monotonic() - start:.1f} s, exit {code}")

    # the run
    if code != 0:
        errors.append(f"the coordinator exited {code}, not 0 (timeout {RUN_TIMEOUT_S} s):\n{log}")
    if "run finished at iteration 2" not in log:
        errors.append(f"the coordinator's log does not say the run finished at iteration 2:\n{log}")
    if not os.path.isfile(os.path.join(elsewhere, "run", "checkpoint.pb")):
        errors.append("no checkpoint in the run directory")
    if len(workers) < 2:
        errors.append(f"{len(workers)} processes of the bundle's poet-worker were seen under the coordinator, not 2")

    # what was loaded: the loader's record of every process, and the maps sampled while they ran
    records = {os.path.basename(p): loader_record(p) for p in glob.glob(os.path.join(traces, "ld.*"))}
    if len(records) < 3:
        errors.append(f"LD_DEBUG_OUTPUT holds the records of {len(records)} processes, not the coordinator's and "
                      f"two workers' ({sorted(records)})")
    for process, loaded in sorted(records.items()):
        errors += [f"{process} (LD_DEBUG) loaded {p} from the machine" for p in bundle.strays(loaded)]
    for path in bundle.strays(mapped):
        errors.append(f"{', '.join(sorted(mapped[path]))} mapped {path} from the machine (/proc/PID/maps)")
    for evidence, paths in (("LD_DEBUG", {p for loaded in records.values() for p in loaded}), ("maps", mapped)):
        if os.path.join(bundle.lib, "libstdc++.so.6") not in paths:
            errors.append(f"{evidence}: libstdc++.so.6 was not loaded from the bundle's lib/")
    from_bundle = {p for p in mapped if bundle.owns(p)}
    print(f"  {len(records)} processes' loader records, {sum(len(v) for v in records.values())} objects loaded; "
          f"{len(mapped)} objects mapped, {len(from_bundle)} of them the bundle's, the others: "
          f"{', '.join(sorted({os.path.basename(p) for p in mapped if not bundle.owns(p)}))}")


def check_every_binary_starts(bundle, root, errors):
    """Each binary of the bundle starts from it (--fingerprint) with nothing but glibc from the machine, and all
    are of one build (one digest)."""
    traces = os.path.join(root, "ld-binaries")
    os.makedirs(traces)
    digests = {}
    for name in sorted(os.listdir(bundle.bin)):
        trace = os.path.join(traces, name)
        r = subprocess.run([os.path.join(bundle.bin, name), "--fingerprint"], capture_output=True, text=True,
                           timeout=30, env=clean_environment(LD_DEBUG="libs,files", LD_DEBUG_OUTPUT=trace))
        m = re.search(r"^digest: (\S+)$", r.stdout, re.MULTILINE)
        if r.returncode != 0 or not m:
            errors.append(f"bin/{name} --fingerprint: exit {r.returncode}, no digest\n{r.stderr}")
            continue
        digests[name] = m.group(1)
        loaded = [p for t in glob.glob(trace + ".*") for p in loader_record(t)]
        errors += [f"bin/{name} --fingerprint loaded {p} from the machine" for p in bundle.strays(loaded)]
    if len(set(digests.values())) > 1:
        errors.append(f"the bundle's binaries are of different builds: {digests}")
    print(f"  {len(digests)} binaries start from the bundle, digest {', '.join(sorted(set(digests.values())))}")


def check_rpath_wins(bundle, root, errors):
    """LD_LIBRARY_PATH naming the system's libraries does not take them over (DT_RPATH comes first)."""
    # the directory of this machine's libraries: where its libc is (Debian's holds libstdc++, libzmq... too)
    system = next(os.path.dirname(p) for p in mapped_objects(os.getpid()) if os.path.basename(p) == "libc.so.6")
    trace = os.path.join(root, "ld-rpath")
    r = subprocess.run([os.path.join(bundle.bin, "poet-worker"), "--fingerprint"], capture_output=True, text=True,
                       timeout=30, env=clean_environment(LD_LIBRARY_PATH=system, LD_DEBUG="libs,files",
                                                         LD_DEBUG_OUTPUT=trace))
    loaded = [p for t in glob.glob(trace + ".*") for p in loader_record(t)]
    if r.returncode != 0 or not loaded:
        errors.append(f"poet-worker --fingerprint with LD_LIBRARY_PATH={system}: exit {r.returncode}, "
                      f"{len(loaded)} objects recorded\n{r.stderr}")
    errors += [f"with LD_LIBRARY_PATH={system}, poet-worker loaded {p}" for p in bundle.strays(loaded)]


def check(args):
    if shutil.which("patchelf") is None:
        missing_tool("patchelf is not installed (Debian package patchelf)")
    binaries = [pair.partition("=")[0] for pair in args.binary]
    errors = []
    root = tempfile.mkdtemp(prefix="poet_bundle_")
    try:
        bundle = make_bundle(args, root)
        check_contents(bundle, binaries, errors)
        if not errors:
            check_every_binary_starts(bundle, root, errors)
            run_from_bundle(bundle, root, errors)
            check_rpath_wins(bundle, root, errors)
    finally:
        shutil.rmtree(root, ignore_errors=True)
    if errors:
        raise Failed(f"{len(errors)} checks failed:\n  - " + "\n  - ".join(errors))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_build_arguments(parser)
    args = parser.parse_args()
    args.source = os.path.realpath(args.source)
    return run_check("bundle", lambda: check(args))


if __name__ == "__main__":
    sys.exit(main())
