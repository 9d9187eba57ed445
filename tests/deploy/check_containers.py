#!/usr/bin/python3
"""The image and the compose files on a real container runtime: deploy/Dockerfile built, deploy/docker-compose.yml
(and docker-compose.curve.yml) driven with whichever Compose is installed (`docker compose`, else Debian's
`docker-compose`).

  image     builds the image, tagged poet-test:DIGEST, DIGEST a hash of the build context (every file of the
            repository that .dockerignore lets through: path, mode and bytes). An image of that tag is the same tree
            built, so it is used as it is. The tag is recorded in the build tree for the checks below (the sources
            may change while they run) and for `cleanup`.
  compose   a healthy coordinator; 2 workers, then 4 (POET_WORKERS); `stop` and `up` resuming at the checkpoint with
            4 workers still; the run to its end; `up` on the finished run exiting 0, its workers told and gone; no
            anonymous volume; the final checkpoint byte for byte the same config's run on threads.
  config    a run of another preset (POET_CONFIG) on the same volume: a run of its own, in its own directory; a
            refusal (a run directory of another config) stops after the bounded restarts, with its message.
  curve     docker-compose.curve.yml with keys made in a container as docs/deploying.md makes them (keys/ not there
            yet): the workers join over CURVE, and the checkpoint is the threads' one.
  cleanup   removes the image tag `image` made and the build's dangling images (POET_TEST_KEEP_IMAGE=1 keeps them,
            for the next run to use).

Each check uses a compose project of its own (poet-ct-PID-CHECK), free host ports, and removes its containers,
volumes and networks whatever happens. They run only where POET_TEST_CONTAINERS=1 and a Docker daemon answers;
elsewhere they skip (exit 77) and say why. Exit codes: 0 passed, 1 failed, 77 skipped.
"""

import argparse
import contextlib
import fnmatch
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from check_support import Failed, Skipped, free_port, run_check  # noqa: E402

IMAGE_REPOSITORY = "poet-test"
BUILD_TIMEOUT_S = 1800  # about 10 min on 2 cores from nothing; the package layer is usually cached
UP_TIMEOUT_S = 180  # `up` waits for the coordinator's healthcheck (interval 5 s)
RUN_TIMEOUT_S = 300  # a few iterations of the quick preset on 2 busy cores
LINGER_S = 30  # the compose file's --linger


# ---------------------------------------------------------------------------------------------------------
# the runtime


def run(argv, timeout=120, check=True, env=None, text=True, cwd=None):
    result = subprocess.run(argv, capture_output=True, timeout=timeout, env=env, text=text, cwd=cwd)
    if check and result.returncode != 0:
        err = result.stderr if text else result.stderr.decode(errors="replace")
        raise Failed(f"{' '.join(argv)}: exit {result.returncode}\n{err}")
    return result


def require_runtime():
    if os.environ.get("POET_TEST_CONTAINERS") != "1":
        raise Skipped("container tests run only with POET_TEST_CONTAINERS=1 (they build the image and start "
                      "containers; docs/contributing.md)")
    if shutil.which("docker") is None:
        raise Skipped("no docker client on PATH")
    info = subprocess.run(["docker", "info", "--format", "{{.ServerVersion}}"], capture_output=True, text=True,
                          timeout=60)
    if info.returncode != 0:
        raise Skipped(f"no Docker daemon answers: {info.stderr.strip()[:200]}")
    return info.stdout.strip()


def compose_command():
    """`docker compose` (Compose v2) where the plugin is installed, else `docker-compose` (v1, Debian's)."""
    if subprocess.run(["docker", "compose", "version"], capture_output=True, timeout=30).returncode == 0:
        return ["docker", "compose"]
    if shutil.which("docker-compose"):
        return ["docker-compose"]
    raise Skipped("neither `docker compose` nor `docker-compose` is installed")


