#!/usr/bin/python3
"""POET on a real SLURM cluster on this machine, through the batch scripts users submit (deploy/slurm/).

The fixture writes a slurm.conf of its own (Debian's slurm-wlm, built with multiple-slurmd support: each node is a
slurmd of its own on its own port, all on this host), and starts a munged on a socket and key of its own,
slurmctld and four slurmd nodes: c1 for the coordinator, w1..w3 for workers. Every daemon is this process's child
(in the foreground, ending with it even if it is killed outright), every process of every job carries a tag in its
environment, and all of them, the daemons and the cluster's directory are removed on pass, failure, SIGTERM and the
check's own deadline. Each scenario runs the quick preset (from the shipped walker, as deploy/run.sh starts it)
through deploy/slurm/submit.sh and must end with the run's checkpoint byte-identical to the same config run on
threads (made once by `reference` and kept in the build tree), and squeue and `scontrol show job` must show what a
user expects:

  reference     the quick preset on two threads, kept as build/slurm-reference/checkpoint.pb (a ctest fixture)
  hetjob        `submit.sh run`: one heterogeneous job (coordinator + 3 worker nodes) runs the preset to its end:
                COMPLETED 0:0, no restart
  chain         2-minute time limits: SLURM's warning (USR1) stops the coordinator at a boundary and the job submits
                the next link of the chain, at least three jobs, each COMPLETED 0:0; the first link is signalled
                as its coordinator starts; a limit within a minute of the lead is refused; the cost of each link
                is printed (seconds and rollouts)
  array         a run on one worker node, then `submit.sh workers 3` mid-run (a job array whose tasks find the
                coordinator through coordinator.endpoint), two tasks cancelled with scancel: they end CANCELLED,
                the third COMPLETED when the run is finished
  requeue       the run's job requeued mid-run (scontrol requeue) and later preempted by a job of a partition of
                higher priority tier (PreemptMode=REQUEUE): Restarts=2, COMPLETED in the end

No accounting database here (slurmdbd needs MariaDB): sacct has nothing to show, so the jobs' history is read from
scontrol (MinJobAge keeps finished jobs) and jobcomp/filetxt, which records every end of a job, requeues included.
The test cluster shortens two waits a site's defaults make long (cred_expire=5 and sched_interval=2: a requeued
job starts within seconds instead of two minutes) and grants OverTimeLimit=2 (the quick preset's transfer
iterations last 27-55 s on two cores, up to twice that beside other tests under ctest -j2: longer than the 70 s
the chain's two-minute limit leaves after its 50-second lead, which breaks the rule docs/slurm.md gives for it).
Needs root and slurm-wlm and munge (deploy/install-deps.sh); without them the check is skipped (exit 77) saying why,
and under CI=true a missing package is a failure.
"""

import argparse
import glob
import hashlib
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

REPOSITORY = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPOSITORY, "tests"))
from check_support import Failed, Skipped, free_port, missing_tool, run_check  # noqa: E402

DEADLINE_S = {"reference": 1100, "hetjob": 1100, "chain": 1500, "array": 1100, "requeue": 1400}
PREFIX = "poet_slurm_"
TAG = "POET_SLURM_CHECK"  # in the environment of every daemon and job process: who to end at the clean-up
NODES = ("c1", "w1", "w2", "w3")
SUBMIT = os.path.join(REPOSITORY, "deploy", "slurm", "submit.sh")
QUICK = os.path.join(REPOSITORY, "deploy", "configs", "quick.textproto")
WALKER = os.path.join(REPOSITORY, "data", "walkers", "flat-walker.json")
STARTED = time.monotonic()


def log(message):
    print(f"[{time.monotonic() - STARTED:6.1f} s] {message}", flush=True)


def load_average():
    with open("/proc/loadavg") as f:
        return f.read().split()[0]


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def read(path):
    try:
        with open(path, errors="replace") as f:
            return f.read()
    except OSError:
        return ""


# ---------------------------------------------------------------------------------------------------------
# the cluster


