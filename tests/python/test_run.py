"""poet.Run: a run directory read without changing it, with poet-report's numbers; the example script runs on
it. The run is made here, by poet-coordinator, in a temporary directory."""

import hashlib
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import poet


def binary(name):
    path = os.environ.get(name)
    if not path:
        pytest.skip(f"{name} is not set (ctest sets it)")
    return path


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory, tiny_config):
    root = tmp_path_factory.mktemp("run")
    subprocess.run([binary("POET_COORDINATOR_BIN"), "--config", str(tiny_config), "--run-dir", str(root / "run"),
                    "--threads", "2", "--quiet"], check=True, capture_output=True, timeout=240)
    return root / "run"


def digest(directory):
    h = hashlib.sha256()
    for path in sorted(directory.rglob("*")):
        if path.is_file():
            h.update(str(path.relative_to(directory)).encode())
            h.update(path.read_bytes())
    return h.hexdigest()


def test_run_equals_poet_reports_numbers_and_writes_nothing(run_dir):
    before = digest(run_dir)
    run = poet.Run(run_dir)
    report = json.loads(subprocess.run([binary("POET_REPORT_BIN"), "--run-dir", str(run_dir), "--json", "-"],
                                       check=True, capture_output=True, text=True, timeout=120).stdout)
    assert digest(run_dir) == before
    assert run.next_iteration == 8 and not run.live
    report["run_dir"] = run.report["run_dir"]  # the same directory, spelled as each was given it
    assert run.report == report

    pairs = run.pairs
    assert list(pairs.index) == [p["id"] for p in report["pairs"]]
    assert pairs["best_score"].tolist() == [p["best_score"] for p in report["pairs"]]
    levels = run.levels
    assert levels.loc["easy", "created"] == report["levels"][0]["created"]
    assert levels["admitted"].sum() == sum(level["admitted"] for level in report["levels"])

    annecs = run.annecs
    assert list(annecs.index) == list(range(run.next_iteration))
    assert annecs["at_admission"].iloc[-1] == report["annecs"]["at_admission"]["value"]
    lines = (run_dir / "annecs.csv").read_text().splitlines()
    assert lines[0] == "iteration,annecs_at_admission,annecs_at_archiving"
    assert lines[1:] == [f"{t},{row.at_admission},{row.at_archiving}" for t, row in annecs.iterrows()]
    events = run.events
    assert set(events["event"]) >= {"pair_created", "reproduction", "transfer_round"}
    assert events["iteration"].max() < run.next_iteration
    stats = run.pair_stats
    assert len(stats) == sum(1 for line in (run_dir / "pair_stats.csv").read_text().splitlines()[1:] if line)
    assert set(stats["pair"]) == set(pairs.index)

    for pair in pairs.index:
        theta = run.theta(pair)
        assert theta.shape == (2804,) and theta.dtype == np.float64 and np.all(np.isfinite(theta))
        encoding = run.encoding(pair)
        assert set(encoding) == {"config", "seed"}
        on_disk = json.loads((run_dir / "envs" / f"pair-{pair}.env.json").read_text())
        assert encoding == on_disk
    assert "seed: 5" in run.config


def test_the_example_plots_a_runs_scores(run_dir, tmp_path):
    example = os.path.join(os.environ.get("POET_SOURCE_DIR", ""), "examples", "plot_scores.py")
    out = tmp_path / "scores.png"
    done = subprocess.run([sys.executable, example, str(run_dir), str(out)], capture_output=True, text=True,
                          timeout=120, env={**os.environ, "MPLCONFIGDIR": str(tmp_path)})
    assert done.returncode == 0, done.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_what_is_not_a_run_says_so(tmp_path):
    with pytest.raises(ValueError, match="checkpoint.pb"):
        poet.Run(tmp_path)
    with pytest.raises(ValueError, match="no such|does not exist|not"):
        poet.Run(tmp_path / "missing")
    with pytest.raises(TypeError):
        poet.Run(42)


def test_an_unknown_pair_is_a_value_error(run_dir):
    run = poet.Run(run_dir)
    with pytest.raises(ValueError, match="no pair 99"):
        run.theta(99)


def test_the_annecs_comparison_plots_runs_within_one_budget(run_dir, tmp_path):
    script = os.path.join(os.environ.get("POET_SOURCE_DIR", ""), "experiments", "annecs_compare.py")
    out = tmp_path / "annecs.png"
    done = subprocess.run([sys.executable, script, "--run", f"a={run_dir}", "--run", f"b={run_dir}",
                           "--out", str(out)], capture_output=True, text=True, timeout=120,
                          env={**os.environ, "MPLCONFIGDIR": str(tmp_path)})
    assert done.returncode == 0, done.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = [line.split() for line in done.stdout.splitlines() if line.startswith(("a ", "b "))]
    assert len(rows) == 2 and rows[0][1:] == rows[1][1:]  # the same run twice: the same figures
    assert int(rows[0][1]) == len(poet.Run(run_dir).annecs)  # every iteration within its own wall time
    bad = subprocess.run([sys.executable, script, "--run", "no-label", "--out", str(out)], capture_output=True,
                         text=True, timeout=60, env={**os.environ, "MPLCONFIGDIR": str(tmp_path)})
    assert bad.returncode == 2 and "LABEL=RUN_DIR" in bad.stderr


