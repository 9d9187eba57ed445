"""poet.VectorWalkerEnv: equal to N single WalkerEnvs stepped one by one (Gymnasium's next-step autoreset
included), whatever the thread count, and its answers to hostile arguments."""

import os
import signal
import time

import numpy as np
import pytest

import poet

COURSES = ["flat", "hardcore-like", "r3"]


def single_env_reference(num_envs, seed, actions, max_steps):
    """What num_envs single envs give for the same actions, with next-step autoreset written out."""
    envs = [poet.WalkerEnv(COURSES[i % len(COURSES)], max_steps=max_steps) for i in range(num_envs)]
    obs = np.array([env.reset(seed=seed + i)[0] for i, env in enumerate(envs)])
    ended = [False] * num_envs
    steps = []
    for batch in actions:
        row = {"obs": [], "reward": [], "terminated": [], "truncated": []}
        for i, env in enumerate(envs):
            if ended[i]:
                o, _ = env.reset()
                r, te, tr = 0.0, False, False
                ended[i] = False
            else:
                o, r, te, tr, _ = env.step(batch[i])
                ended[i] = te or tr
            row["obs"].append(o)
            row["reward"].append(r)
            row["terminated"].append(te)
            row["truncated"].append(tr)
        steps.append({k: np.array(v) for k, v in row.items()})
    return obs, steps


@pytest.mark.parametrize("threads", [1, 3])
def test_equals_single_envs_with_next_step_autoreset(threads):
    num_envs, seed, max_steps = 5, 10, 40
    rng = np.random.default_rng(3)
    actions = rng.uniform(-1, 1, (90, num_envs, poet.ACT_DIM)).astype(np.float32)
    first, expected = single_env_reference(num_envs, seed, actions, max_steps)

    env = poet.VectorWalkerEnv(COURSES, num_envs, threads=threads, max_steps=max_steps)
    obs, info = env.reset(seed=seed)
    assert obs.dtype == np.float32 and obs.shape == (num_envs, poet.OBS_DIM)
    assert np.array_equal(obs, first) and info["seed"].tolist() == list(range(seed, seed + num_envs))
    ends = 0
    for batch, want in zip(actions, expected):
        obs, reward, terminated, truncated, info = env.step(batch)
        assert np.array_equal(obs, want["obs"])
        assert np.array_equal(reward, want["reward"])
        assert np.array_equal(terminated, want["terminated"]) and np.array_equal(truncated, want["truncated"])
        ends += int(terminated.sum() + truncated.sum())
    assert ends >= num_envs  # every walker's episode ended at least once, so autoreset was exercised


def test_hostile_actions_and_order():
    env = poet.VectorWalkerEnv("flat", 2)
    with pytest.raises(RuntimeError, match="before reset"):
        env.step(np.zeros((2, 4), dtype=np.float32))
    env.reset()
    for actions, message in [
        (np.zeros((3, 4), dtype=np.float32), "shape"),
        (np.zeros(4, dtype=np.float32), "shape"),
        (np.zeros((2, 4), dtype=np.int32), "floating-point"),
        (np.array([[0, 0, 0, 0], [0, np.nan, 0, 0]], dtype=np.float32), r"actions\[1, 1\]"),
    ]:
        with pytest.raises(ValueError, match=message):
            env.step(actions)
    env.step(np.zeros((2, 4)))
    for kwargs in ({"num_envs": 0}, {"threads": 0}):
        with pytest.raises(ValueError):
            poet.VectorWalkerEnv("flat", **{"num_envs": 2, **kwargs})
    with pytest.raises(ValueError):
        poet.VectorWalkerEnv([], 2)


def test_hostile_actions_are_named_with_their_shape_and_index():
    env = poet.VectorWalkerEnv("flat", 3)
    env.reset(seed=0)
    for actions, message in [
        ([[0.0] * 4] * 3, r"actions must be a numpy array of shape \(3, 4\)"),
        (np.zeros((4, 3), dtype=np.float32), r"actions must have shape \(3, 4\), got \(4, 3\)"),
        (np.zeros((3, 4, 1), dtype=np.float32), r"got \(3, 4, 1\)"),
        (np.zeros((3, 4), dtype=bool), "floating-point numbers, got dtype bool"),
        (np.array([[0, 0, 0, 0]] * 2 + [[0, 0, 0, -np.inf]]), r"actions\[2, 3\] is not finite"),
    ]:
        with pytest.raises(ValueError, match=message):
            env.step(actions)