def tagged_processes(value=None):
    """Pids of the processes whose environment carries TAG (=value, when given)."""
    pids = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            with open(f"/proc/{entry}/environ", "rb") as f:
                env = f.read().split(b"\0")
        except OSError:
            continue
        for item in env:
            if item.startswith(TAG.encode() + b"="):
                if value is None or item == f"{TAG}={value}".encode():
                    pids.append(int(entry))
                break
    return pids


def alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(")")[-1].split()[0] != "Z"
    except OSError:
        return False


def kill_all(pids):
    for pid in pids:
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass


def sweep_stale():
    """Ends the processes and removes the directories of earlier checks that are gone (killed outright)."""
    for path in glob.glob(os.path.join(tempfile.gettempdir(), PREFIX + "*")):
        m = re.fullmatch(PREFIX + r"(\d+)", os.path.basename(path))
        if m and not alive(int(m.group(1))):
            log(f"removing {path}, left by a check that is gone")
            kill_all(tagged_processes(m.group(1)))
            shutil.rmtree(path, ignore_errors=True)


def _die_with_parent():
    import ctypes
    ctypes.CDLL(None).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


class SlurmCluster:
    """munged, slurmctld and the slurmd nodes, each in the foreground as this process's child."""

    def __init__(self):
        self.tag = str(os.getpid())
        self.dir = os.path.join(tempfile.gettempdir(), PREFIX + self.tag)
        self.conf = os.path.join(self.dir, "slurm.conf")
        self.munge_socket = os.path.join(self.dir, "munge", "munge.socket")
        self.daemons = []  # (name, Popen)
        self.env = dict(os.environ, SLURM_CONF=self.conf, **{TAG: self.tag})

    def _start(self, name, argv, user=None):
        if user:
            argv = ["runuser", "-u", user, "--"] + argv
        out = open(os.path.join(self.dir, "log", name + ".out"), "w")
        proc = subprocess.Popen(argv, stdout=out, stderr=subprocess.STDOUT, env=self.env,
                                preexec_fn=_die_with_parent)
        self.daemons.append((name, proc))
        return proc

    def write_conf(self):
        host = subprocess.run(["hostname", "-s"], capture_output=True, text=True).stdout.strip() or "localhost"
        ports = [free_port() for _ in range(len(NODES) + 1)]
        d = self.dir
        lines = [
            f"ClusterName=poetcheck",
            f"SlurmctldHost={host}(127.0.0.1)",  # its address, whether or not the name resolves here
            "SlurmUser=root",
            "AuthType=auth/munge",
            f"AuthInfo=socket={self.munge_socket},cred_expire=5",
            "ProctrackType=proctrack/linuxproc",
            "TaskPlugin=task/none",
            "SelectType=select/cons_tres",
            "SelectTypeParameters=CR_Core",
            "SchedulerParameters=bf_interval=1,sched_interval=2",
            "SlurmdParameters=config_overrides",
            "ReturnToService=2",
            "KillWait=10",
            "OverTimeLimit=2",
            "JobRequeue=1",
            "MinJobAge=3600",
            "PreemptType=preempt/partition_prio",
            "PreemptMode=REQUEUE",
            f"SlurmctldPort={ports[0]}",
            f"SlurmctldPidFile={d}/run/slurmctld.pid",
            f"SlurmdPidFile={d}/run/slurmd-%n.pid",
            f"SlurmdSpoolDir={d}/spool/%n",
            f"StateSaveLocation={d}/ctld",
            f"SlurmctldLogFile={d}/log/slurmctld.log",
            f"SlurmdLogFile={d}/log/slurmd-%n.log",
            "JobCompType=jobcomp/filetxt",
            f"JobCompLoc={d}/log/jobcomp.txt",
            "MpiDefault=none",
        ]
        for name, port in zip(NODES, ports[1:]):
            lines.append(f"NodeName={name} NodeHostname={host} NodeAddr=127.0.0.1 Port={port} CPUs=2")
        lines.append("PartitionName=main Nodes=ALL Default=YES MaxTime=INFINITE State=UP PriorityTier=1")
        lines.append("PartitionName=urgent Nodes=ALL Default=NO MaxTime=INFINITE State=UP PriorityTier=2 "
                     "PreemptMode=OFF")
        with open(self.conf, "w") as f:
            f.write("\n".join(lines) + "\n")

    def up(self):
        for tool in ("slurmctld", "slurmd", "sbatch", "scontrol", "munged"):
            if shutil.which(tool) is None and not os.path.exists(f"/usr/sbin/{tool}"):
                missing_tool(f"no {tool} (Debian's slurm-wlm and munge)")
        for sub in ("ctld", "log", "run", "munge", "runs") + tuple(f"spool/{n}" for n in NODES):
            os.makedirs(os.path.join(self.dir, sub), exist_ok=True)
        # munged: a key and socket of its own, as the munge user, which must own them
        key = os.path.join(self.dir, "munge", "munge.key")
        with open(key, "wb") as f:
            f.write(os.urandom(1024))
        os.chmod(key, 0o400)
        os.chmod(os.path.join(self.dir, "munge"), 0o700)
        subprocess.run(["chown", "-R", "munge:munge", os.path.join(self.dir, "munge")], check=True)
        self._start("munged", ["/usr/sbin/munged", "-F", "--force", f"--socket={self.munge_socket}",
                               f"--key-file={key}", f"--pid-file={self.dir}/munge/munged.pid",
                               f"--seed-file={self.dir}/munge/seed", f"--log-file={self.dir}/munge/munged.log"],
                    user="munge")
        deadline = time.monotonic() + 20
        while not os.path.exists(self.munge_socket):
            if time.monotonic() > deadline:
                raise Failed(f"munged made no socket: {read(os.path.join(self.dir, 'log', 'munged.out'))}")
            time.sleep(0.1)
        self.write_conf()
        self._start("slurmctld", ["/usr/sbin/slurmctld", "-D", "-c", "-f", self.conf])
        for node in NODES:
            self._start(f"slurmd-{node}", ["/usr/sbin/slurmd", "-D", "-f", self.conf, "-N", node])
        deadline = time.monotonic() + 60
        while True:
            r = self.run(["sinfo", "-h", "-N", "-o", "%N %t"], check=False)
            idle = [l.split()[0] for l in r.stdout.splitlines() if l.split()[1:] == ["idle"]]
            if len(set(idle)) == len(NODES):
                break
            for name, proc in self.daemons:
                if proc.poll() is not None:
                    raise Failed(f"{name} exited {proc.returncode}: "
                                 f"{read(os.path.join(self.dir, 'log', name + '.out'))[-2000:]}")
            if time.monotonic() > deadline:
                raise Failed(f"the nodes never all came up idle: {r.stdout.strip()} {r.stderr.strip()}")
            time.sleep(0.5)
        log(f"SLURM up in {self.dir}: slurmctld and nodes {', '.join(NODES)} (load {load_average()})")

    def run(self, argv, check=True, env=None, timeout=60):
        r = subprocess.run(argv, capture_output=True, text=True, env=env or self.env, timeout=timeout)
        if check and r.returncode != 0:
            raise Failed(f"{' '.join(argv)} exited {r.returncode}: {r.stderr.strip()}")
        return r

    def down(self):
        """Every job cancelled, every daemon ended, every tagged process killed, the directory removed."""
        if self.daemons:
            self.run(["scancel", "--full", "--user", "root"], check=False, timeout=30)
            deadline = time.monotonic() + 15
            while time.monotonic() < deadline:
                r = self.run(["squeue", "-h", "-o", "%i"], check=False, timeout=30)
                if r.returncode != 0 or not r.stdout.strip():
                    break
                time.sleep(0.5)
        for _, proc in reversed(self.daemons):
            if proc.poll() is None:
                proc.terminate()
        for _, proc in reversed(self.daemons):
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait(timeout=10)
        for _ in range(20):  # slurmstepd and the jobs' processes, reparented away from their slurmd
            left = tagged_processes(self.tag)
            if not left:
                break
            kill_all(left)
            time.sleep(0.2)
        if tagged_processes(self.tag):
            raise Failed(f"processes left after the clean-up: {tagged_processes(self.tag)}")
        shutil.rmtree(self.dir, ignore_errors=True)

    # --- what a user would ask ---------------------------------------------------------------------

    def job(self, job_id):
        """`scontrol -o show job ID` as a dict of the first record (a heterogeneous job's component 0)."""
        r = self.run(["scontrol", "-o", "show", "job", str(job_id)], check=False)
        if r.returncode != 0 or not r.stdout.strip():
            return {}
        fields = {}
        for word in r.stdout.splitlines()[0].split():
            key, _, value = word.partition("=")
            fields.setdefault(key, value)
        return fields

    def jobs(self, job_id):
        """Every record scontrol shows for ID (a heterogeneous job's components, an array's tasks)."""
        r = self.run(["scontrol", "-o", "show", "job", str(job_id)], check=False)
        records = []
        for line in r.stdout.splitlines():
            fields = {}
            for word in line.split():
                key, _, value = word.partition("=")
                fields.setdefault(key, value)
            records.append(fields)
        return records

    def squeue(self):
        return self.run(["squeue", "-h", "-t", "all", "-o", "%i %T %r"], check=False).stdout

    def wait_for_state(self, job_id, states, seconds, run_dir=None):
        deadline = time.monotonic() + seconds
        last = None
        while time.monotonic() < deadline:
            state = self.job(job_id).get("JobState")
            if state != last:
                log(f"job {job_id}: {state}" + (f" (iteration {iteration(run_dir)})" if run_dir else ""))
                last = state
            if state in states:
                return self.job(job_id)
            time.sleep(1)
        raise Failed(f"job {job_id} never reached {states} in {seconds} s: {self.job(job_id)}\n{self.squeue()}")

    def jobcomp(self):
        return read(os.path.join(self.dir, "log", "jobcomp.txt"))


