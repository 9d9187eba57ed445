"""poet.start: real poet-coordinator processes started, watched, stopped and resumed from Python, their errors as
exceptions with the coordinator's own messages. Every test ends the processes it started and checks that none
is left."""

import os
import signal
import sys
import time

import pytest

import poet

ENDLESS = 1_000_000  # an iteration limit no test reaches: the run goes on until it is stopped


@pytest.fixture(autouse=True)
def coordinator_bin():
    path = os.environ.get("POET_COORDINATOR_BIN")
    if not path:
        pytest.skip("POET_COORDINATOR_BIN is not set (ctest sets it)")
    return path


@pytest.fixture
def config(tiny_config):
    return tiny_config


def processes_naming(path):
    """The live processes whose command line names path (a zombie's is empty)."""
    found = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as file:
                if os.fsencode(path) in file.read() and int(pid) != os.getpid():
                    found.append(int(pid))
        except OSError:
            pass  # ended while listed
    return found


@pytest.fixture
def launch(tmp_path):
    """poet.start on one thread, bounded in time; at the end every coordinator it started is stopped (killed if need
    be), and the test fails if one was still running or any process naming the test's directory is left."""
    started = []

    def launch_(*args, **kwargs):
        kwargs.setdefault("threads", 1)
        kwargs.setdefault("timeout", 60)
        handle = poet.start(*args, **kwargs)
        started.append(handle)
        return handle

    yield launch_
    running = [handle.pid for handle in started if handle.running]
    for handle in started:
        handle.stop(timeout=10)
    assert not running, f"coordinators left running: {running}"
    assert not processes_naming(tmp_path)


def wait_for_iteration(handle, iteration, timeout=60):
    deadline = time.monotonic() + timeout
    while (reached := handle.status()["iteration"]) < iteration:
        assert time.monotonic() < deadline, f"at iteration {reached} after {timeout} s"
        time.sleep(0.1)
    return reached


@pytest.mark.parametrize("with_tqdm", [True, False])
def test_a_run_started_from_python_finishes_and_reads_as_a_run(launch, config, tmp_path, capsys, monkeypatch,
                                                               with_tqdm):
    if with_tqdm:
        pytest.importorskip("tqdm.auto")
    else:
        monkeypatch.setitem(sys.modules, "tqdm.auto", None)  # as if tqdm were not installed
    run_dir = tmp_path / "run"
    coordinator = launch(config, run_dir)
    assert coordinator.status()["iterations"] == 8
    assert coordinator.wait(progress=True, timeout=120) == 0
    assert not coordinator.running and coordinator.returncode == 0
    progress = capsys.readouterr().err
    assert ("iterations: 100%|" if with_tqdm else "\riteration 8/8\n") in progress

    run = coordinator.run
    assert run.next_iteration == 8 and not run.live and len(run.pairs) >= 2
    log = (run_dir / poet.launch.LOG_NAME).read_text()
    assert coordinator.log_path == str(run_dir / "coordinator.log")
    assert "poet.start: " in log and "status: http://127.0.0.1:" in log and "run finished at iteration 8" in log
    with pytest.raises(RuntimeError, match="finished .exit 0.*it serves no status"):
        coordinator.status()
    assert coordinator.stop() == 0  # an ended process: its exit code

    again = launch(config, run_dir)  # a finished run: nothing to do
    assert again.wait(progress=False, timeout=60) == 0 and again.run.next_iteration == 8


def test_stop_keeps_the_checkpoint_and_start_resumes_from_it(launch, config, tmp_path):
    run_dir = tmp_path / "run"
    coordinator = launch(config, run_dir, iterations=ENDLESS)
    status = coordinator.status()
    assert status["state"] == "running" and status["iterations"] == ENDLESS
    wait_for_iteration(coordinator, 2)
    with pytest.raises(TimeoutError, match="still running"):
        coordinator.wait(progress=False, timeout=0.3)  # the run goes on
    with pytest.raises(ValueError, match="timeout"):
        coordinator.wait(timeout=0)
    assert coordinator.running
    assert coordinator.stop() == 130  # SIGINT, the coordinator's documented code
    assert not coordinator.running
    assert (run_dir / "checkpoint.pb").exists()
    stopped_at = coordinator.run.next_iteration
    assert stopped_at >= 2
    log = (run_dir / "coordinator.log").read_text()
    # the SIGINT came during an iteration or between two (the coordinator's two ways of saying it stopped)
    assert "stopped during iteration" in log or "interrupted at iteration" in log

    # config=None resumes the run in the directory; the iterations go on from the checkpoint
    resumed = launch(None, run_dir, iterations=stopped_at + 2)
    assert resumed.status()["iteration"] >= stopped_at
    assert resumed.wait(progress=False, timeout=120) == 0
    assert resumed.run.next_iteration == stopped_at + 2
    assert f"resumed {run_dir} at iteration {stopped_at}" in (run_dir / "coordinator.log").read_text()

    # the same config resumes it too; leaving the with block stops it
    with launch(config, run_dir, iterations=ENDLESS) as again:
        assert wait_for_iteration(again, stopped_at + 3) >= stopped_at + 3
    assert again.returncode == 130 and again.run.next_iteration >= stopped_at + 3


