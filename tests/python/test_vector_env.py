"""poet.VectorWalkerEnv: equal to N single WalkerEnvs stepped one by one (Gymnasium's next-step autoreset
included), whatever the thread count, and its answers to hostile arguments."""

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