# ---------------------------------------------------------------------------------------------------------
# runs


def iteration(run_dir):
    """The iteration the run's checkpoint resumes at (from annecs.csv's line count: one line an iteration)."""
    lines = read(os.path.join(run_dir, "annecs.csv")).splitlines()
    return max(0, len(lines) - 1)


def submit(cluster, args, run_dir, **settings):
    r = cluster.run(["bash", SUBMIT] + args, env=submit_env(cluster, run_dir, **settings))
    job_id = r.stdout.strip().split(";")[0]
    if not job_id.isdigit():
        raise Failed(f"submit.sh {' '.join(args)} printed {r.stdout!r}")
    log(f"submit.sh {' '.join(args)}: job {job_id}")
    return job_id


def submit_env(cluster, run_dir, **settings):
    env = dict(cluster.env, POET_HOME=REPOSITORY, POET_BUILD=ARGS.build_dir, POET_RUN_DIR=run_dir,
               POET_PRESET=QUICK, POET_START_FROM=WALKER, POET_WORKER_NODES="3", POET_WORKERS_PER_NODE="1",
               POET_TIME="30", POET_STOP_LEAD="1200")
    try:  # the node's host name where it resolves, as on a real cluster; else its address
        socket.getaddrinfo(socket.gethostname(), None)
    except OSError:
        env["POET_ADVERTISE_HOST"] = "127.0.0.1"
    env.update({k: str(v) for k, v in settings.items()})
    return env


