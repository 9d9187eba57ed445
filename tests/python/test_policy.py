"""poet.Policy, poet.evaluate and poet.evaluate_suite: the shipped walker's numbers equal poet-eval's, bit for bit,
whatever the thread count; damaged policy files give the tools' messages."""

import json
import subprocess

import numpy as np
import pytest

import poet


def test_a_policy_acts_on_an_observation(walker_path):
    policy = poet.Policy.load(str(walker_path))
    assert policy.params.shape == (2804,) and policy.params.dtype == np.float64
    obs, _ = poet.WalkerEnv("flat").reset(seed=0)
    action = policy.act(obs)
    assert action.dtype == np.float32 and action.shape == (poet.ACT_DIM,)
    assert np.all(np.abs(action) <= 1)
    with pytest.raises(ValueError, match="shape"):
        policy.act(obs[:10])


def test_a_walk_through_the_environment_finishes_the_flat_course(walker_path):
    policy = poet.Policy.load(str(walker_path))
    env = poet.WalkerEnv("flat")
    obs, _ = env.reset(seed=0)
    total, terminated, truncated, info = 0.0, False, False, {}
    while not (terminated or truncated):
        obs, reward, terminated, truncated, info = env.step(policy.act(obs))
        total += reward
    assert info["finished"] and total > 230


def test_evaluate_equals_poet_eval_bit_for_bit(walker_path, eval_bin):
    policy = poet.Policy.load(str(walker_path))
    for course in ("flat", "hardcore-like"):
        printed = subprocess.run(
            [eval_bin, "--policy", str(walker_path), "--course", course, "--seeds", "3:8", "--json", "-"],
            check=True, capture_output=True, text=True, timeout=120).stdout
        reference = json.loads(printed)["courses"][0]
        ours = poet.evaluate(policy, course, range(3, 9), threads=2)
        assert ours["return"].tolist() == reference["returns"]  # floats parsed from JSON: exact equality
        assert ours["steps"].tolist() == reference["steps"]
        assert [3 + i for i in np.flatnonzero(ours["finished"])] == reference["finished_seeds"]
        assert int(ours["fell"].sum()) == reference["fell"]


def test_evaluate_does_not_depend_on_the_thread_count(walker_path):
    policy = poet.Policy.load(str(walker_path))
    one = poet.evaluate(policy, "r3", [0, 5, 9], threads=1, max_steps=300)
    three = poet.evaluate(policy, "r3", [0, 5, 9], threads=3, max_steps=300)
    for key in ("return", "steps", "finished", "fell"):
        assert np.array_equal(one[key], three[key])
    assert one["return"].dtype == np.float64 and one["steps"].dtype == np.int64 and one["fell"].dtype == bool


def test_evaluate_suite_equals_poet_eval_suite_bit_for_bit(walker_path, eval_bin):
    policy = poet.Policy.load(str(walker_path))
    assert "poet-suite-v1" in poet.suite_names()
    printed = subprocess.run(
        [eval_bin, "--policy", str(walker_path), "--suite", "poet-suite-v1", "--max-steps", "60", "--threads", "2",
         "--json", "-"],
        check=True, capture_output=True, text=True, timeout=120).stdout
    reference = json.loads(printed)
    ours = poet.evaluate_suite(policy, "poet-suite-v1", threads=1, max_steps=60)
    for key in ("policy", "push_scale", "lidar", "max_steps"):  # the command line's, not the suite's
        del reference[key]
    assert ours == reference  # floats parsed from JSON on both sides: exact equality
    assert [g["group"] for g in ours["groups"]] == [
        "easy", "challenging", "very challenging", "extremely challenging", "hardcore-like"]
    assert sum(len(c["episodes"]) for g in ours["groups"] for c in g["courses"]) == ours["episodes"] == 500


def test_evaluate_suite_refuses_bad_arguments(walker_path):
    policy = poet.Policy.load(str(walker_path))
    with pytest.raises(ValueError, match="unknown suite 'poet-suite-v0'"):
        poet.evaluate_suite(policy, "poet-suite-v0")
    with pytest.raises(TypeError):
        poet.evaluate_suite(policy, 1)
    with pytest.raises(TypeError):
        poet.evaluate_suite("not a policy", "poet-suite-v1")
    with pytest.raises(ValueError):
        poet.evaluate_suite(policy, "poet-suite-v1", threads=0)
    with pytest.raises(ValueError, match="max_steps"):
        poet.evaluate_suite(policy, "poet-suite-v1", max_steps=10**7)


@pytest.mark.parametrize(
    "text, message",
    [("", "policy"), ("[[1, 2, 3], 1]", "2804"), ("not json", "")],
)
def test_damaged_policy_files_are_value_errors(tmp_path, text, message):
    path = tmp_path / "policy.json"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        poet.Policy.load(str(path))


def test_a_missing_policy_file_names_its_path(tmp_path):
    with pytest.raises(ValueError, match="missing.json"):
        poet.Policy.load(str(tmp_path / "missing.json"))


def test_evaluate_refuses_bad_arguments(walker_path):
    policy = poet.Policy.load(str(walker_path))
    with pytest.raises(TypeError):
        poet.evaluate("not a policy", "flat", [0])
    with pytest.raises(ValueError):
        poet.evaluate(policy, "flat", [-3])
    with pytest.raises(ValueError):
        poet.evaluate(policy, "flat", [0], threads=0)
    # integers past what C++ holds: the module's ValueError with the range, not pybind11's TypeError
    with pytest.raises(ValueError, match=r"seed must be in \[0, 999999\], got 1180591620717411303424"):
        poet.evaluate(policy, "flat", [0, 2**70])
    with pytest.raises(ValueError, match=r"max_steps must be in \[1, 1000000\], got 9223372036854775808"):
        poet.evaluate(policy, "flat", [0], max_steps=2**63)
    with pytest.raises(ValueError, match=r"threads must be in \[1, 4096\]"):
        poet.evaluate_suite(policy, "poet-suite-v1", threads=2**64)


def test_the_reference_walkers_files_load():
    import os
    import pathlib

    if not os.environ.get("POET_REFERENCE_DIR"):
        pytest.skip("POET_REFERENCE_DIR is not set (the reference data is optional; tests/README.md)")
    reference = pathlib.Path(os.environ["POET_REFERENCE_DIR"]) / "estool-zoo" / "zoo"
    path = reference / "biped.cma.1.96.best.json"
    if not path.is_file():
        pytest.skip(f"no reference data at {reference} (POET_REFERENCE_DIR; see tests/README.md)")
    policy = poet.Policy.load(str(path))
    assert policy.params.shape == (2804,)
    result = poet.evaluate(policy, "flat", [0, 1], threads=2)
    assert result["finished"].all()  # the reference's flat walker finishes flat, as the alignment tests check
