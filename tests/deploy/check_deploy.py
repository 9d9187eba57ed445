#!/usr/bin/python3
"""Checks of the deployment files in deploy/: the Dockerfile, the compose files and the Kubernetes manifests.

No container runs here. Instead:
  compose_config   docker-compose validates the compose files; their structure and variables are checked.
  k8s_manifests    every manifest parses and has the structure that matters (kinds, probes, ports, the Secret).
  references       every binary, flag, config path and port the deployment files (deploy/slurm's scripts too)
                   name exists: flags in the binary's --help, binaries produced by the build and copied by the Dockerfile, configs in the
                   repository and copied, the runtime packages provide every library the binaries load.
  compose_run      the compose topology as plain processes: the coordinator's and the workers' commands exactly
                   as `docker-compose config` gives them, the image's paths mapped to the build tree and the
                   repository, the named volume to a temporary directory, the coordinator's service name to
                   127.0.0.1; a run to its end, then a restart of the same command extending it (the resume path).
  compose_run_curve  the same with docker-compose.curve.yml on top and keys made by poetctl keygen.

Exit codes: 0 passed, 1 failed, 77 skipped (a tool is missing outside CI; under CI=true that is a failure).
"""

import argparse
import contextlib
import ctypes
import fnmatch
import glob
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from check_support import Failed, add_build_arguments, free_port, missing_tool, run_check  # noqa: E402

try:
    import yaml
except ImportError:  # reported by main(): the test fails under CI, skips elsewhere
    yaml = None

SYSTEM_PATHS = ["/dev", "/proc", "/tmp"]  # in every container; the same on this machine
IMAGE_DEFAULT_PATH = ["/usr/local/sbin", "/usr/local/bin", "/usr/sbin", "/usr/bin", "/sbin", "/bin"]
RUN_DEADLINE_S = 150  # the whole compose_run, well inside ctest's TIMEOUT
RUN_TIMEOUT_S = 60  # one run of 2 or 3 iterations of the quick preset (about 5 s on 2 busy cores)


class Checker:
    """Collects failed expectations, so one run reports all of them."""

    def __init__(self):
        self.errors = []
        self.count = 0

    def expect(self, condition, message):
        self.count += 1
        if not condition:
            self.errors.append(message)
        return condition

    def finish(self, what):
        if self.errors:
            raise Failed(f"{what}: {len(self.errors)} of {self.count} checks failed:\n  - " +
                         "\n  - ".join(self.errors))
        print(f"{what}: {self.count} checks passed")


# ---------------------------------------------------------------------------------------------------------
# the Dockerfile


class Dockerfile:
    """The instructions of each stage, and the image's file system as a map to the build tree and the sources."""

    def __init__(self, path):
        self.path = path
        self.stages = []  # [{"name": str, "base": str, "instructions": [(KEYWORD, args)]}]
        text = open(path, encoding="utf-8").read()
        logical, current = [], ""
        for line in text.splitlines():
            stripped = line.strip()
            if not current and (not stripped or stripped.startswith("#")):
                continue
            if current and stripped.startswith("#"):
                continue  # a comment inside a continued instruction
            if stripped.endswith("\\"):
                current += stripped[:-1] + " "
                continue
            logical.append(current + stripped)
            current = ""
        if current:
            logical.append(current)
        for instruction in logical:
            keyword, _, args = instruction.partition(" ")
            keyword = keyword.upper()
            args = args.strip()
            if keyword == "FROM":
                words = args.split()
                name = words[2] if len(words) >= 3 and words[1].upper() == "AS" else str(len(self.stages))
                self.stages.append({"name": name, "base": words[0], "instructions": []})
            elif self.stages:
                self.stages[-1]["instructions"].append((keyword, args))

    def stage(self, name):
        for s in self.stages:
            if s["name"] == name:
                return s
        return None

    @property
    def final(self):
        return self.stages[-1]

    def instructions(self, stage, keyword):
        return [args for k, args in stage["instructions"] if k == keyword]

    @staticmethod
    def copy_parts(args):
        words = shlex.split(args)
        options = [w for w in words if w.startswith("--")]
        paths = [w for w in words if not w.startswith("--")]
        source_stage = None
        for o in options:
            if o.startswith("--from="):
                source_stage = o.split("=", 1)[1]
        return source_stage, paths[:-1], paths[-1]

    def build_tree(self, stage):
        """The build stage's build directory: WORKDIR joined with cmake's -B."""
        workdir = (self.instructions(stage, "WORKDIR") or ["/"])[-1]
        for run in self.instructions(stage, "RUN"):
            m = re.search(r"cmake\s[^&;]*-B\s*(\S+)", run)
            if m:
                return os.path.normpath(os.path.join(workdir, m.group(1)))
        return None

    def image_map(self, source_dir):
        """[(image path, host path, origin)] for everything the final stage copies; origin 'build' or 'context'.
        Build-stage files map to the build tree's path relative to its build directory (resolved by the caller)."""
        entries = []
        final = self.final
        workdir = "/"
        for keyword, args in final["instructions"]:
            if keyword == "WORKDIR":
                workdir = os.path.join(workdir, args)
            if keyword not in ("COPY", "ADD"):
                continue
            source_stage, sources, dest = self.copy_parts(args)
            dest_abs = dest if dest.startswith("/") else os.path.join(workdir, dest)
            for src in sources:
                if source_stage is not None:
                    target = os.path.join(dest_abs, os.path.basename(src)) if dest.endswith("/") else dest_abs
                    entries.append((os.path.normpath(target), src, "build:" + source_stage))
                else:
                    host = os.path.normpath(os.path.join(source_dir, src))
                    if os.path.isdir(host):
                        entries.append((os.path.normpath(dest_abs), host, "context"))
                    else:
                        target = os.path.join(dest_abs, os.path.basename(src)) if dest.endswith("/") else dest_abs
                        entries.append((os.path.normpath(target), host, "context"))
        return entries


def dockerignore_patterns(source_dir):
    path = os.path.join(source_dir, ".dockerignore")
    if not os.path.exists(path):
        return None
    patterns = []
    for line in open(path, encoding="utf-8"):
        line = line.strip()
        if line and not line.startswith("#"):
            patterns.append(line.rstrip("/"))
    return patterns


# ---------------------------------------------------------------------------------------------------------
# docker-compose


def compose_files(source_dir, curve):
    files = [os.path.join(source_dir, "deploy", "docker-compose.yml")]
    if curve:
        files.append(os.path.join(source_dir, "deploy", "docker-compose.curve.yml"))
    return files


def compose_environment(overrides):
    env = {k: v for k, v in os.environ.items() if not k.startswith("POET_") and not k.startswith("COMPOSE_")}
    env.update(overrides)
    return env


def docker_compose(files, overrides, *args):
    tool = shutil.which("docker-compose")
    if tool is None:
        missing_tool("docker-compose is not installed (Debian package docker-compose)")
    command = [tool]
    for f in files:
        command += ["-f", f]
    command += list(args)
    return subprocess.run(command, env=compose_environment(overrides), capture_output=True, text=True, timeout=120)