def reference_checkpoint():
    return os.path.join(ARGS.build_dir, "slurm-reference", "checkpoint.pb")


def make_reference():
    """The quick preset on two threads, the checkpoint kept for the scenarios (made again when the binary or the
    preset changed: the digest of both is kept beside it)."""
    coordinator = os.path.join(ARGS.build_dir, "coordinator", "poet-coordinator")
    key = hashlib.sha256(open(coordinator, "rb").read() + open(QUICK, "rb").read()).hexdigest()
    out = os.path.dirname(reference_checkpoint())
    if read(os.path.join(out, "key")) == key and os.path.exists(reference_checkpoint()) and \
            os.path.exists(os.path.join(out, "reference.err")):
        log(f"reference kept in {out}")
        return
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    run_dir = os.path.join(out, "run")
    t0 = time.monotonic()
    r = subprocess.run([coordinator, "--config", QUICK, "--run-dir", run_dir, "--start-from", WALKER, "--threads",
                        "2", "--quiet", "--status-address", ""], capture_output=True, text=True,
                       timeout=DEADLINE_S["reference"] - 60)
    if r.returncode != 0:
        raise Failed(f"the run on threads exited {r.returncode}: {r.stderr[-3000:]}")
    shutil.copy(os.path.join(run_dir, "checkpoint.pb"), reference_checkpoint())
    with open(os.path.join(out, "reference.err"), "w") as f:  # its score cache's line, for the chain's cost
        f.write(r.stderr)
    with open(os.path.join(out, "key"), "w") as f:
        f.write(key)
    shutil.rmtree(run_dir)
    log(f"RESULT reference: the quick preset on 2 threads in {time.monotonic() - t0:.0f} s (load {load_average()})")


