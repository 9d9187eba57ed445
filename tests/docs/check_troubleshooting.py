#!/usr/bin/python3
"""docs/troubleshooting.md against the binaries: the messages the page shows are what they print now.

Each block of the page marked `<!-- check: NAME -->` is a message copied from a run; this script provokes the same
situation with the built poet-coordinator (or poetctl) and compares. The page writes the parts that differ from run
to run as placeholders (PLACEHOLDERS below): each is replaced by what this run has, TIME by a pattern of spdlog's
time stamp. Every line of a block must be a whole line of the process's output, in the
block's order. A block named here that the page lacks, or a marked block no case provokes, is a failure too.

Usage: check_troubleshooting.py --page docs/troubleshooting.md --source SRC --coordinator BIN --poetctl BIN

Bounded in time (each process at most 20 s, the whole well under a minute), on ephemeral loopback ports; every
process started is killed and the scratch directory removed, also on failure. Debian's python3, stdlib only.
"""

import argparse
import os
import re
import resource
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time
import zlib

PLACEHOLDERS = ("WORKER_DIGEST", "WORKER_ARITHMETIC", "WRITTEN_ARITHMETIC", "ARITHMETIC_PARTS", "ARITHMETIC",
                "WORKER", "RUN_DIR", "CONFIG", "DIGEST", "TIME", "PID", "PORT", "KEYS", "POLICY",
                "PACK", "HEADER_CRC", "BODY_CRC", "BODY_BYTES", "FILE_BYTES")
TIME_PATTERN = r"\d{4}-\d\d-\d\d \d\d:\d\d:\d\d\.\d{3}"  # spdlog's [%Y-%m-%d %H:%M:%S.%e]
MARK = re.compile(r"^<!-- check: ([a-z0-9-]+) -->$")
PROCESS_SECONDS = 20


def page_blocks(path):
    """{name: [lines]} of the page's marked code blocks (the first fenced block after each mark)."""
    blocks = {}
    lines = open(path, encoding="utf-8").read().split("\n")
    i = 0
    while i < len(lines):
        mark = MARK.match(lines[i].strip())
        i += 1
        if not mark:
            continue
        while i < len(lines) and not lines[i].strip():
            i += 1
        if i >= len(lines) or not lines[i].startswith("```"):
            raise SystemExit(f"{path}: the mark '{mark.group(1)}' is not followed by a code block")
        body = []
        i += 1
        while i < len(lines) and not lines[i].startswith("```"):
            body.append(lines[i])
            i += 1
        if mark.group(1) in blocks:
            raise SystemExit(f"{path}: the mark '{mark.group(1)}' comes twice")
        blocks[mark.group(1)] = body
    return blocks


def line_pattern(line, values):
    """A page line as a regular expression: its placeholders replaced by this run's values."""
    tokens = re.split(r"\b(" + "|".join(PLACEHOLDERS) + r")\b", line)
    out = []
    for k, token in enumerate(tokens):
        if k % 2 == 0:
            out.append(re.escape(token))
        elif token == "TIME":
            out.append(TIME_PATTERN)
        elif token in values:
            out.append(re.escape(str(values[token])))
        else:
            out.append(re.escape(token))  # a word of the message itself, not a placeholder of this case
    return re.compile("".join(out))


def missing_lines(block, output, values):
    """The block's lines not found, in order, among the output's whole lines."""
    have = output.split("\n")
    at = 0
    missing = []
    for line in block:
        pattern = line_pattern(line, values)
        k = at
        while k < len(have) and not pattern.fullmatch(have[k]):
            k += 1
        if k == len(have):
            missing.append(line)
        else:
            at = k + 1
    return missing


class Processes:
    """Every process started, killed at the end whatever happened."""

    def __init__(self, scratch):
        self.scratch = scratch
        self.started = []

    def start(self, argv, name, preexec_fn=None):
        err = open(os.path.join(self.scratch, name + ".err"), "wb")
        process = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=err, stderr=err, preexec_fn=preexec_fn)
        err.close()
        process.log = os.path.join(self.scratch, name + ".err")
        self.started.append(process)
        return process

    def run(self, argv, name, preexec_fn=None):
        """Runs to its end (at most PROCESS_SECONDS): (exit code, output)."""
        process = self.start(argv, name, preexec_fn)
        try:
            code = process.wait(PROCESS_SECONDS)
        except subprocess.TimeoutExpired:
            raise AssertionError(f"{name}: still running after {PROCESS_SECONDS} s: {argv}")
        return code, read(process.log)

    def kill_all(self):
        for process in self.started:
            if process.poll() is None:
                process.kill()
            process.wait()