def compose_config(files, overrides):
    """The compose model after interpolation with `overrides` as the only POET_* variables."""
    result = docker_compose(files, overrides, "config")
    if result.returncode != 0:
        raise Failed(f"docker-compose {' '.join(files)} config failed:\n{result.stderr}")
    return yaml.safe_load(result.stdout)


def command_list(command):
    if command is None:
        return []
    return shlex.split(command) if isinstance(command, str) else [str(c) for c in command]


def healthcheck_argv(healthcheck):
    test = healthcheck.get("test") if healthcheck else None
    if test is None:
        return []
    if isinstance(test, str):
        return ["/bin/sh", "-c", test]
    test = [str(t) for t in test]
    if test[0] == "CMD":
        return test[1:]
    if test[0] == "CMD-SHELL":
        return ["/bin/sh", "-c", " ".join(test[1:])]
    return []


def published_ports(service):
    """[(host ip or '', published, target)] of a service's ports, in either of docker-compose's forms."""
    out = []
    for p in service.get("ports", []) or []:
        if isinstance(p, dict):
            out.append((str(p.get("host_ip", "")), int(p["published"]) if p.get("published") else None,
                        int(p["target"])))
            continue
        text = str(p).split("/")[0]
        parts = text.split(":")
        if len(parts) == 3:
            out.append((parts[0], int(parts[1]), int(parts[2])))
        elif len(parts) == 2:
            out.append(("", int(parts[0]), int(parts[1])))
        else:
            out.append(("", None, int(parts[0])))
    return out


def flag_value(argv, flag):
    for i, a in enumerate(argv):
        if a == flag and i + 1 < len(argv):
            return argv[i + 1]
        if a.startswith(flag + "="):
            return a.split("=", 1)[1]
    return None


def endpoint_port(text):
    m = re.search(r":(\d+)(/|$)", text or "")
    return int(m.group(1)) if m else None


def endpoint_host(text):
    m = re.match(r"(?:[a-z]+://)?([^:/]+):\d+", text or "")
    return m.group(1) if m else None


def volume_mounts(service):
    """[(source, target, named)] of a service's volumes."""
    out = []
    for v in service.get("volumes", []) or []:
        if isinstance(v, dict):
            source, target = v.get("source", ""), v["target"]
            named = v.get("type") == "volume"
        else:
            parts = str(v).split(":")
            source, target = (parts[0], parts[1]) if len(parts) >= 2 else ("", parts[0])
            named = bool(source) and not source.startswith(("/", ".", "~"))
        out.append((source, target, named))
    return out


def duration_seconds(text):
    total = 0.0
    for number, unit in re.findall(r"([\d.]+)(us|ms|s|m|h)", str(text)):
        total += float(number) * {"us": 1e-6, "ms": 1e-3, "s": 1, "m": 60, "h": 3600}[unit]
    return total


# ---------------------------------------------------------------------------------------------------------
# Kubernetes


def load_manifests(k8s_dir):
    documents = {}
    for path in sorted(glob.glob(os.path.join(k8s_dir, "*.yaml")) + glob.glob(os.path.join(k8s_dir, "*.yml"))):
        with open(path, encoding="utf-8") as f:
            documents[os.path.basename(path)] = [d for d in yaml.safe_load_all(f) if d is not None]
    return documents


def find_key(value, key, where=""):
    """Paths at which `key` is a mapping key, anywhere in the document."""
    found = []
    if isinstance(value, dict):
        for k, v in value.items():
            here = f"{where}.{k}" if where else str(k)
            if k == key:
                found.append(here)
            found += find_key(v, key, here)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            found += find_key(v, key, f"{where}[{i}]")
    return found


def containers_of(resource):
    return resource.get("spec", {}).get("template", {}).get("spec", {}).get("containers", []) or []


def pod_spec(resource):
    return resource.get("spec", {}).get("template", {}).get("spec", {}) or {}


def container_port(container, ref):
    """The containerPort a probe's or a Service's port (a name or a number) refers to, or None."""
    for p in container.get("ports", []) or []:
        if ref == p.get("name") or ref == p.get("containerPort"):
            return p.get("containerPort")
    return None


# ---------------------------------------------------------------------------------------------------------
# binaries and their --help


class Binaries:
    def __init__(self, pairs, build_dir):
        self.build_dir = os.path.realpath(build_dir)
        self.paths = {}
        for pair in pairs:
            name, _, path = pair.partition("=")
            self.paths[name] = path
        self._help = {}

    def require_built(self):
        missing = [p for p in self.paths.values() if not os.access(p, os.X_OK)]
        if missing:
            raise Failed("not built (run the build first): " + ", ".join(missing))

    def relative(self, name):
        return os.path.relpath(os.path.realpath(self.paths[name]), self.build_dir)

    def help_text(self, path):
        if path not in self._help:
            if os.path.basename(path) == "curl":
                args = [path, "--help", "all"]
            else:
                args = [path, "--help"]
            result = subprocess.run(args, capture_output=True, text=True, timeout=30)
            self._help[path] = result.stdout + result.stderr
        return self._help[path]


def flags_of(argv):
    """Every option named in argv[1:]: '--name' (without '=value'), and each letter of a short cluster '-fsS'."""
    flags = []
    for a in argv[1:]:
        if a.startswith("--") and len(a) > 2:
            flags.append(a.split("=", 1)[0])
        elif re.fullmatch(r"-[A-Za-z]+", a):
            flags += ["-" + c for c in a[1:]]
    return flags


def flag_in_help(flag, text):
    return re.search(r"(^|[\s,])" + re.escape(flag) + r"($|[\s,=])", text, re.MULTILINE) is not None


# Where deploy/install-deps.sh --build puts the sources it fetches (third_party/box2d/fetch-source.sh), in the
# image's build stage as on this machine.
FETCHED_SOURCES = "/usr/local/src/poet"