def expect_reference(run_dir, what):
    make_reference()  # at once when it is there for this binary and preset
    got = os.path.join(run_dir, "checkpoint.pb")
    if not os.path.exists(got):
        raise Failed(f"{what}: no checkpoint in {run_dir}")
    if sha256(got) != sha256(reference_checkpoint()):
        raise Failed(f"{what}: the checkpoint differs from the run on threads (iteration {iteration(run_dir)})")
    if os.path.exists(os.path.join(run_dir, "coordinator.endpoint")):
        raise Failed(f"{what}: coordinator.endpoint left behind")
    log(f"{what}: the checkpoint is byte-identical to the run on threads")


def expect_fields(record, what, **expected):
    for key, value in expected.items():
        if record.get(key) != value:
            raise Failed(f"{what}: {key}={record.get(key)}, expected {value}: {record}")


def run_output(cluster, job_id, run_dir):
    return read(os.path.join(os.path.dirname(run_dir), "slurm-logs", f"run-{job_id}.out"))


# ---------------------------------------------------------------------------------------------------------
# scenarios


def scenario_hetjob(cluster):
    run_dir = os.path.join(cluster.dir, "runs", "quick")
    job = submit(cluster, ["run"], run_dir)
    cluster.wait_for_state(job, ("RUNNING",), 60)
    components = cluster.squeue().split("\n")
    if not any(line.startswith(f"{job}+0 RUNNING") for line in components) or \
            not any(line.startswith(f"{job}+1 RUNNING") for line in components):
        raise Failed(f"squeue does not show the two components running:\n{cluster.squeue()}")
    record = cluster.wait_for_state(job, ("COMPLETED", "FAILED", "TIMEOUT", "CANCELLED"), 900, run_dir)
    expect_fields(record, "the run's job", JobState="COMPLETED", ExitCode="0:0", Restarts="0")
    nodes = [r.get("NodeList") for r in cluster.jobs(job)]
    if nodes[:2] != ["c1", "w[1-3]"]:
        raise Failed(f"the components ran on {nodes}, expected c1 and w[1-3]")
    out = run_output(cluster, job, run_dir)
    if "the run is finished" not in out or "run finished at iteration 30" not in out:
        raise Failed(f"the job's output does not say the run finished:\n{out[-3000:]}")
    expect_reference(run_dir, "hetjob")


