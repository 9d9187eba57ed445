#!/usr/bin/python3
"""crossmachine_debian13: this build's bundle on another C library computes the same bits.

A Debian 13 (trixie) root, made by debootstrap --variant=minbase from http://deb.debian.org/debian (glibc 2.41,
where this machine is Debian 12 with glibc 2.36), gets the archive of deploy/bundle.sh unpacked in it, with
poet_unit_tests beside it (the libraries it loads beyond the bundle's copied next to it and found through
$ORIGIN, as bundle.sh does), and /proc mounted (the loader expands $ORIGIN through /proc/self). Inside the root
(chroot), where every library but the C library is the bundle's and the C library is the root's:

  - poet-coordinator --fingerprint and poet-worker --fingerprint print this machine's fingerprints, line for line
    (the arithmetic: line is what the machine computes: the project's math, Box2D and the walker);
  - poet_unit_tests --gtest_filter='Golden.*' passes (the golden digests of rollouts and small runs);
  - the small run of tests/integration/coordinator_run_fixture.h on two threads ends in the run files
    (checkpoint.pb, events.jsonl, pair_stats.csv, annecs.csv) of the same run made natively, byte for byte.

Only with POET_TEST_CROSSMACHINE=1 and as root; otherwise it exits 77 saying why. A missing tool is installed by
deploy/install-deps.sh --crossmachine. The root is a cache, BUILD/crossmachine/debian13-root (made once, about
200 MB; the check says when it reuses it; remove the directory to make it again); everything else this check
starts or makes — processes, the /proc mount, the bundle in the root, its work directory
BUILD/crossmachine/work/debian13-PID — is removed on success, failure, SIGTERM and its own deadline, and what a run
killed outright left is removed by the next.

  check_debian13.py --build-dir BUILD --source REPOSITORY
"""

import datetime
import os
import re
import shutil
import subprocess
import sys
import time

sys.dont_write_bytecode = True  # no __pycache__ in the source tree

from crossmachine_support import (GLIBC_FAMILY, CacheLock, Children, Cleanup, Failed, checked, compare_fingerprints,
                                  compare_golden, compare_runs, ensure_installed, gtest_summary,
                                  log, main, mounts_under, native_binaries, remove_stale, remove_tree, report,
                                  require_opt_in, set_deadline, stale_native_build, tail, tiny_config,
                                  unmount_all_under, work_dir)

NAME = "crossmachine_debian13"
DEADLINE_S = 3300  # inside ctest's TIMEOUT of 3600
SUITE = "trixie"
VARIANT = "minbase"
MIRROR = os.environ.get("POET_DEBIAN_MIRROR", "http://deb.debian.org/debian")
STAMP = ".poet-crossmachine-root"
TOOLS = ["debootstrap", "patchelf", "chroot", "mount", "umount", "tar", "ldd"]


def stamp_text():
    return f"suite {SUITE}\nvariant {VARIANT}\nmirror {MIRROR}\n"


def c_library(argv):
    """The first line glibc's libc.so.6 prints when run, and its version."""
    r = subprocess.run(argv, capture_output=True, text=True, timeout=60)
    first = (r.stdout.splitlines() or [""])[0]
    m = re.search(r"version (\d+\.\d+)", first)
    if not m:
        raise Failed(f"{' '.join(argv)} printed no glibc version: {r.stdout}{r.stderr}")
    return first, m.group(1)


def make_root(children, cache_root, root, deadline, cleanup):
    """The Debian 13 root: reused when its stamp names this suite, variant and mirror; else made by debootstrap in a
    directory beside it, renamed into place when complete."""
    stamp = os.path.join(root, STAMP)
    if os.path.isfile(stamp):
        with open(stamp) as f:
            text = f.read()
        if text.startswith(stamp_text()):
            made = re.search(r"made (\S+)", text)
            log(f"reusing the Debian 13 root {root} (made {made.group(1) if made else '?'}; "
                f"remove it to make it again)")
            return "reused"
        log(f"{root} was made otherwise ({text.strip()!r}): making it again")
    remove_stale(cache_root, os.path.basename(root) + ".partial")
    partial = f"{root}.partial-{os.getpid()}"
    remove_tree(partial)
    # a root left half made is removed after debootstrap and what it started are killed (the cleanup's order)
    cleanup.push("removing " + partial, lambda: remove_tree(partial))
    log(f"making the Debian 13 root: debootstrap --variant={VARIANT} {SUITE} {partial} {MIRROR}")
    started = time.monotonic()
    code, out, err = children.run(["debootstrap", f"--variant={VARIANT}", SUITE, partial, MIRROR], cache_root,
                                  "debootstrap", deadline - 600)
    if code != 0:
        raise Failed(f"debootstrap exited {code} ({cache_root}/debootstrap.out, .err):\n{tail(out)}\n{tail(err)}")
    with open(os.path.join(partial, STAMP), "w") as f:
        f.write(stamp_text() + f"made {datetime.datetime.now(datetime.timezone.utc).isoformat(timespec='seconds')}\n")
    unmount_all_under(partial, "debootstrap left it mounted")
    remove_tree(root)
    os.rename(partial, root)
    seconds = time.monotonic() - started
    log(f"made the Debian 13 root in {seconds:.0f} s ({cache_root}/debootstrap.out)")
    return f"made in {seconds:.0f} s"