def test_any_floating_layout_steps_as_float64_in_c_order():
    # float16, float32 and a transposed (non-contiguous) float64 array are the same actions to the walkers
    actions = np.random.default_rng(5).uniform(-1, 1, (3, poet.ACT_DIM)).astype(np.float16)
    results = []
    for batch in (actions, actions.astype(np.float32), np.asfortranarray(actions.astype(np.float64)),
                  actions.astype(np.float64).T.copy().T):
        env = poet.VectorWalkerEnv(COURSES, 3, threads=2, max_steps=20)
        env.reset(seed=4)
        results.append([env.step(batch)[0] for _ in range(5)])
    for other in results[1:]:
        assert np.array_equal(np.array(other), np.array(results[0]))


def test_more_threads_than_walkers_and_one_walker_up_to_the_last_seed():
    env = poet.VectorWalkerEnv("flat", 1, threads=8)
    _, info = env.reset(seed=999999)  # one walker: every seed below 1000000 leaves it room
    assert info["seed"].tolist() == [999999]
    obs, reward, terminated, truncated, info = env.step(np.zeros((1, poet.ACT_DIM)))
    assert obs.shape == (1, poet.OBS_DIM) and reward.shape == terminated.shape == truncated.shape == (1,)
    assert info["steps"].tolist() == [1]


def test_num_envs_threads_and_max_steps_are_bounded_at_any_size():
    for kwargs, message in [
        ({"num_envs": 10**9}, r"num_envs must be in \[1, 4096\], got 1000000000"),
        ({"num_envs": 4097}, r"num_envs must be in \[1, 4096\]"),
        ({"num_envs": -(2**70)}, r"num_envs must be in \[1, 4096\]"),
        ({"threads": 2**70}, r"threads must be in \[1, 4096\]"),
        ({"max_steps": 2**63}, r"max_steps must be in \[1, 2147483647\], got 9223372036854775808"),
    ]:
        with pytest.raises(ValueError, match=message):
            poet.VectorWalkerEnv("flat", **{"num_envs": 2, **kwargs})


def test_a_seed_is_checked_as_the_user_gave_it():
    # walker i gets seed + i: the last seed that leaves room for both walkers is 999998, and the message says so
    env = poet.VectorWalkerEnv("flat", 2)
    for seed in (999999, -1, 2**63, 2**200):
        with pytest.raises(ValueError, match=r"seed must be in \[0, 999998\] \(walker i gets seed \+ i") as error:
            env.reset(seed=seed)
        assert f"got {seed}" in str(error.value)
    with pytest.raises(ValueError, match="an integer of 16610 bits"):  # too long to print
        env.reset(seed=10**5000)
    _, info = env.reset(seed=999998)
    assert info["seed"].tolist() == [999998, 999999]


def test_autoreset_mode_is_declared_as_gymnasium_names_it():
    assert poet.VectorWalkerEnv.metadata["autoreset_mode"] == "NextStep"  # gymnasium.vector.AutoresetMode.NEXT_STEP


def test_a_forked_child_steps_on_threads_of_its_own():
    # the walkers step on threads kept between steps; a child forked after they started (Python's multiprocessing
    # forks on Linux) has none of them, and must start its own rather than wait for ever
    env = poet.VectorWalkerEnv("hardcore-like", 4, threads=2)
    env.reset(seed=1)
    action = np.full((4, poet.ACT_DIM), 0.3, dtype=np.float32)
    env.step(action)
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:
        code = 1
        try:
            obs, *_ = env.step(action)
            os.write(write_end, obs.tobytes())
            code = 0
        finally:
            os._exit(code)
    os.close(write_end)
    expected, *_ = env.step(action)
    deadline = time.monotonic() + 30
    while (done := os.waitpid(pid, os.WNOHANG))[0] == 0 and time.monotonic() < deadline:
        time.sleep(0.05)
    if done[0] == 0:
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        pytest.fail("the forked child's step did not return in 30 s")
    with os.fdopen(read_end, "rb") as pipe:
        got = np.frombuffer(pipe.read(), dtype=np.float32).reshape(expected.shape)
    assert os.waitstatus_to_exitcode(done[1]) == 0
    assert np.array_equal(got, expected)