def context_digest(source):
    """A hash of the build context: each file .dockerignore lets through, by path, mode and content."""
    patterns = []
    for line in open(os.path.join(source, ".dockerignore"), encoding="utf-8"):
        line = line.strip()
        if line and not line.startswith("#"):
            patterns.append(line.strip("/"))

    def ignored(rel):
        parts = rel.split("/")
        return any(fnmatch.fnmatch("/".join(parts[:i]), p) for p in patterns for i in range(1, len(parts) + 1))

    h = hashlib.sha256()
    for root, dirs, files in os.walk(source):
        rel_root = os.path.relpath(root, source)
        dirs[:] = sorted(d for d in dirs if not ignored(os.path.normpath(os.path.join(rel_root, d))))
        for f in sorted(files):
            rel = os.path.normpath(os.path.join(rel_root, f))
            path = os.path.join(root, f)
            if ignored(rel) or not os.path.isfile(path):
                continue
            h.update(f"{rel}\0{os.stat(path).st_mode & 0o777:o}\0".encode())
            with open(path, "rb") as stream:
                h.update(hashlib.sha256(stream.read()).digest())
    return h.hexdigest()[:16]


def image_tag(source):
    return f"{IMAGE_REPOSITORY}:{context_digest(source)}"


def image_exists(tag):
    return subprocess.run(["docker", "image", "inspect", tag], capture_output=True, timeout=60).returncode == 0


def dangling_images():
    return set(run(["docker", "images", "-q", "--filter", "dangling=true"]).stdout.split())


def state_path(args):
    return os.path.join(args.build_dir, "tests", "container_image.json")


# ---------------------------------------------------------------------------------------------------------
# a compose project


class Project:
    """One compose project on deploy/'s files: its own name, variables and ports; `remove` deletes whatever it made."""

    def __init__(self, args, tag, check_name, curve=False):
        self.source = args.source
        self.compose = compose_command()
        self.name = f"poet-ct-{os.getpid()}-{check_name}"
        self.files = [os.path.join(args.source, "deploy", "docker-compose.yml")]
        if curve:
            self.files.append(os.path.join(args.source, "deploy", "docker-compose.curve.yml"))
        self.variables = {"POET_IMAGE": tag, "POET_JOB_PORT": str(free_port()), "POET_STATUS_PORT": str(free_port()),
                          "POET_HEALTH_PORT": "8581", "POET_WORKER_THREADS": "1"}
        self.tag = tag

    def env(self, overrides):
        env = {k: v for k, v in os.environ.items() if not k.startswith(("POET_", "COMPOSE_"))}
        env.update(self.variables)
        env.update(overrides)
        return env

    def __call__(self, *args, overrides=None, timeout=UP_TIMEOUT_S, check=True):
        argv = list(self.compose) + ["-p", self.name]
        for f in self.files:
            argv += ["-f", f]
        argv += list(args)
        result = subprocess.run(argv, capture_output=True, text=True, timeout=timeout, env=self.env(overrides or {}))
        print(f"  $ {' '.join(self.compose)} {' '.join(args)}  -> exit {result.returncode}")
        if check and result.returncode != 0:
            raise Failed(f"{' '.join(argv)}: exit {result.returncode}\n{result.stdout}\n{result.stderr}")
        return result

    def containers(self, service, all_states=True):
        argv = ["docker", "ps", "-q", "--filter", f"label=com.docker.compose.project={self.name}",
                "--filter", f"label=com.docker.compose.service={service}"]
        if all_states:
            argv.insert(2, "-a")
        return run(argv).stdout.split()

    def inspect(self, container):
        return json.loads(run(["docker", "inspect", container]).stdout)[0]

    def logs(self, service):
        out = []
        for c in self.containers(service):
            r = run(["docker", "logs", c], check=False)
            out.append(r.stdout + r.stderr)
        return "\n".join(out)

    def volume(self):
        return f"{self.name.replace('.', '')}_poet-run"

    def read_volume_file(self, path):
        """A file of the run volume, read through a throwaway container of the image."""
        r = run(["docker", "run", "--rm", "-v", f"{self.volume()}:/v:ro", "--entrypoint", "cat", self.tag,
                 f"/v/{path}"], text=False)
        return r.stdout

    def remove(self):
        with contextlib.suppress(Exception):
            self("down", "-v", "--remove-orphans", "--timeout", "5", timeout=180, check=False)
        label = f"label=com.docker.compose.project={self.name}"
        for kind, listing in (("container", ["docker", "ps", "-aq", "--filter", label]),
                              ("volume", ["docker", "volume", "ls", "-q", "--filter", label]),
                              ("network", ["docker", "network", "ls", "-q", "--filter", label])):
            with contextlib.suppress(Exception):
                leftovers = run(listing, check=False).stdout.split()
                if leftovers:
                    run(["docker", kind, "rm", "-f"] + leftovers if kind != "network" else
                        ["docker", "network", "rm"] + leftovers, check=False)