def scenario_chain(cluster):
    run_dir = os.path.join(cluster.dir, "runs", "quick")
    # a limit within a minute of the lead is refused: SLURM's warning could come as the job starts
    r = cluster.run(["bash", SUBMIT, "run"], env=submit_env(cluster, run_dir, POET_TIME="1", POET_STOP_LEAD="50"),
                    check=False)
    if r.returncode != 2 or "leaves no minute beyond POET_STOP_LEAD=50" not in r.stderr or cluster.squeue().strip():
        raise Failed(f"submit.sh run with POET_TIME=1 and POET_STOP_LEAD=50 exited {r.returncode} ({r.stderr!r}), "
                     f"expected a refusal and no job:\n{cluster.squeue()}")
    log(f"submit.sh run with POET_TIME=1 and POET_STOP_LEAD=50 refused: {r.stderr.strip().split('] ', 1)[-1]}")
    t0 = time.monotonic()
    job = submit(cluster, ["run"], run_dir, POET_TIME="2", POET_STOP_LEAD="50")
    # the first link is asked to stop as the coordinator starts (as a warning sent early would), in the seconds
    # before it has taken SIGUSR1 over: the script passes it on once it has
    cluster.wait_for_state(job, ("RUNNING",), 60)
    deadline = time.monotonic() + 60
    while "link 1 of the chain" not in run_output(cluster, job, run_dir):
        if time.monotonic() > deadline:
            raise Failed(f"job {job}'s script never started:\n{run_output(cluster, job, run_dir)}")
        time.sleep(0.05)
    cluster.run(["scancel", "--batch", "--signal=USR1", job])
    log(f"scancel --batch --signal=USR1 {job} as its script starts the coordinator")
    jobs, outputs = [], []
    while True:  # each link names the next in its output
        record = cluster.wait_for_state(job, ("COMPLETED", "FAILED", "TIMEOUT", "CANCELLED"), 300, run_dir)
        out = run_output(cluster, job, run_dir)
        jobs.append(job)
        outputs.append(out)
        expect_fields(record, f"link {len(jobs)} of the chain (job {job})", JobState="COMPLETED", ExitCode="0:0",
                      Restarts="0")
        if "the run is finished" in out:
            break
        m = re.search(r"stopped at a boundary before the time limit: link (\d+) submitted as job (\d+)", out)
        if not m or int(m.group(1)) != len(jobs) + 1:
            raise Failed(f"job {job} neither finished the run nor submitted link {len(jobs) + 1}:\n{out[-4000:]}")
        job = m.group(2)
        if len(jobs) > 40:
            raise Failed(f"more than 40 links: {jobs}")
    wall = time.monotonic() - t0
    if len(jobs) < 3:
        raise Failed(f"the run took {len(jobs)} jobs, expected at least 3 with 2-minute limits:\n{outputs[-1][-3000:]}")
    if "TIMEOUT" in cluster.jobcomp():
        raise Failed(f"a job of the chain ran into its time limit:\n{cluster.jobcomp()}")
    for i, out in enumerate(outputs[:-1]):
        if "SIGUSR1: the coordinator stops" not in out or "stopped at the boundary of iterations" not in out:
            raise Failed(f"link {i + 1} (job {jobs[i]}) did not stop at a boundary on SIGUSR1:\n{out[-3000:]}")
    expect_reference(run_dir, "chain")
    whole = "\n".join(outputs)
    links = chain_links(whole)
    if len(links) != len(jobs) - 1:
        raise Failed(f"{len(jobs)} jobs but {len(links)} links read from their output:\n{whole[-4000:]}")
    saved = [int(n) for n in re.findall(r"score cache: (\d+) episodes asked for again were not run", whole)]
    straight = re.search(r"score cache: (\d+) episodes", read(os.path.join(os.path.dirname(reference_checkpoint()),
                                                                          "reference.err")))
    extra = int(straight.group(1)) - sum(saved) if straight else None
    mean = lambda values: sum(values) / len(values)  # noqa: E731
    log(f"RESULT chain: {len(jobs)} jobs ({', '.join(jobs)}) of 2 minutes for the quick preset's 30 iterations, "
        f"{wall:.0f} s from the first sbatch to the last job COMPLETED; a link, from the coordinator's stop at the "
        f"boundary to the next coordinator open (resumed): {', '.join(f'{l[0]:.1f}' for l in links)} s (mean "
        f"{mean([l[0] for l in links]):.1f}), to its first worker joined: {', '.join(f'{l[1]:.1f}' for l in links)} s "
        f"(mean {mean([l[1] for l in links]):.1f}); rollouts repeated: none (the iteration a stop finishes is "
        f"saved); episodes the score cache no longer spared: {extra if extra is not None else 'unknown'} (it spared "
        f"{sum(saved)} across the chain, {straight.group(1) if straight else '?'} straight through); "
        f"load {load_average()}")