class Image:
    """The image's file system as seen from this machine: binaries in the build tree, files in the repository."""

    def __init__(self, source_dir, binaries, check):
        self.source_dir = source_dir
        self.dockerfile = Dockerfile(os.path.join(source_dir, "deploy", "Dockerfile"))
        self.check = check
        self.binaries = binaries
        build = self.dockerfile.stage("build")
        check.expect(build is not None, "Dockerfile: no stage named build")
        self.build_tree = self.dockerfile.build_tree(build) if build else None
        check.expect(self.build_tree is not None, "Dockerfile: the build stage runs no `cmake ... -B DIR`")
        self.map = []  # (image path, host path, origin)
        self.copied_binaries = {}  # name -> image path
        by_relative = {binaries.relative(n): n for n in binaries.paths}
        for image_path, source, origin in self.dockerfile.image_map(source_dir):
            if origin.startswith("build:") and source.startswith(FETCHED_SOURCES + "/"):
                # a file of the sources install-deps.sh --build fetches (Box2D's licence): the same path here
                found = sorted(glob.glob(source))
                if check.expect(found, f"Dockerfile copies {source} from the build stage, and no such file is "
                                       f"here (deploy/install-deps.sh --build fetches {FETCHED_SOURCES})"):
                    self.map.append((image_path, found[-1], "build"))
            elif origin.startswith("build:"):
                rel = os.path.relpath(source, self.build_tree) if self.build_tree else source
                name = by_relative.get(rel)
                if check.expect(name is not None and not rel.startswith(".."),
                                f"Dockerfile copies {source} from the build stage, which is no executable the "
                                f"build produces (build tree {self.build_tree}; executables: "
                                f"{', '.join(sorted(by_relative))})"):
                    self.copied_binaries[name] = image_path
                    self.map.append((image_path, binaries.paths[name], "build"))
            else:
                self.map.append((image_path, source, "context"))
        env_path = None
        for args in self.dockerfile.instructions(self.dockerfile.final, "ENV"):
            m = re.match(r"PATH[= ](\S+)", args)
            if m:
                env_path = m.group(1)
        self.path_dirs = env_path.split(":") if env_path else IMAGE_DEFAULT_PATH

    def host_path(self, image_path):
        """The host file for an image path, through the longest copied prefix; None when nothing copies it."""
        best = None
        for image, host, _ in self.map:
            if image_path == image or image_path.startswith(image.rstrip("/") + "/"):
                if best is None or len(image) > len(best[0]):
                    best = (image, host)
        if best is None:
            return None
        return best[1] + image_path[len(best[0]):]

    def executable(self, name):
        """(image path, host path) of a command run by name, through the image's PATH; None if not copied."""
        if "/" in name:
            host = self.host_path(name)
            return (name, host) if host else None
        for d in self.path_dirs:
            host = self.host_path(os.path.join(d, name))
            if host:
                return os.path.join(d, name), host
        return None

    def apt_installed(self, name):
        """Whether the runtime stage installs a package of this name with apt-get (curl for the healthcheck)."""
        return any(re.search(r"apt-get\s+install\b.*\b" + re.escape(name) + r"\b", run)
                   for run in self.dockerfile.instructions(self.dockerfile.final, "RUN"))


def check_command(check, image, binaries, argv, what, mounts=()):
    """The binary exists in the image, each flag is in its --help, each absolute path exists in the image or a
    mount. `mounts` are image paths provided by volumes (the run directory, the keys)."""
    if not check.expect(bool(argv), f"{what}: no command"):
        return
    found = image.executable(argv[0])
    host = None
    if found:
        host = found[1]
        check.expect(os.access(host, os.X_OK), f"{what}: {argv[0]} maps to {host}, which is not built")
    elif image.apt_installed(argv[0]) and shutil.which(argv[0]):
        host = shutil.which(argv[0])
    check.expect(host is not None, f"{what}: {argv[0]} is neither copied into the image nor installed there")
    if host and os.access(host, os.X_OK):
        text = binaries.help_text(host)
        for flag in flags_of(argv):
            check.expect(flag_in_help(flag, text), f"{what}: {argv[0]} has no option {flag} (not in its --help)")
    for a in argv[1:]:
        value = a.split("=", 1)[1] if a.startswith("--") and "=" in a else a
        if not value.startswith("/"):
            continue
        if any(value == m or value.startswith(m.rstrip("/") + "/") for m in list(mounts) + SYSTEM_PATHS):
            continue
        mapped = image.host_path(value)
        check.expect(mapped is not None and os.path.exists(mapped),
                     f"{what}: {value} is not in the image (nothing the Dockerfile copies provides it"
                     + (f"; it maps to {mapped}, which does not exist)" if mapped else ")"))


# ---------------------------------------------------------------------------------------------------------
# the checks