def copy_unit_tests(unit_tests, target_dir, bundle_lib_rel):
    """poet_unit_tests in target_dir with the libraries it loads beyond the bundle's beside it, its RPATH (and
    theirs) $ORIGIN and the bundle's lib/; the sonames copied."""
    os.makedirs(target_dir)
    shutil.copy2(unit_tests, target_dir)
    binary = os.path.join(target_dir, os.path.basename(unit_tests))
    listing = subprocess.run(["ldd", unit_tests], capture_output=True, text=True, timeout=60).stdout
    if "not found" in listing:
        raise Failed(f"{unit_tests}: libraries not found on this machine:\n{listing}")
    bundled = set(os.listdir(os.path.join(target_dir, "..", bundle_lib_rel)))
    extra = []
    for soname, path in re.findall(r"^\s*(\S+) => (/\S+)", listing, re.M):
        if GLIBC_FAMILY.match(soname) or soname in bundled:
            continue
        shutil.copy(os.path.realpath(path), os.path.join(target_dir, soname))
        extra.append(soname)
    rpath = f"$ORIGIN:$ORIGIN/../{bundle_lib_rel}"
    for f in [binary] + [os.path.join(target_dir, s) for s in extra]:
        subprocess.run(["patchelf", "--force-rpath", "--set-rpath", rpath, f], check=True, timeout=120)
    return binary, extra


def check_loaded_objects(children, root, in_root, binary, scratch, deadline):
    """Inside the root, with the environment's library path emptied: every library but glibc's resolves to the
    bundle's (or poet_unit_tests' own) copy; glibc's are the root's. (LD_TRACE_LOADED_OBJECTS is ldd's own way.)"""
    code, out, err = children.run(["chroot", root, "/usr/bin/env", "-u", "LD_LIBRARY_PATH", "-u", "LD_PRELOAD",
                                   "LD_TRACE_LOADED_OBJECTS=1", binary], scratch,
                                  "ldd_" + os.path.basename(binary), deadline)
    checked(code, out, err, f"LD_TRACE_LOADED_OBJECTS=1 {binary} in the root")
    strays, ours, libc = [], 0, None
    for soname, path in re.findall(r"^\s*(\S+) => (\S+)", out, re.M):
        path = os.path.normpath(path)
        if path == "not" or "not found" in path:
            strays.append(f"{soname} not found")
        elif GLIBC_FAMILY.match(soname):
            if path.startswith(in_root + "/"):
                strays.append(f"{soname} => {path} (glibc must be the root's)")
            if soname == "libc.so.6":
                libc = path
        elif path.startswith(in_root + "/"):
            ours += 1
        else:
            strays.append(f"{soname} => {path} (the root's, not the bundle's)")
    if "not found" in out:
        strays.append("a library not found:\n" + out)
    if strays:
        raise Failed(f"{binary} in the root loads:\n  " + "\n  ".join(strays))
    return ours, libc