def wait_until(what, predicate, timeout):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(1)
    raise Failed(f"timed out after {timeout} s waiting for {what}")


def status(project):
    """The coordinator's /status on its published status port, or None while it does not answer."""
    url = f"http://127.0.0.1:{project.variables['POET_STATUS_PORT']}/status"
    try:
        with urllib.request.urlopen(url, timeout=5) as response:
            return json.loads(response.read())
    except Exception:
        return None


def field(doc, name):
    camel = re.sub(r"_([a-z])", lambda m: m.group(1).upper(), name)
    return doc.get(name, doc.get(camel, 0))


def running_count(project, service):
    return len(project.containers(service, all_states=False))


def coordinator_exited(project):
    """The coordinator container's exit code once it has stopped (and is not being restarted), else None."""
    ids = project.containers("coordinator")
    if not ids:
        return None
    state = project.inspect(ids[0])["State"]
    return None if state["Running"] or state["Restarting"] else state["ExitCode"]


def threads_checkpoint(args, root, config, iterations):
    """The same config's run on this machine's build, on threads: its checkpoint's bytes."""
    run_dir = os.path.join(root, f"threads-{config}-{iterations}")
    run([args.coordinator, "--config", os.path.join(args.source, "deploy", "configs", config + ".textproto"),
         "--run-dir", run_dir, "--iterations", str(iterations), "--start-from",
         os.path.join(args.source, "data", "walkers", "flat-walker.json"), "--threads", "2", "--status-address", "",
         "--quiet"], timeout=RUN_TIMEOUT_S)
    with open(os.path.join(run_dir, "checkpoint.pb"), "rb") as f:
        return f.read()


def same_checkpoint(args, project, root, config, iterations):
    containers = project.read_volume_file(f"runs/{config}/checkpoint.pb")
    threads = threads_checkpoint(args, root, config, iterations)
    if containers != threads:
        fingerprints = [run(["docker", "run", "--rm", project.tag, "poet-coordinator", "--fingerprint"],
                            check=False).stdout.strip(),
                        run([args.coordinator, "--fingerprint"], check=False).stdout.strip()]
        raise Failed(f"the containers' checkpoint of {config} at iteration {iterations} ({len(containers)} bytes, "
                     f"sha256 {hashlib.sha256(containers).hexdigest()[:16]}) is not the threads' "
                     f"({len(threads)} bytes, sha256 {hashlib.sha256(threads).hexdigest()[:16]}); fingerprints: "
                     f"image {fingerprints[0]!r}, build {fingerprints[1]!r}")
    print(f"  checkpoint of {config} at iteration {iterations}: {len(threads)} bytes, the same as on threads "
          f"(sha256 {hashlib.sha256(threads).hexdigest()[:16]})")


def expect(condition, message):
    if not condition:
        raise Failed(message)


# ---------------------------------------------------------------------------------------------------------
# the checks