def test_a_bad_config_raises_the_coordinators_message(launch, tmp_path):
    run_dir = tmp_path / "run"
    unknown = tmp_path / "unknown.textproto"
    unknown.write_text("bogus: 1\n")
    with pytest.raises(poet.CoordinatorError, match='unknown.textproto: line 1:6: .*no field named "bogus"') as error:
        launch(unknown, run_dir)
    assert error.value.returncode == 2 and error.value.log_path == str(run_dir / "coordinator.log")
    contradiction = tmp_path / "contradiction.textproto"
    contradiction.write_text("poet { mc_low: 300 mc_high: 50 }\n")
    with pytest.raises(poet.CoordinatorError, match="poet.mc_low: 300 exceeds poet.mc_high 50") as error:
        launch(contradiction, run_dir)
    assert "bogus" not in str(error.value)  # the message is this start's, not the log's earlier one
    assert not (run_dir / "checkpoint.pb").exists()

    damaged = tmp_path / "damaged"
    damaged.mkdir()
    (damaged / "checkpoint.pb").write_bytes(b"not a checkpoint")
    with pytest.raises(poet.CoordinatorError, match="checkpoint.pb"):
        launch(None, damaged)


def test_a_directory_owned_by_a_live_run_is_refused_with_its_owner(launch, config, tmp_path):
    run_dir = tmp_path / "run"
    owner = launch(config, run_dir, iterations=ENDLESS)
    with pytest.raises(poet.CoordinatorError, match=rf"is in use by another process \(pid {owner.pid}\)") as error:
        launch(config, run_dir)
    assert error.value.returncode == 2
    assert owner.running and owner.status()["state"] == "running"  # the owner goes on
    assert owner.stop() == 130


def test_a_coordinator_killed_is_a_failure_and_one_terminated_is_a_stop(launch, config, tmp_path):
    run_dir = tmp_path / "run"
    killed = launch(config, run_dir, iterations=ENDLESS)
    os.kill(killed.pid, signal.SIGKILL)
    with pytest.raises(poet.CoordinatorError, match="killed by SIGKILL") as error:
        killed.wait(progress=False, timeout=30)
    assert error.value.returncode == -signal.SIGKILL

    terminated = launch(config, run_dir, iterations=ENDLESS)  # resumes after kill -9
    os.kill(terminated.pid, signal.SIGTERM)
    assert terminated.wait(progress=False, timeout=30) == 143


def test_hostile_arguments_are_refused_before_anything_starts(config, tmp_path, monkeypatch):
    new = tmp_path / "new"
    with pytest.raises(TypeError, match="config must be a path"):
        poet.start(42, new)
    with pytest.raises(TypeError, match="run_dir must be a path"):
        poet.start(config, None)
    with pytest.raises(FileNotFoundError, match="config: .*missing.textproto is not a file"):
        poet.start(tmp_path / "missing.textproto", new)
    with pytest.raises(ValueError, match="config is required for a new run: .*holds no run"):
        poet.start(None, new)
    for name, value in (("threads", "2"), ("threads", True), ("threads", 1.5), ("iterations", "10")):
        with pytest.raises(TypeError, match=f"{name} must be an integer"):
            poet.start(config, new, **{name: value})
    for name, value, least in (("threads", 0, 1), ("local_workers", -1, 0), ("iterations", -1, 0)):
        with pytest.raises(ValueError, match=f"{name} must be at least {least}, got {value}"):
            poet.start(config, new, **{name: value})
    with pytest.raises(FileNotFoundError, match="start_from: "):
        poet.start(config, new, start_from=tmp_path / "no-walker.json")
    for timeout in (0, -1):
        with pytest.raises(ValueError, match=f"timeout must be a positive number of seconds, got {timeout}"):
            poet.start(config, new, timeout=timeout)
    for timeout in ("5", None, True):
        with pytest.raises(TypeError, match="timeout must be a number of seconds"):
            poet.start(config, new, timeout=timeout)
    held = tmp_path / "held"
    held.mkdir()
    (held / "checkpoint.pb").write_bytes(b"")
    with pytest.raises(ValueError, match="start_from is a new run's first policy: it needs a config"):
        poet.start(None, held, start_from=config)

    with pytest.raises(FileNotFoundError, match="coordinator: .*nowhere is not an executable file"):
        poet.start(config, new, coordinator=tmp_path / "nowhere")
    monkeypatch.setenv("POET_COORDINATOR_BIN", str(tmp_path / "nowhere"))
    with pytest.raises(FileNotFoundError, match="POET_COORDINATOR_BIN: .*nowhere is not an executable file"):
        poet.start(config, new)
    assert not new.exists() and not processes_naming(tmp_path)


def test_the_coordinator_is_found_beside_the_module_in_the_build_tree(coordinator_bin, monkeypatch):
    monkeypatch.delenv("POET_COORDINATOR_BIN")
    assert os.path.samefile(poet.launch.find_coordinator(), coordinator_bin)