def test_the_hardest_solved_ranks_a_runs_solved_environments(tmp_path):
    source = os.environ.get("POET_SOURCE_DIR", "")
    walker = os.path.join(source, "data", "walkers", "flat-walker.json")
    config = tmp_path / "cppn.textproto"
    config.write_text("""mode: POET
seed: 3
iterations: 3
es { perturbations: 2 }
poet { mutation_interval: 1 transfer_interval: 2 repro_threshold: 200 mc_low: 25 mc_high: 340
       max_children: 4 max_admitted: 1 active_cap: 4 environments: CPPN_TERRAIN novelty: PATA_EC }
""")
    run_dir = tmp_path / "run"
    subprocess.run([binary("POET_COORDINATOR_BIN"), "--config", str(config), "--run-dir", str(run_dir),
                    "--start-from", walker, "--threads", "2", "--quiet"], check=True, capture_output=True, timeout=240)
    script = os.path.join(source, "experiments", "hardest_solved.py")
    done = subprocess.run([sys.executable, script, str(run_dir), walker, "--seeds", "2"], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    rows = [line.split() for line in done.stdout.splitlines()[1:]]
    solved = poet.Run(run_dir).pairs["solved"].notna().sum()
    assert len(rows) == solved >= 2  # the first environment and at least one child
    returns = [float(row[4]) for row in rows]
    assert returns == sorted(returns)  # hardest first
    assert all(row[1].startswith("cppn-") for row in rows)


def test_the_time_per_stage_splits_the_wall_time_by_phase(run_dir):
    script = os.path.join(os.environ.get("POET_SOURCE_DIR", ""), "experiments", "time_per_stage.py")
    done = subprocess.run([sys.executable, script, str(run_dir), "--stage-iterations", "4"], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    rows = [line.split("|")[1:-1] for line in done.stdout.splitlines() if line.startswith("| ") and "–" in line]
    assert [row[0].strip() for row in rows] == ["0–3", "4–7"]
    for row in rows:
        assert row[7].strip() == "4 of 4"  # every iteration of this build's run has its phases timed
        shares = [float(cell.strip().rstrip(" %")) for cell in row[8:13]]
        assert shares[1] > 0 and 95 <= sum(shares) <= 105  # ES steps took time; the shares make the whole
    bad = subprocess.run([sys.executable, script, str(run_dir), "--stage-iterations", "0"], capture_output=True,
                         text=True, timeout=60)
    assert bad.returncode == 2 and "at least 1" in bad.stderr


def test_the_eligibility_table_counts_the_reproductions_and_their_parents(run_dir):
    script = os.path.join(os.environ.get("POET_SOURCE_DIR", ""), "experiments", "eligibility.py")
    done = subprocess.run([sys.executable, script, str(run_dir), "--block", "4"], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    rows = [line.split("|")[1:-1] for line in done.stdout.splitlines() if line.startswith("| ") and "–" in line]
    run = poet.Run(run_dir)
    events = run.events
    reproductions = events[events["event"] == "reproduction"]
    assert sum(int(row[1]) for row in rows) == len(reproductions)  # every reproduction is in a row
    assert sum(int(row[3]) for row in rows) == int(reproductions["admitted"].fillna(0).sum())
    # the run's threshold (-1000) makes every pair eligible: none without a parent, latest and best alike
    assert "≥ -1000" in done.stdout
    for row in rows:
        assert int(row[2]) == 0 and float(row[4]) == float(row[5]) > 0


def test_pair_stats_are_the_rows_the_checkpoint_vouched_for(run_dir, tmp_path):
    # Run reads pair_stats.csv once, with the report's checks (its size and CRC-32 against the checkpoint); what
    # the file says later — a live run appending, or damage — does not change the rows it gives
    import shutil

    copy = tmp_path / "run"
    shutil.copytree(run_dir, copy)
    run = poet.Run(copy)
    before = run.pair_stats
    (copy / "pair_stats.csv").write_text("iteration,pair\n1,2\n")
    assert run.pair_stats.equals(before) and len(before) > 2
    with pytest.raises(ValueError, match="pair_stats.csv"):
        poet.Run(copy)  # read again, the damage is named


def test_the_transfer_value_table_cuts_each_run_at_one_budget(run_dir):
    script = os.path.join(os.environ.get("POET_SOURCE_DIR", ""), "experiments", "transfer_value.py")
    report_bin = binary("POET_REPORT_BIN")
    steps = poet.Run(run_dir).pair_stats["run_env_steps"]
    budget = int(steps.iloc[len(steps) // 2])  # part-way through the run
    done = subprocess.run([sys.executable, script, f"whole={run_dir}", f"cut={run_dir}", "--env-steps", str(budget),
                           "--report", report_bin], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    rows = {line.split("|")[1].strip(): [cell.strip() for cell in line.split("|")[2:-1]]
            for line in done.stdout.splitlines() if line.startswith("| ") and not line.startswith("| |")}
    assert rows["iterations"][0] == rows["iterations"][1]
    assert int(rows["iterations"][0]) < poet.Run(run_dir).next_iteration
    assert float(rows["environment steps"][0].rstrip(" M")) <= budget / 1e6 + 0.05
    assert "ANNECS at admission" in rows and "highest level solved" in rows
    whole = subprocess.run([sys.executable, script, f"a={run_dir}", f"b={run_dir}", "--report", report_bin],
                           capture_output=True, text=True, timeout=300)
    assert whole.returncode == 0 and f"| iterations | {poet.Run(run_dir).next_iteration} |" in whole.stdout
    alone = subprocess.run([sys.executable, script, f"a={run_dir}"], capture_output=True, text=True, timeout=60)
    assert alone.returncode == 2 and "two runs" in alone.stderr