def chain_links(out):
    """For each link of a chain read from the job's output (the batch script's lines and the coordinators'): the
    seconds from a coordinator's stop at a boundary to the next one's `resumed` line, and to its first worker
    joined."""
    import datetime
    events = []
    for line in out.splitlines():
        m = re.match(r"\[(?:poet-slurm )?(\d{4}-\d\d-\d\d \d\d:\d\d:\d\d(?:\.\d+)?)\] ", line)
        if not m:
            continue
        stamp = m.group(1)
        when = datetime.datetime.strptime(stamp, "%Y-%m-%d %H:%M:%S.%f" if "." in stamp else "%Y-%m-%d %H:%M:%S")
        if "[poet-coordinator]" in line and "stopped at the boundary of iterations" in line:
            events.append(("stop", when))
        elif "[poet-coordinator]" in line and "] resumed " in line:
            events.append(("resumed", when))
        elif "[poet-coordinator]" in line and " joined: " in line:
            events.append(("joined", when))
    links = []
    stop = resumed = None
    for kind, when in events:
        if kind == "stop":
            stop, resumed = when, None
        elif kind == "resumed" and stop is not None:
            resumed = when
        elif kind == "joined" and stop is not None and resumed is not None:
            links.append(((resumed - stop).total_seconds(), (when - stop).total_seconds()))
            stop = resumed = None
    return links


def scenario_array(cluster):
    run_dir = os.path.join(cluster.dir, "runs", "quick")
    job = submit(cluster, ["run"], run_dir, POET_WORKER_NODES="1")
    cluster.wait_for_state(job, ("RUNNING",), 60)
    wait_for_iteration(run_dir, 2, 300)
    array = submit(cluster, ["workers", "3"], run_dir)
    coordinator_log = lambda: run_output(cluster, job, run_dir)  # noqa: E731
    deadline = time.monotonic() + 120
    while len(set(re.findall(r"worker array-" + array + r"_(\d)@\S+ \(\d+ threads\) joined", coordinator_log()))) < 3:
        if time.monotonic() > deadline:
            raise Failed(f"the array's workers never all joined:\n{coordinator_log()[-3000:]}\n{cluster.squeue()}")
        time.sleep(1)
    log(f"the array's 3 workers joined at iteration {iteration(run_dir)}")
    wait_for_iteration(run_dir, iteration(run_dir) + 2, 300)
    cluster.run(["scancel", f"{array}_0", f"{array}_1"])
    log(f"scancel {array}_0 {array}_1 at iteration {iteration(run_dir)}")
    record = cluster.wait_for_state(job, ("COMPLETED", "FAILED", "TIMEOUT", "CANCELLED"), 900, run_dir)
    expect_fields(record, "the run's job", JobState="COMPLETED", ExitCode="0:0", Restarts="0")
    tasks = {r.get("ArrayTaskId"): r for r in cluster.jobs(array)}
    for task in ("0", "1"):
        expect_fields(tasks.get(task, {}), f"array task {task}", JobState="CANCELLED")
    last = cluster.wait_for_state(f"{array}_2", ("COMPLETED", "FAILED", "CANCELLED", "TIMEOUT"), 60)
    expect_fields(last, "array task 2", JobState="COMPLETED", ExitCode="0:0")
    expect_reference(run_dir, "array")


def wait_for_iteration(run_dir, n, seconds):
    deadline = time.monotonic() + seconds
    while iteration(run_dir) < n:
        if time.monotonic() > deadline:
            raise Failed(f"the run never reached iteration {n} (at {iteration(run_dir)})")
        time.sleep(0.5)