def project_version(source):
    """CMake's PROJECT_VERSION, the version the image must be labelled with (the Dockerfile's default repeats it)."""
    with open(os.path.join(source, "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"^project\(poet VERSION ([0-9.]+)", f.read(), re.M).group(1)


def check_image(args):
    tag = image_tag(args.source)
    if image_exists(tag):
        print(f"  {tag} exists: the image of this tree, used as it is")
        created = False
        with open(state_path(args), "w", encoding="utf-8") as f:
            json.dump({"tag": tag, "created": False, "dangling": []}, f)
    else:
        before = dangling_images()
        started = time.monotonic()
        print(f"  building {tag} (docker build --network host: the build installs packages with apt-get)")
        build = subprocess.run(["docker", "build", "--network", "host", "-f",
                                os.path.join(args.source, "deploy", "Dockerfile"), "-t", tag, args.source],
                               capture_output=True, text=True, timeout=BUILD_TIMEOUT_S)
        new_dangling = sorted(dangling_images() - before)
        created = build.returncode == 0
        with open(state_path(args), "w", encoding="utf-8") as f:
            json.dump({"tag": tag, "created": created, "dangling": new_dangling}, f)
        if build.returncode != 0:
            raise Failed(f"docker build: exit {build.returncode}\n{build.stdout[-4000:]}\n{build.stderr[-4000:]}")
        print(f"  built in {time.monotonic() - started:.0f} s")
    label = run(["docker", "image", "inspect", "--format",
                 '{{index .Config.Labels "org.opencontainers.image.version"}}', tag]).stdout.strip()
    expect(label == project_version(args.source),
           f"the image's org.opencontainers.image.version is {label!r}, CMakeLists.txt's version "
           f"{project_version(args.source)}")
    # the licences travel with the binaries: the project's, and Box2D's, which they contain
    licences = run(["docker", "run", "--rm", "--entrypoint", "ls", tag, "/usr/share/doc/poet",
                    "/usr/share/doc/poet/box2d"], check=False)
    expect(licences.returncode == 0 and all(name in licences.stdout.split() for name in ("LICENSE", "NOTICE")),
           f"the image lacks /usr/share/doc/poet/LICENSE, NOTICE or box2d/LICENSE:\n{licences.stdout}{licences.stderr}")
    size = int(run(["docker", "image", "inspect", "--format", "{{.Size}}", tag]).stdout)
    volumes = run(["docker", "image", "inspect", "--format", "{{json .Config.Volumes}}", tag]).stdout.strip()
    expect(volumes in ("null", "{}"), f"the image declares volumes {volumes}: every container would get one")
    print(f"  {tag}: {size / 1e6:.0f} MB, no VOLUME; {'built here' if created else 'reused'}")


def check_cleanup(args):
    path = state_path(args)
    if not os.path.exists(path):
        print("  the image check recorded no image: nothing to remove")
        return
    state = json.load(open(path, encoding="utf-8"))
    if os.environ.get("POET_TEST_KEEP_IMAGE") == "1":
        print(f"  POET_TEST_KEEP_IMAGE=1: {state['tag']} kept")
    else:
        if state.get("created"):
            run(["docker", "rmi", state["tag"]], check=False)
        leftovers = [i for i in state.get("dangling", []) if i in dangling_images()]
        if leftovers:
            run(["docker", "rmi"] + leftovers, check=False)
        print(f"  removed {state['tag'] if state.get('created') else 'no tag'} and {len(leftovers)} dangling images")
    os.remove(path)


def require_image(args):
    """The tag container_image built or found in this run: the tree may change while the checks run."""
    path = state_path(args)
    tag = json.load(open(path, encoding="utf-8"))["tag"] if os.path.exists(path) else None
    if tag is None or not image_exists(tag):
        raise Failed("no image: container_image builds it first (ctest -R container runs it as a fixture)")
    return tag


@contextlib.contextmanager
def compose_project(args, check_name, curve=False):
    """A Project on this tree's image; the coordinator's log printed when the check fails, and whatever the project
    made removed however it ends."""
    project = Project(args, require_image(args), check_name, curve)
    try:
        yield project
    except Failed:
        print(project.logs("coordinator")[-6000:])
        raise
    finally:
        project.remove()


def check_compose(args, root):
    volumes_before = set(run(["docker", "volume", "ls", "-q"]).stdout.split())
    iterations = 6
    env = {"POET_CONFIG": "quick", "POET_ITERATIONS": str(iterations)}
    with compose_project(args, "compose") as project:
        # a healthy coordinator and 2 workers
        started = time.monotonic()
        project("up", "-d", "--no-build", overrides=dict(env, POET_WORKERS="2"))
        coordinator = project.containers("coordinator")[0]
        health = project.inspect(coordinator)["State"].get("Health", {}).get("Status")
        expect(health == "healthy", f"`up` returned with the coordinator {health}, not healthy")
        expect(running_count(project, "worker") == 2, f"{running_count(project, 'worker')} workers run, not 2")
        wait_until("2 workers connected", lambda: (status(project) or {}).get("workers") == 2, 60)
        print(f"  healthy coordinator, 2 workers connected: {time.monotonic() - started:.0f} s after `up`")

        # 4 workers: POET_WORKERS
        project("up", "-d", "--no-build", overrides=dict(env, POET_WORKERS="4"))
        wait_until("4 workers connected", lambda: (status(project) or {}).get("workers") == 4, 60)
        print("  scaled to 4 workers")

        # stop once a checkpoint is written, and `up` again: resumed there, still 4 workers
        saved = wait_until("a checkpoint", lambda: field(status(project) or {}, "last_checkpoint_iteration") >= 2
                           and field(status(project) or {}, "last_checkpoint_iteration"), RUN_TIMEOUT_S)
        project("stop", timeout=300)
        expect(coordinator_exited(project) == 143, f"`stop` ended the coordinator with {coordinator_exited(project)}")
        log = project.logs("coordinator")
        stopped_at = [int(m) for m in re.findall(r"(?:its checkpoint|interrupted) at iteration (\d+)", log)]
        expect(stopped_at and stopped_at[-1] >= saved, f"the stopped coordinator's log names no checkpoint:\n{log}")
        project("up", "-d", "--no-build", overrides=dict(env, POET_WORKERS="4"))
        expect(running_count(project, "worker") == 4, f"`up` after the stop runs {running_count(project, 'worker')} "
                                                      f"workers, not 4")
        log = project.logs("coordinator")
        expect(f"resumed /var/lib/poet/runs/quick at iteration {stopped_at[-1]} of {iterations}" in log,
               f"`up` did not resume at the checkpoint (iteration {stopped_at[-1]}):\n{log}")
        print(f"  stopped with the checkpoint at iteration {stopped_at[-1]}; `up` resumed there with 4 workers")

        # the run to its end: the coordinator exits 0, the workers are told
        wait_until("the end of the run", lambda: coordinator_exited(project) is not None, RUN_TIMEOUT_S)
        expect(coordinator_exited(project) == 0, f"the coordinator exited {coordinator_exited(project)}")
        wait_until("the workers' exits", lambda: running_count(project, "worker") == 0, 60)
        codes = [project.inspect(c)["State"]["ExitCode"] for c in project.containers("worker")]
        expect(codes == [0] * 4, f"the workers exited {codes}, not 0")
        print(f"  the run finished at iteration {iterations}; the 4 workers exited 0")

        # `up` on the finished run: exit 0, the run says it is finished, the workers are told and leave
        finished_up = time.monotonic()
        result = project("up", "-d", "--no-build", overrides=dict(env, POET_WORKERS="4"), check=False)
        expect(result.returncode == 0, f"`up` on a finished run: exit {result.returncode}\n{result.stderr}")
        wait_until("the finished run's coordinator to exit", lambda: coordinator_exited(project) is not None,
                   LINGER_S + 60)
        expect(coordinator_exited(project) == 0, f"the finished run's coordinator exited {coordinator_exited(project)}")
        wait_until("the workers to leave the finished run", lambda: running_count(project, "worker") == 0, 30)
        log, workers_log = project.logs("coordinator"), project.logs("worker")
        expect("the run was finished already" in log, f"the coordinator does not say the run was finished:\n{log}")
        expect(workers_log.count("the coordinator shuts the worker down: the run is finished") >= 8,
               f"the workers were not told the run is finished:\n{workers_log}")
        print(f"  `up` on the finished run: exit 0; the coordinator said so, told the 4 workers and exited 0 "
              f"({time.monotonic() - finished_up:.0f} s)")

        # no anonymous volume: the project's named volume is the only new one
        new_volumes = set(run(["docker", "volume", "ls", "-q"]).stdout.split()) - volumes_before
        expect(new_volumes == {project.volume()}, f"volumes made by the project: {sorted(new_volumes)}, not only "
                                                  f"{project.volume()}")
        print(f"  volumes: {project.volume()} alone")
        same_checkpoint(args, project, root, "quick", iterations)


def check_config(args, root):
    with compose_project(args, "config") as project:
        # a run of quick, then of es_alone on the same volume
        for config in ("quick", "es_alone"):
            project("up", "-d", "--no-build", overrides={"POET_CONFIG": config, "POET_ITERATIONS": "1"})
            wait_until(f"the end of the {config} run", lambda: coordinator_exited(project) is not None, RUN_TIMEOUT_S)
            log = project.logs("coordinator")
            expect(coordinator_exited(project) == 0 and f"new run in /var/lib/poet/runs/{config}" in log,
                   f"POET_CONFIG={config}: exit {coordinator_exited(project)}, no new run in runs/{config}:\n{log}")
            print(f"  POET_CONFIG={config}: a new run in /var/lib/poet/runs/{config}, finished")
        expect(project.read_volume_file("runs/quick/checkpoint.pb") != b"", "the quick run's checkpoint is gone")

        # a directory that holds a run of another config: a refusal, tried 1 + 3 times, then down with its message
        project("run", "--rm", "--no-deps", "-T", "coordinator", "cp", "-R", "/var/lib/poet/runs/quick",
                "/var/lib/poet/runs/no_transfer", overrides={"POET_CONFIG": "quick"})
        result = project("up", "-d", "--no-build", overrides={"POET_CONFIG": "no_transfer", "POET_ITERATIONS": "1"},
                         check=False)
        wait_until("the refused coordinator to stay down", lambda: coordinator_exited(project) is not None, 120)
        time.sleep(5)  # and it stays down
        container = project.inspect(project.containers("coordinator")[0])
        state, log = container["State"], project.logs("coordinator")
        refusals = log.count("already holds a run of another config")
        expect(not state["Running"] and state["ExitCode"] == 2 and container["RestartCount"] == 3,
               f"the refusing coordinator: running {state['Running']}, exit {state['ExitCode']}, restarted "
               f"{container['RestartCount']} times (expected down, exit 2, 3 restarts)")
        expect(refusals == 4, f"the refusal is logged {refusals} times, not 4:\n{log}")
        print(f"  a run directory of another config: refused 4 times (exit 2), then down; `up` exit "
              f"{result.returncode}")


def check_curve(args, root):
    workdir = os.path.join(root, "machine")
    os.makedirs(workdir)
    with compose_project(args, "curve", curve=True) as project:
        tag = project.tag
        # docs/deploying.md's command, in a directory without keys/
        for who in ("coordinator", "worker --authorize"):
            run(["sh", "-c", "docker run --rm --user root -v \"$PWD:/out\" -w /out " + tag +
                 " sh -c \"poetctl keygen keys " + who + " && chown -R $(id -u):$(id -g) keys && "
                 "chown 10001:10001 keys/*.key_secret\""], cwd=workdir, timeout=120)
        keys = os.path.join(workdir, "keys")
        expect(sorted(os.listdir(keys)) == ["authorized", "coordinator.key", "coordinator.key_secret", "worker.key",
                                            "worker.key_secret"], f"keys/ holds {sorted(os.listdir(keys))}")
        expect(os.stat(os.path.join(keys, "worker.key_secret")).st_uid == 10001, "the secret halves are not uid 10001's")
        iterations = 2
        project.variables["POET_KEYS"] = keys
        project("up", "-d", "--no-build", overrides={"POET_CONFIG": "quick", "POET_ITERATIONS": str(iterations),
                                                     "POET_WORKERS": "2"})
        wait_until("2 workers connected over CURVE", lambda: (status(project) or {}).get("workers") == 2, 60)
        wait_until("the end of the run", lambda: coordinator_exited(project) is not None, RUN_TIMEOUT_S)
        log = project.logs("coordinator")
        expect(coordinator_exited(project) == 0, f"the coordinator exited {coordinator_exited(project)}:\n{log}")
        expect("CURVE" in log or "curve" in log, f"the coordinator's log does not mention CURVE:\n{log}")
        print("  keys made in a container; 2 workers joined over CURVE; the run finished")
        same_checkpoint(args, project, root, "quick", iterations)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("check", choices=["image", "compose", "config", "curve", "cleanup"])
    parser.add_argument("--source", required=True, help="the repository root")
    parser.add_argument("--build-dir", required=True, help="the CMake build directory")
    parser.add_argument("--coordinator", required=True, help="this build's poet-coordinator (the threads' run)")
    args = parser.parse_args()
    args.source = os.path.realpath(args.source)

    def check():
        version = require_runtime()
        print(f"  Docker {version}; compose: {' '.join(compose_command())}")
        if args.check == "image":
            check_image(args)
        elif args.check == "cleanup":
            check_cleanup(args)
        else:
            root = tempfile.mkdtemp(prefix=f"poet_containers_{args.check}_")
            try:
                {"compose": check_compose, "config": check_config, "curve": check_curve}[args.check](args, root)
            finally:
                shutil.rmtree(root, ignore_errors=True)
                if os.path.exists(root):  # files of the containers' users
                    subprocess.run(["docker", "run", "--rm", "--user", "root", "-v", f"{root}:/t",
                                    image_tag(args.source), "rm", "-rf", "/t/machine"], capture_output=True,
                                   timeout=60)
                    shutil.rmtree(root, ignore_errors=True)

    return run_check(f"container_{args.check}", check)


if __name__ == "__main__":
    sys.exit(main())