def read(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        return f.read()


def await_line(process, pattern, what):
    """Waits (at most PROCESS_SECONDS) until the process's output has a line matching pattern; the match."""
    deadline = time.monotonic() + PROCESS_SECONDS
    regex = re.compile(pattern, re.MULTILINE)
    while time.monotonic() < deadline:
        found = regex.search(read(process.log))
        if found:
            return found
        if process.poll() is not None:
            raise AssertionError(f"{what}: the process ended ({process.returncode}) first:\n{read(process.log)}")
        time.sleep(0.05)
    raise AssertionError(f"{what}: not seen within {PROCESS_SECONDS} s:\n{read(process.log)}")


def taken_port():
    """A loopback TCP socket listening on an ephemeral port: (the socket, its port). Close it when done."""
    s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    s.bind(("127.0.0.1", 0))
    s.listen(1)
    return s, s.getsockname()[1]


# --- a peer that speaks ZMTP 3.0 (NULL security) with a Hello of another build: the coordinator's refusal ---

def _varint(n):
    out = bytearray()
    while True:
        byte = n & 0x7F
        n >>= 7
        out.append(byte | (0x80 if n else 0))
        if not n:
            return bytes(out)


def _field(number, wire_type, payload):
    key = _varint(number << 3 | wire_type)
    if wire_type == 2:
        return key + _varint(len(payload)) + payload
    return key + payload


def wire_protocol_version(source):
    """The PROTOCOL_VERSION of proto/wire.proto, which the coordinator compares before the fingerprint."""
    text = read(os.path.join(source, "proto", "wire.proto"))
    found = re.search(r"^\s*PROTOCOL_VERSION\s*=\s*(\d+)\s*;", text, re.MULTILINE)
    if found is None:
        raise Failure("proto/wire.proto: no line `PROTOCOL_VERSION = N;`")
    return int(found.group(1))


def hello_message(protocol_version, digest, name, arithmetic, arithmetic_parts):
    """proto/wire.proto's WorkerMessage{hello: Hello{protocol_version, fingerprint_digest, threads, name,
    arithmetic_digest, arithmetic}}."""
    hello = (_field(1, 0, _varint(protocol_version)) + _field(2, 1, struct.pack("<Q", digest)) +
             _field(4, 0, _varint(1)) + _field(5, 2, name.encode()) +
             _field(7, 1, struct.pack("<Q", arithmetic)) + _field(8, 2, arithmetic_parts.encode()))
    return _field(1, 2, hello)


def _zmtp_frame(body, command=False):
    flags = 0x04 if command else 0x00
    if len(body) > 255:
        return bytes([flags | 0x02]) + struct.pack(">Q", len(body)) + body
    return bytes([flags, len(body)]) + body


def _recv_exactly(conn, n):
    data = b""
    while len(data) < n:
        chunk = conn.recv(n - len(data))
        if not chunk:
            raise AssertionError("the coordinator closed the connection")
        data += chunk
    return data


def _recv_frame(conn):
    flags = _recv_exactly(conn, 1)[0]
    size = struct.unpack(">Q", _recv_exactly(conn, 8))[0] if flags & 0x02 else _recv_exactly(conn, 1)[0]
    return flags, _recv_exactly(conn, size)


def send_hello(port, message):
    """Connects to the job socket as a DEALER, sends one message and returns the first message answered."""
    with socket.create_connection(("127.0.0.1", port), timeout=PROCESS_SECONDS) as conn:
        greeting = b"\xff" + b"\x00" * 8 + b"\x7f" + bytes([3, 0]) + b"NULL".ljust(20, b"\x00") + b"\x00" * 32
        conn.sendall(greeting)
        _recv_exactly(conn, 64)
        ready = b"\x05READY" + b"\x0bSocket-Type" + struct.pack(">I", 6) + b"DEALER"
        conn.sendall(_zmtp_frame(ready, command=True))
        flags, body = _recv_frame(conn)
        if not (flags & 0x04 and body.startswith(b"\x05READY")):
            raise Failure(f"the job socket answered the greeting with {body!r}, not READY")
        conn.sendall(_zmtp_frame(message))
        while True:
            flags, body = _recv_frame(conn)
            if not flags & 0x04:
                return body


# --- the cases: each returns {block name: (output, placeholder values)} ---

def write(path, text):
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path


def refused_configs(args, procs, scratch):
    """Configs refused before any file is written: exit 2, the file and the field named."""
    cases = {
        "config-syntax": "mode: POET\nes { init_lr: 0.01\n",
        "config-unknown-field": "mode: POET\nseeds: 7\n",
        "config-out-of-bounds": "es { l2_coeff: 2 }\n",
        "config-contradiction": "poet { mc_low: 300 mc_high: 50 }\n",
        "config-sets-nothing": "# only a comment\n",
    }
    seen = {}
    for name, text in cases.items():
        config = write(os.path.join(scratch, name + ".textproto"), text)
        run_dir = os.path.join(scratch, name)
        code, out = procs.run([args.coordinator, "--config", config, "--run-dir", run_dir], name)
        expect(code == 2, f"{name}: exit {code}, not 2:\n{out}")
        expect(not os.path.exists(os.path.join(run_dir, "checkpoint.pb")), f"{name}: a checkpoint was written")
        seen[name] = (out, {"CONFIG": config, "RUN_DIR": run_dir})
    missing = os.path.join(scratch, "nowhere.textproto")
    code, out = procs.run([args.coordinator, "--config", missing, "--run-dir", os.path.join(scratch, "M")],
                          "config-missing")
    expect(code == 2, f"config-missing: exit {code}:\n{out}")
    seen["config-missing"] = (out, {"CONFIG": missing})
    return seen


def bad_command_line(args, procs, scratch):
    run_dir = os.path.join(scratch, "B")
    code, out = procs.run([args.coordinator, "--run-dir", run_dir, "--resume", "--iteration", "5"], "bad-option")
    expect(code == 2, f"bad-option: exit {code}:\n{out}")
    expect(not os.path.exists(run_dir), "bad-option: the run directory was made")
    return {"bad-command-line": (out, {})}


def refused_command_lines(args, procs, scratch):
    """Command lines refused before any file is opened: exit 2, no run directory made."""
    keys = os.path.join(scratch, "no-keys")
    cases = {
        "no-config-no-resume": ([], {}),
        "from-pack-without-resume": (["--from-pack", os.path.join(scratch, "some.pack")], {}),
        "listen-port-range": (["--config", args.quick, "--listen", "tcp://127.0.0.1:99999"], {}),
        "open-port": (["--config", args.quick, "--listen", "tcp://0.0.0.0:5555"], {}),
        "curve-keys-missing": (["--config", args.quick, "--curve-keys", keys], {"KEYS": keys}),
    }
    seen = {}
    for name, (options, values) in cases.items():
        run_dir = os.path.join(scratch, name)
        code, out = procs.run([args.coordinator, "--run-dir", run_dir, "--status-address", ""] + options, name)
        expect(code == 2, f"{name}: exit {code}, not 2:\n{out}")
        expect(not os.path.exists(run_dir), f"{name}: the run directory was made")
        seen[name] = (out, values)
    return seen


def refused_first_policies(args, procs, scratch):
    """--start-from a file that is not there, or not a policy of this network: exit 2, no checkpoint."""
    missing = os.path.join(scratch, "no-policy.json")
    small = write(os.path.join(scratch, "small-policy.json"), "[[1, 2, 3], 0]\n")
    seen = {}
    for name, policy in (("start-from-missing", missing), ("start-from-wrong-size", small)):
        run_dir = os.path.join(scratch, name)
        code, out = procs.run([args.coordinator, "--config", args.quick, "--run-dir", run_dir, "--start-from", policy,
                               "--status-address", ""], name)
        expect(code == 2, f"{name}: exit {code}, not 2:\n{out}")
        expect(not os.path.exists(os.path.join(run_dir, "checkpoint.pb")), f"{name}: a checkpoint was written")
        seen[name] = (out, {"POLICY": policy})
    return seen


def resume(args, procs, run_dir, name, more=()):
    """poet-coordinator --run-dir RUN_DIR --resume, without a status socket: (exit code, output)."""
    return procs.run([args.coordinator, "--run-dir", run_dir, "--resume", "--status-address", ""] + list(more), name)


def nothing_to_resume(args, procs, scratch):
    seen = {}
    absent = os.path.join(scratch, "absent")
    empty = os.path.join(scratch, "empty")
    os.mkdir(empty)
    for name, run_dir in (("resume-no-directory", absent), ("resume-no-checkpoint", empty)):
        code, out = resume(args, procs, run_dir, name)
        expect(code == 2, f"{name}: exit {code}, not 2:\n{out}")
        seen[name] = (out, {"RUN_DIR": run_dir})
    expect(not os.path.exists(absent), "resume-no-directory: the directory was made")
    return seen


def finished_run(args, procs, scratch, name):
    """A run of the quick preset stopped at iteration 0 (a checkpoint and its logs, in a fraction of a second)."""
    run_dir = os.path.join(scratch, name)
    code, out = procs.run([args.coordinator, "--config", args.quick, "--run-dir", run_dir, "--iterations", "0",
                           "--status-address", "", "--quiet"], name + "-made")
    expect(code == 0, f"{name}: the run of 0 iterations exited {code}:\n{out}")
    return run_dir


CHECKPOINT_HEADER = struct.Struct("<8sIQI")  # run_directory/files/checkpoint_file.h: magic, version, body size, CRC-32


def refused_checkpoints(args, procs, scratch, cases, run=None):
    """Each case's checkpoint bytes written as a run directory's (a copy of `run`, or alone): each resume refused
    with exit 2, the checkpoint left as it was. {case: (output, placeholder values)}."""
    seen = {}
    for name, (data, values) in cases.items():
        run_dir = os.path.join(scratch, name)
        if run is None:
            os.mkdir(run_dir)
        else:
            shutil.copytree(run, run_dir)
        with open(os.path.join(run_dir, "checkpoint.pb"), "wb") as f:
            f.write(data)
        code, out = resume(args, procs, run_dir, name)
        expect(code == 2, f"{name}: exit {code}, not 2:\n{out}")
        expect(open(os.path.join(run_dir, "checkpoint.pb"), "rb").read() == data, f"{name}: the checkpoint changed")
        seen[name] = (out, dict(values, RUN_DIR=run_dir))
    return seen


def _read_varint(data, at):
    value, shift = 0, 0
    while True:
        byte = data[at]
        at += 1
        value |= (byte & 0x7F) << shift
        shift += 7
        if byte < 0x80:
            return value, at


def checkpoint_fields(body):
    """The top-level fields of a serialised message, in order: (field number, start, end) of each key and value."""
    spans, at = [], 0
    while at < len(body):
        start = at
        key, at = _read_varint(body, at)
        wire = key & 7
        if wire == 0:
            _, at = _read_varint(body, at)
        elif wire == 1:
            at += 8
        elif wire == 2:
            length, at = _read_varint(body, at)
            at += length
        elif wire == 5:
            at += 4
        else:
            raise AssertionError(f"the checkpoint's field {key >> 3} has wire type {wire}")
        spans.append((key >> 3, start, at))
    return spans


def checkpoints_of_other_arithmetic(args, procs, scratch):
    """A run whose checkpoint has no arithmetic digest (written before the project's own math), or another one (a
    machine that computes differently): each resume refused with exit 2, the checkpoint left as it was."""
    sound = finished_run(args, procs, scratch, "arithmetic-sound")
    good = open(os.path.join(sound, "checkpoint.pb"), "rb").read()
    body = good[CHECKPOINT_HEADER.size:]
    # the top-level fields, as (number, start, end) spans: field 12 is arithmetic_digest (fixed64), and a build
    # before the project's own math wrote neither it nor what came after it (field 13, written_by)
    spans = checkpoint_fields(body)
    digest = [(start, end) for number, start, end in spans if number == 12]
    expect(len(digest) == 1 and digest[0][1] - digest[0][0] == 9, "the checkpoint has no arithmetic digest (field 12)")
    value_at = digest[0][1] - 8
    written = struct.unpack("<Q", body[value_at:value_at + 8])[0]
    ours, parts = fingerprint_arithmetic(args.coordinator)
    expect(written == ours, f"the checkpoint's arithmetic digest {written:016x} is not --fingerprint's {ours:016x}")
    before_own_math = b"".join(body[start:end] for number, start, end in spans if number < 12)

    def with_body(new_body):
        header = CHECKPOINT_HEADER.pack(b"POETCKPT", 1, len(new_body), zlib.crc32(new_body))
        return header + new_body
    cases = {
        "checkpoint-before-own-math": (with_body(before_own_math), {}),
        "checkpoint-other-arithmetic": (with_body(body[:value_at] + struct.pack("<Q", ours ^ 1) + body[value_at + 8:]), {
            "ARITHMETIC": f"{ours:016x}", "ARITHMETIC_PARTS": parts, "WRITTEN_ARITHMETIC": f"{ours ^ 1:016x}"}),
    }
    return refused_checkpoints(args, procs, scratch, cases, sound)


def damaged_checkpoints(args, procs, scratch):
    """A checkpoint cut to 4 bytes, replaced by text, cut in its body, one byte of its body changed, or of a newer
    format: each resume refused with exit 2, the checkpoint left as it was."""
    good = open(os.path.join(finished_run(args, procs, scratch, "sound"), "checkpoint.pb"), "rb").read()
    _, version, body_bytes, header_crc = CHECKPOINT_HEADER.unpack_from(good)
    flipped = bytearray(good)
    flipped[CHECKPOINT_HEADER.size + 100] ^= 0xFF
    newer = bytearray(good)
    struct.pack_into("<I", newer, 8, version + 1)
    half = good[:len(good) // 2]
    cases = {
        "checkpoint-short": (good[:4], {}),
        "checkpoint-not-a-checkpoint": (b"not a checkpoint, but text in its place\n", {}),
        "checkpoint-truncated": (half, {"BODY_BYTES": body_bytes, "FILE_BYTES": len(half) - CHECKPOINT_HEADER.size}),
        "checkpoint-checksum": (bytes(flipped), {
            "HEADER_CRC": f"{header_crc:08x}",
            "BODY_CRC": f"{zlib.crc32(bytes(flipped[CHECKPOINT_HEADER.size:])):08x}"}),
        "checkpoint-newer-format": (bytes(newer), {}),
    }
    return refused_checkpoints(args, procs, scratch, cases)


def refused_run_dirs(args, procs, scratch):
    """A new run refused on a directory holding a run of another config, or a run's logs without its checkpoint."""
    seen = {}
    other_run = finished_run(args, procs, scratch, "other-run")
    other = write(os.path.join(scratch, "other.textproto"), "mode: POET\nseed: 2\n")
    code, out = procs.run([args.coordinator, "--config", other, "--run-dir", other_run, "--status-address", ""],
                          "another-config")
    expect(code == 2, f"another-config: exit {code}, not 2:\n{out}")
    seen["run-dir-another-config"] = (out, {"RUN_DIR": other_run})

    # the page's listing, made up file by file: the message names each with its size
    logs = os.path.join(scratch, "logs-only")
    for path, size in (("events.jsonl", 115), ("pair_stats.csv", 542), ("annecs.csv", 62), ("envs/0.json", 0),
                       ("policies/0.json", 0), ("policies/1.json", 0)):
        os.makedirs(os.path.dirname(os.path.join(logs, path)), exist_ok=True)
        write(os.path.join(logs, path), "x" * size)
    code, out = procs.run([args.coordinator, "--config", args.quick, "--run-dir", logs, "--status-address", ""],
                          "logs-only")
    expect(code == 2, f"logs-only: exit {code}, not 2:\n{out}")
    expect(not os.path.exists(os.path.join(logs, "checkpoint.pb")), "logs-only: a checkpoint was written")
    seen["run-dir-logs-without-checkpoint"] = (out, {"RUN_DIR": logs})
    return seen


def run_dir_of_another_user(args, procs, scratch):
    """A run directory the image's user (uid 10001) cannot write, as a root-owned bind mount is: shown, as the page's
    container section shows every message, with the container's path, /var/lib/poet/runs/quick."""
    shown = "/var/lib/poet/runs/quick"
    base = tempfile.mkdtemp(prefix="poet-troubleshooting-uid-")  # not under scratch (0700): the user must reach it
    try:
        run_dir = os.path.join(base, "runs", "quick")
        os.makedirs(run_dir)
        # The user reaches nothing of the checkout's (it may lie under a 0700 home): the binary and its inputs are
        # copied beside the run directory, readable by all.
        inputs = {}
        for name, path, mode in (("coordinator", args.coordinator, 0o755), ("quick", args.quick, 0o644),
                                 ("walker", args.walker, 0o644)):
            inputs[name] = os.path.join(base, os.path.basename(path))
            shutil.copyfile(path, inputs[name])
            os.chmod(inputs[name], mode)
        for path in (base, os.path.join(base, "runs"), run_dir):
            os.chmod(path, 0o755 if os.geteuid() == 0 else 0o555)  # as root, another user; else a read-only directory

        def image_user():
            if os.geteuid() == 0:
                os.setgroups([])
                os.setgid(10001)
                os.setuid(10001)

        code, out = procs.run([inputs["coordinator"], "--config", inputs["quick"], "--run-dir", run_dir,
                               "--start-from", inputs["walker"], "--status-address", ""], "run-dir-another-user",
                              preexec_fn=image_user)
        expect(code == 2, f"run-dir-another-user: exit {code}, not 2:\n{out}")
        return {"run-dir-another-user": (out.replace(run_dir, shown), {})}
    finally:
        for path in (base, os.path.join(base, "runs")):
            if os.path.isdir(path):
                os.chmod(path, 0o755)
        shutil.rmtree(base, ignore_errors=True)


def config_copy_rewritten(args, procs, scratch):
    """A resume (of a finished run: it ends at once) whose config.textproto was removed, or edited: a warning."""
    seen = {}
    for name in ("config-copy-missing", "config-copy-differs"):
        run_dir = finished_run(args, procs, scratch, name)
        copy = os.path.join(run_dir, "config.textproto")
        if name == "config-copy-missing":
            os.remove(copy)
        else:
            with open(copy, "a", encoding="utf-8") as f:
                f.write("seed: 3\n")
        code, out = resume(args, procs, run_dir, name)
        expect(code == 0, f"{name}: exit {code}, not 0:\n{out}")
        seen[name] = (out, {"RUN_DIR": run_dir})
    return seen


def refused_packs(args, procs, scratch):
    """--from-pack of no file, of a file that is not a pack, or into a directory that holds a run: exit 2."""
    absent = os.path.join(scratch, "absent.pack")
    garbage = write(os.path.join(scratch, "garbage.pack"), "not a pack\n")
    held = finished_run(args, procs, scratch, "held")
    cases = {
        "pack-missing": (os.path.join(scratch, "into-1"), absent),
        "pack-not-a-pack": (os.path.join(scratch, "into-2"), garbage),
        "pack-target-not-empty": (held, garbage),
    }
    seen = {}
    for name, (run_dir, pack) in cases.items():
        code, out = resume(args, procs, run_dir, name, ["--from-pack", pack])
        expect(code == 2, f"{name}: exit {code}, not 2:\n{out}")
        seen[name] = (out, {"RUN_DIR": run_dir, "PACK": pack})
    expect(not os.path.exists(os.path.join(scratch, "into-1", "checkpoint.pb")), "pack-missing: a checkpoint appeared")
    return seen


def bad_status_address(args, procs, scratch):
    """--status-address that is not HOST:PORT: a warning, and the run (of 0 iterations) goes on to its end."""
    code, out = procs.run([args.coordinator, "--config", args.quick, "--run-dir", os.path.join(scratch, "S"),
                           "--iterations", "0", "--status-address", "nonsense", "--quiet"], "status-nonsense")
    expect(code == 0, f"status-nonsense: exit {code}, not 0:\n{out}")
    return {"status-address-nonsense": (out, {})}


def few_descriptors(args, procs, scratch):
    """A hard RLIMIT_NOFILE of 1024: the listeners' caps shrink into half of it, with a warning; the run goes on."""
    def limit():
        resource.setrlimit(resource.RLIMIT_NOFILE, (1024, 1024))

    code, out = procs.run([args.coordinator, "--config", args.quick, "--run-dir", os.path.join(scratch, "F"),
                           "--iterations", "0", "--status-address", "127.0.0.1:0", "--quiet"], "few-descriptors",
                          preexec_fn=limit)
    expect(code == 0, f"few-descriptors: exit {code}, not 0:\n{out}")
    return {"few-descriptors": (out, {})}


def stop_requests(args, procs, scratch):
    """poetctl stop --at-boundary on a directory that holds no run (exit 1), and on a run no coordinator runs."""
    nothing = os.path.join(scratch, "no-run")
    os.makedirs(nothing)
    code, refused = procs.run([args.poetctl, "stop", nothing, "--at-boundary"], "stop-no-run")
    expect(code == 1, f"stop-no-run: exit {code}, not 1:\n{refused}")
    idle = os.path.join(scratch, "idle-run")
    os.makedirs(idle)
    open(os.path.join(idle, "config.textproto"), "w").close()
    code, asked = procs.run([args.poetctl, "stop", idle, "--at-boundary"], "stop-idle")
    expect(code == 0, f"stop-idle: exit {code}, not 0:\n{asked}")
    expect(os.path.exists(os.path.join(idle, "stop-at-boundary")), "stop-idle: no request file")
    return {"stop-no-run": (refused, {"RUN_DIR": nothing}), "stop-idle": (asked, {"RUN_DIR": idle})}


def keygen_refusals(args, procs, scratch):
    """poetctl keygen over an existing pair (exit 1), and --authorize for a coordinator pair (exit 2)."""
    keys = os.path.join(scratch, "keys")
    code, out = procs.run([args.poetctl, "keygen", keys, "worker"], "keygen-first")
    expect(code == 0, f"keygen: the first pair: exit {code}:\n{out}")
    code, again = procs.run([args.poetctl, "keygen", keys, "worker"], "keygen-again")
    expect(code == 1, f"keygen-exists: exit {code}, not 1:\n{again}")
    code, authorize = procs.run([args.poetctl, "keygen", keys, "coordinator", "--authorize"], "keygen-authorize")
    expect(code == 2, f"keygen-authorize: exit {code}, not 2:\n{authorize}")
    expect(not os.path.exists(os.path.join(keys, "coordinator.key")), "keygen-authorize: a key was written")
    return {"keygen-exists": (again, {"KEYS": keys}), "keygen-authorize": (authorize, {})}


def job_socket_in_use(args, procs, scratch):
    held, port = taken_port()
    try:
        run_dir = os.path.join(scratch, "P")
        code, out = procs.run([args.coordinator, "--config", args.quick, "--run-dir", run_dir, "--listen",
                               f"tcp://127.0.0.1:{port}", "--status-address", ""], "listen-in-use")
    finally:
        held.close()
    expect(code == 2, f"listen-in-use: exit {code}:\n{out}")
    expect(not os.path.exists(os.path.join(run_dir, "checkpoint.pb")), "listen-in-use: a checkpoint was written")
    return {"listen-in-use": (out, {"PORT": port})}


def owned_run(args, procs, scratch):
    """One coordinator waiting for workers: its status and health ports were taken (it goes on without them);
    a second coordinator on its directory is refused with its pid; a Hello of another build is refused."""
    status, status_port = taken_port()
    health, health_port = taken_port()
    seen = {}
    try:
        run_dir = os.path.join(scratch, "owned")
        owner = procs.start([args.coordinator, "--config", args.quick, "--run-dir", run_dir, "--start-from",
                             args.walker, "--listen", "tcp://127.0.0.1:*", "--status-address",
                             f"127.0.0.1:{status_port}", "--health-address", f"127.0.0.1:{health_port}",
                             "--quiet"], "owner")
        job_port = int(await_line(owner, r"workers connect to tcp://127\.0\.0\.1:(\d+)$", "the job socket")
                       .group(1))
        await_line(owner, r"new run in ", "the owner's new run")
        # the status socket, then the health listener, are tried after the run is opened; each line names its port
        await_line(owner, rf"127\.0\.0\.1:{health_port}\b", "the health listener's line")
        seen["status-in-use"] = (read(owner.log), {"PORT": status_port})
        seen["health-in-use"] = (read(owner.log), {"PORT": health_port})

        code, out = procs.run([args.coordinator, "--config", args.quick, "--run-dir", run_dir, "--start-from",
                               args.walker, "--status-address", ""], "second")
        expect(code == 2, f"second coordinator: exit {code}:\n{out}")
        seen["run-dir-in-use"] = (out, {"RUN_DIR": run_dir, "PID": owner.pid})

        digest = fingerprint_digest(args.coordinator)
        arithmetic, parts = fingerprint_arithmetic(args.coordinator)
        version = wire_protocol_version(args.source)
        other = digest ^ 1
        answer = send_hello(job_port, hello_message(version, other, "other-build", arithmetic, parts))
        expect(b"differs from the coordinator's" in answer, f"the Hello of another build was answered {answer!r}")
        await_line(owner, r"refused worker other-build: ", "the refusal's log line")
        values = {"DIGEST": f"{digest:016x}", "WORKER_DIGEST": f"{other:016x}", "WORKER": "other-build"}
        seen["worker-fingerprint"] = (read(owner.log), values)
        # a machine whose walker part computes other bits: its parts name it
        their_parts = re.sub(r"walker ([0-9a-f]{16})", lambda m: f"walker {int(m.group(1), 16) ^ 1:016x}", parts)
        answer = send_hello(job_port, hello_message(version, digest, "other-machine", arithmetic ^ 1, their_parts))
        expect(b"computes differently" in answer, f"the Hello of another machine was answered {answer!r}")
        await_line(owner, r"refused worker other-machine: ", "the arithmetic refusal's log line")
        values = {"ARITHMETIC": f"{arithmetic:016x}", "WORKER_ARITHMETIC": f"{arithmetic ^ 1:016x}",
                  "WORKER": "other-machine"}
        seen["worker-arithmetic"] = (read(owner.log), values)
        owner.send_signal(signal.SIGTERM)
        code = owner.wait(PROCESS_SECONDS)
        expect(code == 143, f"the owner stopped by SIGTERM exited {code}:\n{read(owner.log)}")
    finally:
        status.close()
        health.close()
    return seen


def fingerprint_arithmetic(binary):
    """The arithmetic digest and its parts ("math H, box2d H, walker H") of the binary's --fingerprint."""
    out = subprocess.run([binary, "--fingerprint"], capture_output=True, text=True, timeout=PROCESS_SECONDS).stdout
    found = re.search(r"^arithmetic: ([0-9a-f]{16}) \((.*)\)$", out, re.MULTILINE)
    expect(found is not None, f"--fingerprint printed no arithmetic line:\n{out}")
    return int(found.group(1), 16), found.group(2)


def fingerprint_digest(binary):
    out = subprocess.run([binary, "--fingerprint"], capture_output=True, text=True, timeout=PROCESS_SECONDS).stdout
    found = re.search(r"^digest: ([0-9a-f]{16})$", out, re.MULTILINE)
    expect(found is not None, f"--fingerprint printed no digest line:\n{out}")
    return int(found.group(1), 16)


class Failure(Exception):
    pass


def expect(condition, message):
    if not condition:
        raise Failure(message)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--page", required=True)
    parser.add_argument("--source", required=True, help="the repository root (for the quick preset and walker)")
    parser.add_argument("--coordinator", required=True)
    parser.add_argument("--poetctl", required=True)
    args = parser.parse_args()
    args.quick = os.path.join(args.source, "deploy", "configs", "quick.textproto")
    args.walker = os.path.join(args.source, "data", "walkers", "flat-walker.json")
    blocks = page_blocks(args.page)

    scratch = tempfile.mkdtemp(prefix="poet-troubleshooting-")
    procs = Processes(scratch)
    failures = []
    seen = {}
    try:
        for case in (refused_configs, bad_command_line, refused_command_lines, refused_first_policies,
                     nothing_to_resume, damaged_checkpoints, checkpoints_of_other_arithmetic, refused_run_dirs, run_dir_of_another_user,
                     config_copy_rewritten, refused_packs,
                     bad_status_address, few_descriptors, keygen_refusals, stop_requests, job_socket_in_use, owned_run):
            try:
                seen.update(case(args, procs, scratch))
            except Exception as e:  # a case that fails is reported; the others still run
                failures.append(f"{case.__name__}: {e}")
    finally:
        procs.kill_all()
        shutil.rmtree(scratch, ignore_errors=True)

    for name, (output, values) in sorted(seen.items()):
        if name not in blocks:
            failures.append(f"the page has no block marked '{name}'; the binary printed\n  " +
                            "\n  ".join(output.strip().split("\n")))
            continue
        missing = missing_lines(blocks[name], output, values)
        if missing:
            failures.append(f"{name}: the page shows\n  " + "\n  ".join(missing) +
                            f"\nbut the binary printed\n  " + "\n  ".join(output.strip().split("\n")))
    for name in sorted(set(blocks) - set(seen)):
        failures.append(f"the page's block '{name}' is marked for checking, but no case provokes it")
    if failures:
        print("\n\n".join(failures), file=sys.stderr)
        return 1
    print(f"{len(seen)} messages of {args.page} match what the binaries print")
    return 0


if __name__ == "__main__":
    sys.exit(main())