def check_compose_config(args):
    check = Checker()
    base = compose_files(args.source, curve=False)
    both = compose_files(args.source, curve=True)
    for files in (base, both):
        result = docker_compose(files, {}, "config", "-q")
        check.expect(result.returncode == 0, f"docker-compose {' '.join(os.path.basename(f) for f in files)} "
                                             f"config -q: exit {result.returncode}\n{result.stderr}")
    if check.errors:
        check.finish("compose_config")

    env = {"POET_CONFIG": "es_alone", "POET_ITERATIONS": "7", "POET_JOB_PORT": "6101", "POET_STATUS_PORT": "6102",
           "POET_HEALTH_PORT": "6103", "POET_WORKER_THREADS": "3", "POET_IMAGE": "example/poet:test", "POET_START_FROM": "",
           "POET_WORKERS": "5"}
    for files, label in ((base, "docker-compose.yml"), (both, "docker-compose.yml + docker-compose.curve.yml")):
        config = compose_config(files, env)
        services = config.get("services", {})
        check.expect(set(services) == {"coordinator", "worker"}, f"{label}: services {sorted(services)}")
        coordinator, worker = services.get("coordinator", {}), services.get("worker", {})
        c_argv, w_argv = command_list(coordinator.get("command")), command_list(worker.get("command"))

        # the variables reach the commands, the ports and the healthcheck
        check.expect(flag_value(c_argv, "--config") == "/opt/poet/configs/es_alone.textproto",
                     f"{label}: POET_CONFIG does not choose --config: {c_argv}")
        check.expect(flag_value(c_argv, "--iterations") == "7", f"{label}: POET_ITERATIONS does not set --iterations")
        check.expect(flag_value(c_argv, "--start-from") == "",
                     f"{label}: an empty POET_START_FROM does not empty --start-from (random parameters)")
        listen, status = flag_value(c_argv, "--listen"), flag_value(c_argv, "--status-address")
        check.expect(endpoint_port(listen) == 6101, f"{label}: POET_JOB_PORT does not set --listen ({listen})")
        check.expect(endpoint_port(status) == 6102,
                     f"{label}: POET_STATUS_PORT does not set --status-address ({status})")
        health = flag_value(c_argv, "--health-address")
        check.expect(endpoint_port(health) == 6103,
                     f"{label}: POET_HEALTH_PORT does not set --health-address ({health})")
        check.expect(flag_value(w_argv, "--threads") == "3", f"{label}: POET_WORKER_THREADS does not set --threads")
        # the scale every `up` keeps (Compose v1 and v2 both read `scale:`; v1 reads deploy.replicas only with
        # --compatibility)
        check.expect(str(worker.get("scale")) == "5" and "replicas" not in (worker.get("deploy") or {}),
                     f"{label}: POET_WORKERS does not set the workers' scale: {worker.get('scale')}")
        # a run directory per preset: another POET_CONFIG is a run of its own on the same volume, not a refusal
        check.expect(flag_value(c_argv, "--run-dir") == "/var/lib/poet/runs/es_alone",
                     f"{label}: the run directory is not /var/lib/poet/runs/POET_CONFIG: {c_argv}")
        # a finished run opened again tells the workers started beside it, so that `up` on it ends
        check.expect(int(flag_value(c_argv, "--linger") or 0) > 0,
                     f"{label}: the coordinator does not linger on a finished run for its workers: {c_argv}")
        check.expect(coordinator.get("image") == worker.get("image") == "example/poet:test",
                     f"{label}: the services do not share the image POET_IMAGE names")
        ports = published_ports(coordinator)
        for port, name in ((6101, "job"), (6102, "status")):
            check.expect(any(p[1] == port and p[2] == port for p in ports),
                         f"{label}: the {name} port {port} is not published as {port}:{port}: {ports}")
        check.expect(endpoint_host(flag_value(w_argv, "--connect")) == "coordinator" and
                     endpoint_port(flag_value(w_argv, "--connect")) == 6101,
                     f"{label}: the worker does not connect to coordinator:POET_JOB_PORT: {w_argv}")

        # the coordinator: healthcheck on /healthz at the health port (which the status socket's clients cannot
        # hold up), restart, a grace period, the named volume
        hc = healthcheck_argv(coordinator.get("healthcheck"))
        url = next((a for a in hc if a.startswith("http")), "")
        check.expect(url.endswith("/healthz") and endpoint_port(url) == 6103,
                     f"{label}: the coordinator's healthcheck does not ask /healthz on the health port: {hc}")
        # a crash is resumed; a refusal (exit 2) would fail again at every restart, so the retries are bounded
        check.expect(re.fullmatch(r"on-failure:[1-9]\d*", str(coordinator.get("restart", ""))) is not None,
                     f"{label}: the coordinator's restart policy is not a bounded on-failure:N: "
                     f"{coordinator.get('restart')}")
        check.expect(duration_seconds(coordinator.get("stop_grace_period", "0s")) >= 30,
                     f"{label}: the coordinator's stop_grace_period is under 30 s: "
                     f"{coordinator.get('stop_grace_period')}")
        run_dir = flag_value(c_argv, "--run-dir") or ""
        named = [(s, t) for s, t, n in volume_mounts(coordinator) if n]
        check.expect(any(run_dir == t or run_dir.startswith(t.rstrip("/") + "/") for _, t in named) and
                     all(s in (config.get("volumes") or {}) for s, _ in named),
                     f"{label}: the run directory {run_dir} is not on a named volume: {named}")

        # the worker scales: no container name, no host ports; it waits for a healthy coordinator
        check.expect("container_name" not in worker, f"{label}: the worker has a container_name")
        check.expect(not worker.get("ports"), f"{label}: the worker publishes ports")
        depends = worker.get("depends_on") or {}
        check.expect(isinstance(depends, dict) and
                     (depends.get("coordinator") or {}).get("condition") == "service_healthy",
                     f"{label}: the worker does not depend on a healthy coordinator: {depends}")
        check.expect(worker.get("restart") is not None, f"{label}: the worker has no restart policy")

    # the defaults: the quick preset from the shipped walker, as deploy/run.sh runs it
    defaults = compose_config(base, {})
    c_argv = command_list(defaults["services"]["coordinator"].get("command"))
    check.expect(flag_value(c_argv, "--config") == "/opt/poet/configs/quick.textproto",
                 f"the default config is not the quick preset: {c_argv}")
    run_sh = open(os.path.join(args.source, "deploy", "run.sh"), encoding="utf-8").read()
    m = re.search(r"--start-from\s+\"?\$root/(\S+?)\"?(\s|$)", run_sh)
    if m:
        check.expect(os.path.basename(flag_value(c_argv, "--start-from") or "") == os.path.basename(m.group(1)),
                     f"deploy/run.sh starts from {m.group(1)}, the compose file from "
                     f"{flag_value(c_argv, '--start-from')}")

    # the CURVE file only adds --curve-keys and the keys' mount to each command (in place of the coordinator's
    # --open-port, the plain file's last flag)
    plain, curve = compose_config(base, {}), compose_config(both, {})
    for name in ("coordinator", "worker"):
        a = command_list(plain["services"][name].get("command"))
        if name == "coordinator":
            check.expect(a[-1:] == ["--open-port"], f"docker-compose.yml: the coordinator's command does not end "
                         f"with --open-port, which its job port without CURVE needs:\n    {a}")
            a = a[:-1]
        b = command_list(curve["services"][name].get("command"))
        keys = flag_value(b, "--curve-keys")
        check.expect(keys is not None and b[:len(a)] == a and b[len(a):] == ["--curve-keys", keys],
                     f"docker-compose.curve.yml: the {name}'s command is not docker-compose.yml's plus "
                     f"--curve-keys DIR (without --open-port):\n    {a}\n    {b}")
        targets = [t for _, t, named in volume_mounts(curve["services"][name]) if not named]
        check.expect(keys in targets, f"docker-compose.curve.yml: the {name} does not mount its keys at {keys}")
    check.finish("compose_config")


