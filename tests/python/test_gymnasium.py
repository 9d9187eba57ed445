"""poet with gymnasium: poet/Walker-v0 registered on import and made by gymnasium.make, the wrapper's spaces,
seeding and rendering. gymnasium is not in Debian: these run against a stand-in written to its rules
(gymnasium_stand_in/) in a child process, and gymnasium's own env checker runs when gymnasium is installed."""

import importlib.util
import os
import pathlib
import subprocess
import sys

import pytest

import poet

STAND_IN = pathlib.Path(__file__).resolve().parent / "gymnasium_stand_in"

CHILD = r"""
import warnings
import numpy as np
import gymnasium
import poet

assert "poet/Walker-v0" in gymnasium.registry, "import poet registers its id"
env = gymnasium.make("poet/Walker-v0", course="hardcore-like", render_mode="rgb_array", width=200, height=100)
assert isinstance(env, gymnasium.Env) and env.spec.kwargs["course"] == "hardcore-like"
assert env.observation_space.dtype == np.float32 and env.observation_space.shape == (24,)
assert env.action_space.dtype == np.float32 and env.action_space.shape == (4,)
assert np.all(env.action_space.low == -1) and np.all(env.action_space.high == 1)

obs_1, info = env.reset(seed=123)
assert env.observation_space.contains(obs_1) and info["seed"] == 123
rng_1 = env.unwrapped._np_random.bit_generator.state   # gymnasium.Env.reset seeded it
obs_2, _ = env.reset()
obs_3, _ = env.reset(seed=123)
assert np.array_equal(obs_1, obs_3) and env.unwrapped._np_random.bit_generator.state == rng_1
env.reset(seed=456)
assert env.unwrapped._np_random.bit_generator.state != rng_1

obs, reward, terminated, truncated, info = env.step(env.action_space.low * 0.5)  # a float32 array
assert env.observation_space.contains(obs) and isinstance(reward, float)
obs, *_ = env.step([0.0, 0.0, 0.0, 0.0])                                        # a list, as samplers give
frame = env.render()
assert frame.dtype == np.uint8 and frame.shape == (100, 200, 3)

# the checker remakes the env from its spec in each render mode
again = env.spec.make(render_mode="rgb_array")
again.reset(seed=1)
assert again.render().shape == (100, 200, 3)
plain = gymnasium.make("poet/Walker-v0")
plain.reset()
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    assert plain.render() is None and caught

wrapped = poet.as_gymnasium(poet.WalkerEnv("flat", seed=2))
assert isinstance(wrapped, gymnasium.Env) and wrapped.reset(seed=4)[1]["seed"] == 4
try:
    poet.as_gymnasium("flat")
except TypeError:
    pass
else:
    raise AssertionError("as_gymnasium took a course name")
print("ok")
"""


def test_registered_and_made_by_gymnasiums_rules():
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(STAND_IN), os.environ.get("PYTHONPATH", "")]))
    child = subprocess.run([sys.executable, "-c", CHILD], env=env, capture_output=True, text=True, timeout=120)
    assert child.returncode == 0 and child.stdout.strip() == "ok", child.stderr


def test_without_gymnasium_import_poet_works_and_the_wrapper_says_what_is_missing():
    if importlib.util.find_spec("gymnasium") is not None:
        pytest.skip("gymnasium is installed here: nothing to show without it")
    code = "import poet\ntry:\n    poet.as_gymnasium(poet.WalkerEnv('flat'))\nexcept ImportError as e:\n    print(e.name)"
    child = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert child.returncode == 0 and child.stdout.strip() == "gymnasium", child.stderr


def test_gymnasiums_own_env_checker_passes():
    gymnasium = pytest.importorskip(
        "gymnasium", reason="gymnasium is not installed (it is not in Debian): its env checker runs when it is")
    from gymnasium.utils.env_checker import check_env

    check_env(gymnasium.make("poet/Walker-v0", course="hardcore-like", render_mode="rgb_array").unwrapped)
    check_env(gymnasium.make("poet/Walker-v0", course="flat").unwrapped, skip_render_check=True)
    assert isinstance(poet.as_gymnasium(poet.WalkerEnv("flat")), gymnasium.Env)