def check(args):
    require_opt_in("the bundle in a Debian 13 root")
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
    ensure_installed(source, TOOLS, [], deadline)
    times = {}

    cache_root = os.path.join(build_dir, "crossmachine")
    CacheLock(cache_root, "debian13", cleanup)
    root = os.path.join(cache_root, "debian13-root")
    unmount_all_under(root, "left mounted by a run that was killed")
    scratch = work_dir(build_dir, "debian13", cleanup)
    children = Children(cleanup)
    times["root"] = make_root(children, cache_root, root, deadline, cleanup)
    remove_stale(os.path.join(root, "tmp"), "poet-crossmachine")

    host_line, host_version = c_library(["/lib/x86_64-linux-gnu/libc.so.6"])
    root_line, root_version = c_library(["chroot", root, "/usr/lib/x86_64-linux-gnu/libc.so.6"])
    log(f"this machine's C library: {host_line}")
    log(f"the root's C library:     {root_line}")
    if host_version == root_version:
        raise Failed(f"the root's glibc is this machine's ({host_version}): the check would prove nothing")

    in_root = f"/tmp/poet-crossmachine-{os.getpid()}"  # as the root sees it
    on_host = root + in_root
    cleanup.push("removing " + on_host, lambda: remove_tree(on_host))
    os.makedirs(on_host)

    # the bundle, unpacked in the root
    started = time.monotonic()
    archive = os.path.join(scratch, "poet.tar.gz")
    code, out, err = children.run(["bash", os.path.join(source, "deploy", "bundle.sh"), build_dir, archive], scratch,
                                  "bundle", deadline)
    checked(code, out, err, "deploy/bundle.sh")
    log(tail(out, 1))
    subprocess.run(["tar", "-xzf", archive, "-C", on_host], check=True, timeout=300)
    bundles = [d for d in os.listdir(on_host) if d.startswith("poet-")]
    if len(bundles) != 1:
        raise Failed(f"the archive unpacked into {bundles}, not one poet-VERSION directory")
    bundle = bundles[0]
    unit_tests, extra = copy_unit_tests(native["unit_tests"], os.path.join(on_host, "tests"), f"{bundle}/lib")
    times["bundle"] = time.monotonic() - started
    log(f"bundle {bundle} unpacked in the root at {in_root} in {times['bundle']:.0f} s; poet_unit_tests beside it "
        f"with {len(extra)} more librar{'y' if len(extra) == 1 else 'ies'} ({', '.join(extra) or 'none'})")

    # /proc in the root: $ORIGIN is expanded through /proc/self/exe
    proc = os.path.join(root, "proc")
    if mounts_under(proc):
        raise Failed(f"{proc} is mounted already")
    subprocess.run(["mount", "-t", "proc", "proc", proc], check=True, timeout=60)
    cleanup.push("unmounting " + proc, lambda: unmount_all_under(proc, "the check is over"))

    bin_dir = f"{in_root}/{bundle}/bin"
    for binary in (f"{bin_dir}/poet-coordinator", f"{bin_dir}/poet-worker", f"{in_root}/tests/poet_unit_tests"):
        ours, libc = check_loaded_objects(children, root, in_root, binary, scratch, deadline)
        log(f"{os.path.basename(binary)} in the root: {ours} libraries from {in_root}, the C library the root's "
            f"({libc})")

    problems = []
    env = {k: v for k, v in os.environ.items() if not k.startswith("LD_") and k != "GLIBC_TUNABLES"}

    # the fingerprints
    for name, native_binary in (("poet-coordinator", native["coordinator"]), ("poet-worker", native["worker"])):
        here = checked(*children.run([native_binary, "--fingerprint"], scratch, f"fp_native_{name}", deadline),
                       f"{native_binary} --fingerprint")
        there = checked(*children.run(["chroot", root, f"{bin_dir}/{name}", "--fingerprint"], scratch,
                                      f"fp_root_{name}", deadline, env=env), f"{name} --fingerprint in the root")
        differences = compare_fingerprints(here, there, "Debian 13 root", whole=True)
        if differences:
            problems.append(f"{name} --fingerprint differs in the Debian 13 root:\n" + "\n".join(differences))
        else:
            lines = dict(line.split(": ", 1) for line in here.splitlines() if ": " in line)
            log(f"{name} --fingerprint: identical ({len(here.splitlines())} lines; arithmetic: "
                f"{lines.get('arithmetic')}; digest: {lines.get('digest')})")

    # the golden digests, in the root and (to tell a pin awaiting its update from a difference) natively
    golden = ["--gtest_filter=Golden.*", "--gtest_brief=1"]
    native_golden = children.run([native["unit_tests"]] + golden, scratch, "golden_native", deadline)
    started = time.monotonic()
    code, out, err = children.run(["chroot", root, f"{in_root}/tests/poet_unit_tests"] + golden, scratch,
                                  "golden_root", deadline, env=env)
    times["golden"] = time.monotonic() - started
    golden_problems = compare_golden(native_golden[:2], (code, out), "the Debian 13 root")
    problems += golden_problems
    if not golden_problems:
        log(f"poet_unit_tests --gtest_filter=Golden.* in the root: {gtest_summary(out)} in {times['golden']:.0f} s")

    # the small run on two threads, natively and in the root
    config = tiny_config(source)
    for path in (os.path.join(scratch, "tiny.textproto"), os.path.join(on_host, "tiny.textproto")):
        with open(path, "w") as f:
            f.write(config)
    common = ["--quiet", "--status-address", "127.0.0.1:0", "--threads", "2"]
    started = time.monotonic()
    checked(*children.run([native["coordinator"], "--config", os.path.join(scratch, "tiny.textproto"), "--run-dir",
                           os.path.join(scratch, "native-run")] + common, scratch, "run_native", deadline),
            "the native run")
    times["run_native"] = time.monotonic() - started
    started = time.monotonic()
    checked(*children.run(["chroot", root, f"{bin_dir}/poet-coordinator", "--config", f"{in_root}/tiny.textproto",
                           "--run-dir", f"{in_root}/run"] + common, scratch, "run_root", deadline, env=env),
            "the run in the root")
    times["run_root"] = time.monotonic() - started
    log(f"the small run on 2 threads: {times['run_native']:.1f} s natively, {times['run_root']:.1f} s in the root; "
        f"its files:")
    differences = compare_runs(os.path.join(scratch, "native-run"), os.path.join(on_host, "run"), "the root's run",
                               source=source)
    if differences:
        problems.append("the run in the Debian 13 root differs from the native one:\n  " + "\n  ".join(differences))

    report(NAME, problems, stale, f"root {times['root']}",
           f"root {times['root']}; glibc {root_version} in the root, {host_version} here; bundle "
           f"{times['bundle']:.0f} s; fingerprints identical; golden digests pass ({times['golden']:.0f} s); the run's "
           f"files identical ({times['run_native']:.1f} s native, {times['run_root']:.1f} s in the root)")


if __name__ == "__main__":
    main(NAME, check, __doc__)