def check_k8s(args):
    check = Checker()
    k8s_dir = os.path.join(args.source, "deploy", "k8s")
    documents = load_manifests(k8s_dir)
    kustomization = (documents.pop("kustomization.yaml", None) or [{}])[0]
    check.expect(kustomization.get("kind") == "Kustomization", "kustomization.yaml: no kind Kustomization")
    listed = kustomization.get("resources") or []
    check.expect(sorted(listed) == sorted(documents),
                 f"kustomization.yaml lists {sorted(listed)}, the directory holds {sorted(documents)}")
    for name, docs in list(documents.items()) + [("kustomization.yaml", [kustomization])]:
        for d in docs:
            check.expect(not find_key(d, "namespace"), f"{name}: names a namespace at {find_key(d, 'namespace')}")

    resources = [d for docs in documents.values() for d in docs]
    by_kind = {}
    for r in resources:
        by_kind.setdefault(r.get("kind"), []).append(r)
    for kind in ("StatefulSet", "Service", "Deployment", "HorizontalPodAutoscaler"):
        check.expect(len(by_kind.get(kind, [])) == 1, f"expected one {kind}, found {len(by_kind.get(kind, []))}")
    if check.errors:
        check.finish("k8s_manifests")
    sts, svc = by_kind["StatefulSet"][0], by_kind["Service"][0]
    dep, hpa = by_kind["Deployment"][0], by_kind["HorizontalPodAutoscaler"][0]

    # the coordinator
    check.expect(sts["spec"].get("replicas") == 1, f"the StatefulSet's replicas is {sts['spec'].get('replicas')}")
    check.expect(sts["spec"].get("serviceName") == svc["metadata"]["name"],
                 "the StatefulSet's serviceName is not the Service")
    coordinators = containers_of(sts)
    check.expect(len(coordinators) == 1, "the StatefulSet has not one container")
    coordinator = coordinators[0]
    c_argv = command_list(coordinator.get("command")) + command_list(coordinator.get("args"))
    check.expect(c_argv[:1] == ["poet-coordinator"], f"the StatefulSet does not run poet-coordinator: {c_argv}")
    status_port = endpoint_port(flag_value(c_argv, "--status-address"))
    health_port = endpoint_port(flag_value(c_argv, "--health-address"))
    job_port = endpoint_port(flag_value(c_argv, "--listen"))
    check.expect(container_port(coordinator, status_port) == status_port,
                 f"the status port {status_port} (--status-address) is not a container port")
    check.expect(container_port(coordinator, health_port) == health_port,
                 f"the health port {health_port} (--health-address) is not a container port")
    check.expect(container_port(coordinator, job_port) == job_port,
                 f"the job port {job_port} (--listen) is not a container port")
    for probe in ("livenessProbe", "readinessProbe", "startupProbe"):
        p = coordinator.get(probe)
        if probe == "startupProbe" and p is None:
            continue
        get = (p or {}).get("httpGet") or {}
        check.expect(get.get("path") == "/healthz" and container_port(coordinator, get.get("port")) == health_port,
                     f"the coordinator's {probe} is not httpGet /healthz on the health port {health_port}: {p}")
    claims = [t["metadata"]["name"] for t in sts["spec"].get("volumeClaimTemplates", []) or []]
    check.expect(len(claims) == 1, f"the StatefulSet has {len(claims)} volumeClaimTemplates")
    run_dir = flag_value(c_argv, "--run-dir") or ""
    mounts = {m["name"]: m["mountPath"] for m in coordinator.get("volumeMounts", []) or []}
    check.expect(any(n in claims and (run_dir == p or run_dir.startswith(p.rstrip("/") + "/"))
                     for n, p in mounts.items()),
                 f"the run directory {run_dir} is not on the volumeClaimTemplate's volume: {mounts}")

    # the Service
    selector = svc["spec"].get("selector") or {}
    labels = sts["spec"]["template"]["metadata"].get("labels") or {}
    check.expect(selector and all(labels.get(k) == v for k, v in selector.items()),
                 "the Service's selector does not select the coordinator's pods")
    check.expect(sts["spec"]["selector"].get("matchLabels", {}).items() <= labels.items(),
                 "the StatefulSet's selector does not match its pods")
    service_targets = {}
    for p in svc["spec"].get("ports", []):
        target = container_port(coordinator, p.get("targetPort", p.get("port")))
        if check.expect(target is not None, f"the Service's port {p} targets no container port"):
            service_targets[target] = p.get("port")
    check.expect(set(service_targets) == {job_port, status_port},
                 f"the Service's ports reach {sorted(service_targets)}, not the job and status ports "
                 f"{sorted({job_port, status_port})}")

    # the workers
    workers = containers_of(dep)
    check.expect(len(workers) == 1, "the Deployment has not one container")
    worker = workers[0]
    w_argv = command_list(worker.get("command")) + command_list(worker.get("args"))
    check.expect(w_argv[:1] == ["poet-worker"], f"the Deployment does not run poet-worker: {w_argv}")
    connect = flag_value(w_argv, "--connect")
    check.expect(endpoint_host(connect) == svc["metadata"]["name"] and
                 endpoint_port(connect) == service_targets.get(job_port),
                 f"the workers connect to {connect}, not to the Service's job port "
                 f"{svc['metadata']['name']}:{service_targets.get(job_port)}")
    check.expect(worker.get("image") == coordinator.get("image"), "the workers and the coordinator differ in image")
    dep_labels = dep["spec"]["template"]["metadata"].get("labels") or {}
    check.expect(dep["spec"]["selector"].get("matchLabels", {}).items() <= dep_labels.items(),
                 "the Deployment's selector does not match its pods")
    check.expect(not (selector and all(dep_labels.get(k) == v for k, v in selector.items())),
                 "the Service's selector also selects the workers")
    target = hpa["spec"].get("scaleTargetRef") or {}
    check.expect(target.get("kind") == "Deployment" and target.get("name") == dep["metadata"]["name"] and
                 target.get("apiVersion") == "apps/v1", f"the HPA does not scale the workers' Deployment: {target}")
    check.expect(1 <= hpa["spec"].get("minReplicas", 1) <= hpa["spec"].get("maxReplicas", 0),
                 "the HPA's replica bounds are not 1 <= min <= max")
    check.expect(bool(((worker.get("resources") or {}).get("requests") or {}).get("cpu")),
                 "the workers request no CPU (the HPA's utilization needs it)")

    # the CURVE Secret, mounted at --curve-keys with the files each side reads
    def secret_files(resource, container, argv, need, what):
        keys_dir = flag_value(argv, "--curve-keys")
        if not check.expect(keys_dir is not None, f"the {what} has no --curve-keys"):
            return None
        mount = next((m for m in container.get("volumeMounts", []) or [] if m["mountPath"] == keys_dir), None)
        if not check.expect(mount is not None, f"the {what} mounts nothing at --curve-keys {keys_dir}"):
            return None
        volume = next((v for v in pod_spec(resource).get("volumes", []) or [] if v["name"] == mount["name"]), {})
        secret = volume.get("secret")
        if not check.expect(secret is not None, f"the {what}'s {keys_dir} is not a Secret volume"):
            return None
        check.expect(mount.get("readOnly") is True, f"the {what}'s keys are not mounted read-only")
        paths = [i["path"] for i in secret.get("items", []) or []]
        for n in need:
            check.expect(any(fnmatch.fnmatch(p, n) for p in paths),
                         f"the {what}'s Secret volume gives no {n} in {keys_dir}: {paths}")
        mode = secret.get("defaultMode")
        check.expect(mode is None or mode & 0o007 == 0, f"the {what}'s keys are readable by others (mode {mode:o})")
        return secret.get("secretName")

    s1 = secret_files(sts, coordinator, c_argv, ["coordinator.key", "coordinator.key_secret", "authorized/*.key"],
                      "coordinator")
    s2 = secret_files(dep, worker, w_argv, ["worker.key", "worker.key_secret", "coordinator.key"], "worker")
    check.expect(s1 is not None and s1 == s2, f"the coordinator and the workers mount different Secrets: {s1}, {s2}")
    for r, what in ((sts, "coordinator"), (dep, "worker")):
        sc = pod_spec(r).get("securityContext") or {}
        check.expect(sc.get("runAsNonRoot") is True and sc.get("runAsUser", 0) != 0,
                     f"the {what} does not run as a non-root user")

    # kustomize's own rendering, when kubectl is here (it is no dependency of the project)
    kubectl = shutil.which("kubectl")
    if kubectl:
        result = subprocess.run([kubectl, "kustomize", k8s_dir], capture_output=True, text=True, timeout=60)
        if check.expect(result.returncode == 0, f"kubectl kustomize {k8s_dir}: {result.stderr}"):
            rendered = sorted((d["kind"], d["metadata"]["name"]) for d in yaml.safe_load_all(result.stdout) if d)
            check.expect(rendered == sorted((r["kind"], r["metadata"]["name"]) for r in resources),
                         f"kubectl kustomize renders {rendered}")
    else:
        print("k8s_manifests: kubectl not found; kustomize's rendering not checked")
    check.finish("k8s_manifests")