def scenario_requeue(cluster):
    run_dir = os.path.join(cluster.dir, "runs", "quick")
    job = submit(cluster, ["run"], run_dir)
    cluster.wait_for_state(job, ("RUNNING",), 60)
    wait_for_iteration(run_dir, 3, 300)
    at = iteration(run_dir)
    cluster.run(["scontrol", "requeue", job])
    log(f"scontrol requeue {job} at iteration {at}")
    requeued = time.monotonic()
    deadline = requeued + 120
    nudged = False
    while int(cluster.job(job).get("Restarts", "0")) < 1 or cluster.job(job).get("JobState") != "RUNNING":
        if time.monotonic() > deadline:
            raise Failed(f"the requeued job never ran again: {cluster.job(job)}\n{cluster.squeue()}")
        if not nudged and time.monotonic() > requeued + 30:
            # SLURM 22.05 starts a requeued heterogeneous job on a backfill pass only, which an idle cluster runs
            # when something changes: what docs/slurm.md tells an operator to do then
            cluster.run(["scontrol", "update", f"jobid={job}", "starttime=now"])
            log(f"job {job} still pending 30 s after the requeue on the idle cluster: scontrol update "
                f"jobid={job} starttime=now")
            nudged = True
        time.sleep(0.5)
    log(f"job {job} running again {time.monotonic() - requeued:.0f} s after the requeue, Restarts=1")
    wait_for_iteration(run_dir, at + 4, 400)
    at = iteration(run_dir)
    urgent = cluster.run(["sbatch", "--parsable", "--partition", "urgent", "--nodelist", "c1", "--exclusive",
                          "--output", os.path.join(cluster.dir, "log", "urgent-%j.out"), "--wrap", "sleep 5"])
    urgent_id = urgent.stdout.strip()
    log(f"job {urgent_id} of the partition urgent on c1 at iteration {at}: it preempts the run's job")
    cluster.wait_for_state(urgent_id, ("COMPLETED",), 120)
    record = cluster.wait_for_state(job, ("COMPLETED", "FAILED", "TIMEOUT", "CANCELLED"), 900, run_dir)
    expect_fields(record, "the run's job", JobState="COMPLETED", ExitCode="0:0", Restarts="2")
    comp = cluster.jobcomp()
    if f"JobId={job} " not in comp or "PREEMPTED" not in comp:
        raise Failed(f"jobcomp does not record the preemption:\n{comp}")
    expect_reference(run_dir, "requeue")


SCENARIOS = {"hetjob": scenario_hetjob, "chain": scenario_chain, "array": scenario_array,
             "requeue": scenario_requeue}


def check():
    if os.geteuid() != 0:
        raise Skipped("needs root (it starts munged, slurmctld and slurmd)")
    if ARGS.scenario == "reference":
        make_reference()
        return
    def deadline(_signum, _frame):
        raise Failed(f"the check's own deadline of {DEADLINE_S[ARGS.scenario]} s passed")

    signal.signal(signal.SIGALRM, deadline)
    signal.alarm(DEADLINE_S[ARGS.scenario])
    sweep_stale()
    cluster = SlurmCluster()
    try:
        cluster.up()
        SCENARIOS[ARGS.scenario](cluster)
    except Failed:
        log(f"squeue at the failure:\n{cluster.squeue() if cluster.daemons else ''}")
        log(f"jobcomp:\n{cluster.jobcomp()}")
        for path in sorted(glob.glob(os.path.join(cluster.dir, "runs", "slurm-logs", "*.out"))):
            log(f"{path}:\n{read(path)[-3000:]}")
        for name in ("slurmctld.log", "slurmd-c1.log"):  # what SLURM says of a job that failed to launch
            log(f"{name}, its end:\n{read(os.path.join(cluster.dir, 'log', name))[-2500:]}")
        raise
    finally:
        signal.alarm(0)
        for sig in (signal.SIGTERM, signal.SIGINT):  # a second signal must not cut the clean-up short
            signal.signal(sig, signal.SIG_IGN)
        cluster.down()


def main():
    global ARGS
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenario", choices=["reference"] + list(SCENARIOS))
    parser.add_argument("--build-dir", default=os.path.join(REPOSITORY, "build"))
    ARGS = parser.parse_args()
    ARGS.build_dir = os.path.abspath(ARGS.build_dir)
    return run_check(f"slurm_{ARGS.scenario}", check)


if __name__ == "__main__":
    sys.exit(main())