def check_references(args, binaries):
    check = Checker()
    binaries.require_built()
    image = Image(args.source, binaries, check)
    dockerfile = image.dockerfile

    # the Dockerfile: two stages on debian:bookworm, install-deps.sh in both, non-root, the run volume
    build, final = dockerfile.stage("build"), dockerfile.final
    check.expect(all(s["base"] == "debian:bookworm" for s in dockerfile.stages) and len(dockerfile.stages) >= 2,
                 f"Dockerfile: stages {[(s['name'], s['base']) for s in dockerfile.stages]}")
    check.expect(final is not build, "Dockerfile: the final stage is the build stage")
    build_runs = dockerfile.instructions(build, "RUN") if build else []
    check.expect(any(re.search(r"install-deps\.sh\s+--build(\s*$|\s*&&)", r) for r in build_runs),
                 "Dockerfile: the build stage does not run deploy/install-deps.sh --build")
    # install-deps.sh --build fetches Box2D's source with third_party/box2d's script and patch: copied before it runs
    early = []
    for keyword, words in (build["instructions"] if build else []):
        if keyword == "RUN" and re.search(r"install-deps\.sh\s+--build", words):
            break
        if keyword == "COPY":
            early += Dockerfile.copy_parts(words)[1]
    for needed in ("third_party/box2d/fetch-source.sh", "third_party/box2d/project-trigonometry.patch"):
        check.expect(any(p in (".", "./") or needed == p.rstrip("/") or needed.startswith(p.rstrip("/") + "/")
                         for p in early),
                     f"Dockerfile: the build stage runs install-deps.sh --build before copying {needed}")
    check.expect(any("CMAKE_BUILD_TYPE=Release" in r for r in build_runs),
                 "Dockerfile: the build stage does not build Release")
    final_runs = dockerfile.instructions(final, "RUN")
    check.expect(any(re.search(r"install-deps\.sh\s+--runtime", r) for r in final_runs),
                 "Dockerfile: the runtime stage does not run install-deps.sh --runtime")
    users = dockerfile.instructions(final, "USER")
    check.expect(bool(users) and users[-1].split(":")[0] not in ("root", "0"),
                 f"Dockerfile: the runtime stage runs as {users[-1] if users else 'root'}")
    # no VOLUME: each container of the image (every worker, every tool) would get an anonymous volume; the run
    # directories' volumes are mounted on directories the image makes and gives to its user
    check.expect(not dockerfile.instructions(final, "VOLUME"),
                 "Dockerfile: the runtime stage declares a VOLUME, which gives every container an anonymous volume")
    volumes = []
    for run in final_runs:
        for m in re.finditer(r"chown\s+(?:-R\s+)?\S+\s+((?:/\S+\s*)+)", run):
            volumes += m.group(1).split()
    exposed = set()
    for e in dockerfile.instructions(final, "EXPOSE"):
        exposed |= {int(p.split("/")[0]) for p in e.split()}

    # every executable the build makes is copied, and onto PATH
    for name in binaries.paths:
        image_path = image.copied_binaries.get(name)
        check.expect(image_path is not None, f"Dockerfile: the build's executable {name} is not copied")
        if image_path:
            check.expect(os.path.dirname(image_path) in image.path_dirs,
                         f"Dockerfile: {name} is copied to {image_path}, not onto the image's PATH")
    patterns = dockerignore_patterns(args.source)
    if check.expect(patterns is not None, ".dockerignore: missing at the repository root (the build context)"):
        for needed in ("build*", "out", "runs", ".git"):
            check.expect(needed in patterns, f".dockerignore: does not exclude {needed}")
        for image_path, host, origin in image.map:
            if origin == "context":
                top = os.path.relpath(host, args.source).split(os.sep)[0]
                check.expect(not any(fnmatch.fnmatch(top, p) for p in patterns),
                             f".dockerignore excludes {top}, which the Dockerfile copies")

    # install-deps.sh: --runtime provides every library the binaries load; the default has the test tools, and
    # --build is the default without them (and without the test libraries, which the image does not build)
    listing = subprocess.run(["bash", os.path.join(args.source, "deploy", "install-deps.sh"), "--runtime", "--list"],
                             capture_output=True, text=True, timeout=30)
    runtime = set(listing.stdout.split())
    check.expect(listing.returncode == 0 and runtime, f"install-deps.sh --runtime --list: {listing.stderr}")
    full = subprocess.run(["bash", os.path.join(args.source, "deploy", "install-deps.sh"), "--list"],
                          capture_output=True, text=True, timeout=30).stdout.split()
    for p in ("docker-compose", "python3-yaml", "curl", "patchelf"):
        check.expect(p in full, f"install-deps.sh does not install {p} (the deploy tests need it)")
    build_set = subprocess.run(["bash", os.path.join(args.source, "deploy", "install-deps.sh"), "--build", "--list"],
                               capture_output=True, text=True, timeout=30).stdout.split()
    check.expect(bool(build_set) and set(build_set) < set(full),
                 f"install-deps.sh --build is not a part of the default set: {sorted(set(build_set) - set(full))}")
    for p in ("build-essential", "cmake", "dpkg-dev", "libcairo2-dev"):
        check.expect(p in build_set, f"install-deps.sh --build does not install {p}")
    # Box2D is built from Debian's source package (third_party/box2d), never Debian's prebuilt library
    prebuilt = sorted(p for p in set(full) | runtime if p.startswith("libbox2d"))
    check.expect(not prebuilt, f"install-deps.sh installs Debian's prebuilt Box2D: {prebuilt}")
    for p in ("chromium", "docker-compose", "libgtest-dev", "libbenchmark-dev"):
        check.expect(p not in build_set, f"install-deps.sh --build installs {p}, a test tool")
    check.expect(not (runtime & {"build-essential", "cmake"}) and not any(p.endswith("-dev") for p in runtime),
                 f"install-deps.sh --runtime installs build packages: {sorted(runtime)}")
    if shutil.which("dpkg") is None or shutil.which("ldd") is None:
        missing_tool("dpkg and ldd are needed to check the runtime packages")
    owners = {}
    for name, path in binaries.paths.items():
        ldd = subprocess.run(["ldd", path], capture_output=True, text=True, timeout=30).stdout
        needed = subprocess.run(["readelf", "-d", path], capture_output=True, text=True, timeout=30).stdout \
            if shutil.which("readelf") else ""
        direct = set(re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", needed))
        for line in ldd.splitlines():
            m = re.match(r"\s*(\S+) => (/\S+)", line)
            if not m or (direct and m.group(1) not in direct):
                continue
            real = os.path.realpath(m.group(2))
            if real not in owners:
                owner = None
                for candidate in (real, re.sub(r"^/usr(?=/lib)", "", real), m.group(2)):
                    r = subprocess.run(["dpkg", "-S", candidate], capture_output=True, text=True, timeout=30)
                    if r.returncode == 0:
                        owner = r.stdout.split(":")[0].strip()
                        break
                owners[real] = owner
            owner = owners[real]
            check.expect(owner is None or owner in runtime,
                         f"{name} loads {m.group(1)} from package {owner}, which install-deps.sh --runtime lacks")
            check.expect("box2d" not in m.group(1).lower(),
                         f"{name} loads {m.group(1)}: Box2D must be the project's static build (third_party/box2d)")

    # the compose files' and the manifests' commands
    compose_variants = [("docker-compose.yml", compose_files(args.source, False)),
                        ("docker-compose.yml + docker-compose.curve.yml", compose_files(args.source, True))]
    for label, files in compose_variants:
        config = compose_config(files, {})
        for service_name, service in config["services"].items():
            mounts = [t for _, t, _ in volume_mounts(service)]
            argv = command_list(service.get("command"))
            check_command(check, image, binaries, argv, f"{label} {service_name}", mounts)
            if service.get("healthcheck"):
                check_command(check, image, binaries, healthcheck_argv(service["healthcheck"]),
                              f"{label} {service_name} healthcheck", mounts)
            for _, target, named in volume_mounts(service):
                if named:
                    check.expect(target in volumes, f"{label} {service_name}: the named volume at {target} is not a "
                                                    f"directory the image gives its user ({volumes})")
            for _, _, port in published_ports(service):
                check.expect(port in exposed, f"{label} {service_name}: port {port} is not EXPOSEd by the image")
    for name, docs in load_manifests(os.path.join(args.source, "deploy", "k8s")).items():
        for d in docs:
            for c in containers_of(d) if d.get("kind") in ("StatefulSet", "Deployment") else []:
                mounts = [m["mountPath"] for m in c.get("volumeMounts", []) or []]
                argv = command_list(c.get("command")) + command_list(c.get("args"))
                check_command(check, image, binaries, argv, f"k8s/{name} {c['name']}", mounts)
                for p in c.get("ports", []) or []:
                    check.expect(p["containerPort"] in exposed,
                                 f"k8s/{name}: port {p['containerPort']} is not EXPOSEd by the image")
                for m in c.get("volumeMounts", []) or []:
                    if m["mountPath"].startswith("/var/lib/poet"):
                        check.expect(m["mountPath"] in volumes,
                                     f"k8s/{name}: {m['mountPath']} is not a directory the image gives its user "
                                     f"({volumes})")
    check_slurm_scripts(args, binaries, check)
    check.finish("references")


# how deploy/slurm's scripts name the binaries (common.sh's poet_bin)
SLURM_BINARIES = {'"$coordinator_bin"': "poet-coordinator", '"$worker_bin"': "poet-worker",
                  '"$(poet_bin poetctl)"': "poetctl"}


def check_slurm_scripts(args, binaries, check):
    """Every flag deploy/slurm's scripts give a binary is in that binary's --help (poetctl's: its subcommand's),
    and every preset and file they default to exists."""
    slurm = os.path.join(args.source, "deploy", "slurm")
    for name in sorted(os.listdir(slurm)):
        text = open(os.path.join(slurm, name)).read().replace("\\\n", " ")
        for line in text.splitlines():
            for ref, binary in SLURM_BINARIES.items():
                if ref not in line or line.lstrip().startswith("#"):
                    continue
                words = line.split(ref, 1)[1].split()
                path = binaries.paths[binary]
                help_args = [path, words[0], "--help"] if binary == "poetctl" else [path, "--help"]
                text_of_help = subprocess.run(help_args, capture_output=True, text=True, timeout=30)
                help_text = text_of_help.stdout + text_of_help.stderr
                for flag in flags_of([binary] + words):
                    check.expect(flag_in_help(flag, help_text),
                                 f"deploy/slurm/{name}: {binary} has no {flag} ({' '.join(help_args[1:])})")
    settings = open(os.path.join(slurm, "settings.sh")).read()
    preset = re.search(r"POET_PRESET=\$\{POET_PRESET:-(\w+)\}", settings)
    check.expect(preset and os.path.exists(os.path.join(args.source, "deploy", "configs", preset.group(1) +
                                                        ".textproto")), "deploy/slurm/settings.sh: its preset")
    walker = re.search(r"POET_START_FROM=\$\{POET_START_FROM-([^}]+)\}", settings)
    check.expect(walker and os.path.exists(os.path.join(args.source, "data", walker.group(1))),
                 "deploy/slurm/settings.sh: its first policy")


# ---------------------------------------------------------------------------------------------------------
# the compose topology as processes


def _die_with_parent():
    # the children end with this process even if it is killed outright (a ctest timeout)
    libc = ctypes.CDLL("libc.so.6", use_errno=True)
    libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


class Processes:
    """Children in their own process groups, each group killed at the end whatever happened."""

    def __init__(self, root):
        self.root = root
        self.children = {}

    def start(self, name, argv, env):
        out = open(os.path.join(self.root, name + ".out"), "w")
        err = open(os.path.join(self.root, name + ".err"), "w")
        print(f"  start {name}: {shlex.join(argv)}")
        p = subprocess.Popen(argv, stdout=out, stderr=err, env=env, start_new_session=True,
                             preexec_fn=_die_with_parent)
        out.close()
        err.close()
        self.children[name] = p
        return p

    def log(self, name):
        path = os.path.join(self.root, name + ".err")
        return open(path, encoding="utf-8", errors="replace").read() if os.path.exists(path) else ""

    def wait(self, name, deadline):
        p = self.children[name]
        try:
            return p.wait(timeout=max(0.1, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            return None

    def kill_all(self):
        for p in self.children.values():
            if p.poll() is None:
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(p.pid, signal.SIGKILL)
                with contextlib.suppress(Exception):
                    p.wait(timeout=10)


class Mapping:
    """Rewrites a container's argv for this machine: image paths → build tree and repository, mounts → host
    directories, the compose service's host name and the container's any-address → 127.0.0.1."""

    def __init__(self, image, mounts, service_hosts):
        self.image = image
        self.mounts = sorted(mounts.items(), key=lambda kv: -len(kv[0]))
        self.service_hosts = service_hosts

    def path(self, value):
        if any(value == s or value.startswith(s + "/") for s in SYSTEM_PATHS):
            return value
        for target, host in self.mounts:
            if value == target or value.startswith(target.rstrip("/") + "/"):
                return host + value[len(target):]
        mapped = self.image.host_path(value)
        if mapped is None:
            raise Failed(f"{value}: no file of the image or mount provides it")
        return mapped

    def argv(self, argv):
        found = self.image.executable(argv[0])
        if found:
            head = found[1]
        elif self.image.apt_installed(argv[0]) and shutil.which(argv[0]):
            head = shutil.which(argv[0])
        else:
            raise Failed(f"{argv[0]}: neither copied into the image nor installed there")
        out = [head]
        for a in argv[1:]:
            prefix, value = "", a
            if a.startswith("--") and "=" in a:
                prefix, value = a.split("=", 1)
                prefix += "="
            if value.startswith("/"):
                value = self.path(value)
            value = re.sub(r"^(tcp://)?0\.0\.0\.0:", r"\g<1>127.0.0.1:", value)
            for host in self.service_hosts:
                value = re.sub(r"^(tcp://|https?://)?" + re.escape(host) + r":", r"\g<1>127.0.0.1:", value)
            out.append(prefix + value)
        return out


def compose_run(args, binaries, curve):
    check = Checker()
    binaries.require_built()
    deadline = time.monotonic() + RUN_DEADLINE_S
    root = tempfile.mkdtemp(prefix="poet_deploy_run_")
    processes = Processes(root)
    try:
        image = Image(args.source, binaries, check)
        if check.errors:
            check.finish("compose_run")
        env = {"POET_CONFIG": "quick", "POET_ITERATIONS": "2", "POET_JOB_PORT": str(free_port()),
               "POET_STATUS_PORT": str(free_port()), "POET_HEALTH_PORT": str(free_port()), "POET_WORKER_THREADS": "1"}
        if curve:
            keys = os.path.join(root, "keys")
            poetctl = image.executable("poetctl")
            if not poetctl:
                raise Failed("poetctl is not in the image")
            for who in (["coordinator"], ["worker", "--authorize"]):
                r = subprocess.run([poetctl[1], "keygen", keys] + who, capture_output=True, text=True, timeout=30)
                if r.returncode != 0:
                    raise Failed(f"poetctl keygen {keys} {' '.join(who)}: {r.stderr}")
            env["POET_KEYS"] = keys
        files = compose_files(args.source, curve)

        def topology(variables):
            config = compose_config(files, variables)
            services = config["services"]
            mounts = {}
            for service in services.values():
                for source, target, named in volume_mounts(service):
                    if named:  # a named volume: a directory of its own, empty at first, as Docker makes it
                        host = os.path.join(root, "volumes", source)
                        os.makedirs(host, exist_ok=True)
                    else:
                        host = source
                    mounts[target] = host
            mapping = Mapping(image, mounts, list(services))
            return services, mapping

        def run_once(label, variables, iterations):
            services, mapping = topology(variables)
            coordinator, worker = services["coordinator"], services["worker"]
            c_env = compose_environment({})
            c_env.update({k: str(v) for k, v in (coordinator.get("environment") or {}).items()})
            c_argv = mapping.argv(command_list(coordinator["command"]))
            health = mapping.argv(healthcheck_argv(coordinator["healthcheck"]))
            w_argv = mapping.argv(command_list(worker["command"]))
            run_dir = mapping.path(flag_value(command_list(coordinator["command"]), "--run-dir"))

            name = f"coordinator-{label}"
            c = processes.start(name, c_argv, c_env)
            healthy = False
            health_deadline = min(deadline, time.monotonic() + 30)
            while time.monotonic() < health_deadline and c.poll() is None:
                r = subprocess.run(health, capture_output=True, text=True, timeout=10)
                if r.returncode == 0:
                    healthy = True
                    break
                time.sleep(0.2)
            if not check.expect(healthy, f"{label}: the coordinator's healthcheck {shlex.join(health)} never "
                                         f"succeeded (coordinator exit {c.poll()}):\n{processes.log(name)}"):
                return
            print(f"  {label}: the healthcheck succeeded: {shlex.join(health)}")
            worker_names = []
            for i in (1, 2):
                w_env = compose_environment({})
                w_env.update({k: str(v) for k, v in (worker.get("environment") or {}).items()})
                worker_names.append(f"worker{i}-{label}")
                processes.start(worker_names[-1], w_argv, w_env)
            run_deadline = min(deadline, time.monotonic() + RUN_TIMEOUT_S)
            workers = [processes.children[w] for w in worker_names]
            # until the coordinator ends; a run whose workers all failed cannot finish
            while c.poll() is None and time.monotonic() < run_deadline and \
                    not all(w.poll() not in (None, 0) for w in workers):
                time.sleep(0.2)
            code = processes.wait(name, min(run_deadline, time.monotonic() + 2))
            log = processes.log(name)
            check.expect(code == 0, f"{label}: the coordinator exited {code}, not 0:\n{log}")
            check.expect(f"run finished at iteration {iterations}" in log,
                         f"{label}: the coordinator's log does not say the run finished at iteration "
                         f"{iterations}:\n{log}")
            check.expect(os.path.isfile(os.path.join(run_dir, "checkpoint.pb")),
                         f"{label}: no checkpoint in the run directory {run_dir}")
            for w in worker_names:
                code = processes.wait(w, min(deadline, time.monotonic() + 30))
                check.expect(code is not None, f"{label}: {w} did not exit after the run finished")
                check.expect(code in (0, None), f"{label}: {w} exited {code}:\n{processes.log(w)}")
                check.expect(f"connecting to tcp://127.0.0.1:{variables['POET_JOB_PORT']}" in processes.log(w),
                             f"{label}: {w} did not connect to the coordinator's job port:\n{processes.log(w)}")
            start_from = flag_value(command_list(coordinator["command"]), "--start-from")
            if start_from and label == "new":
                check.expect("the first pair starts from " + mapping.path(start_from) in log,
                             f"{label}: the coordinator did not start from {start_from}:\n{log}")
            joined = len(re.findall(r"joined: \d+ connected", log))
            check.expect(joined >= 2, f"{label}: {joined} workers joined the coordinator, not 2")
            return log

        start = time.monotonic()
        run_once("new", env, 2)
        print(f"  new run: {time.monotonic() - start:.1f} s")
        if not curve and not check.errors:
            # the same command again, with a higher limit: what a restart of the container (or `up` after a
            # change of POET_ITERATIONS) does to a volume that holds the run
            start = time.monotonic()
            log = run_once("restart", dict(env, POET_ITERATIONS="3"), 3)
            check.expect(log is not None and "resumed" in log and "at iteration 2 of 3" in log,
                         f"restart: the coordinator did not resume the run at iteration 2:\n{log}")
            print(f"  restart: {time.monotonic() - start:.1f} s")
        if curve and not check.errors:
            log = processes.log("coordinator-new")
            check.expect("CURVE" in log or "curve" in log,
                         f"curve: the coordinator's log does not mention CURVE:\n{log}")
        check.finish("compose_run" + ("_curve" if curve else ""))
    finally:
        processes.kill_all()
        shutil.rmtree(root, ignore_errors=True)


# ---------------------------------------------------------------------------------------------------------


def run_selected_check(args):
    binaries = Binaries(args.binary, args.build_dir)
    if args.check == "compose_config":
        check_compose_config(args)
    elif args.check == "k8s_manifests":
        check_k8s(args)
    elif args.check == "references":
        check_references(args, binaries)
    else:
        compose_run(args, binaries, curve=args.check == "compose_run_curve")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("check", choices=["compose_config", "k8s_manifests", "references", "compose_run",
                                          "compose_run_curve"])
    add_build_arguments(parser)
    args = parser.parse_args()
    args.source = os.path.realpath(args.source)

    def check():
        if yaml is None:
            missing_tool(f"PyYAML is not importable by {sys.executable} (Debian package python3-yaml)")
        try:
            run_selected_check(args)
        except FileNotFoundError as e:  # a program the checks run is not installed
            missing_tool(f"{e.filename or e}: not found")

    return run_check(args.check, check)


if __name__ == "__main__":
    sys.exit(main())
