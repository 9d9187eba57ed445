"""poet.WalkerEnv against Gymnasium's conventions, checked the way its env checker checks them (written here, not
imported), and its answers to hostile arguments."""

import numpy as np
import pytest

import poet


def zero_action():
    return np.zeros(poet.ACT_DIM, dtype=np.float32)


def test_reset_and_step_follow_gymnasiums_signatures_and_types():
    env = poet.WalkerEnv("flat", seed=3)
    obs, info = env.reset()
    assert isinstance(obs, np.ndarray) and obs.dtype == np.float32 and obs.shape == (poet.OBS_DIM,)
    assert isinstance(info, dict) and info["seed"] == 3 and info["steps"] == 0
    assert np.all(obs >= env.observation_low) and np.all(obs <= env.observation_high)
    result = env.step(env.action_high * 0.5)
    assert len(result) == 5
    obs, reward, terminated, truncated, info = result
    assert obs.dtype == np.float32 and obs.shape == (poet.OBS_DIM,)
    assert isinstance(reward, float) and np.isfinite(reward)
    assert isinstance(terminated, bool) and isinstance(truncated, bool)
    assert info["steps"] == 1
    for bound in (env.observation_low, env.observation_high, env.action_low, env.action_high):
        assert bound.dtype == np.float32
    assert env.action_low.shape == env.action_high.shape == (poet.ACT_DIM,)
    assert np.all(env.action_low == -1) and np.all(env.action_high == 1)
    with pytest.raises(ValueError):  # shared by every env: read-only
        env.action_low[0] = 3


def test_a_seed_makes_the_episode_deterministic():
    def episode(seed):
        env = poet.WalkerEnv("hardcore-like")
        obs, _ = env.reset(seed=seed)
        observations, rewards = [obs], []
        rng = np.random.default_rng(7)
        for _ in range(60):
            obs, reward, terminated, truncated, _ = env.step(rng.uniform(-1, 1, poet.ACT_DIM).astype(np.float32))
            observations.append(obs)
            rewards.append(reward)
            if terminated or truncated:
                break
        return np.array(observations), np.array(rewards)

    a_obs, a_rewards = episode(11)
    b_obs, b_rewards = episode(11)
    assert np.array_equal(a_obs, b_obs) and np.array_equal(a_rewards, b_rewards)
    c_obs, _ = episode(12)
    assert not np.array_equal(a_obs[: len(c_obs)], c_obs[: len(a_obs)])


def test_the_seed_stays_until_another_is_given():
    env = poet.WalkerEnv("r3")
    first, _ = env.reset(seed=5)
    again, info = env.reset()
    assert info["seed"] == 5 and np.array_equal(first, again)


def test_time_limit_truncates_and_a_step_after_the_end_is_a_runtime_error():
    env = poet.WalkerEnv("flat", max_steps=5)
    env.reset(seed=0)
    for k in range(5):
        _, _, terminated, truncated, _ = env.step(zero_action())
        assert not terminated
        assert truncated == (k == 4)
    with pytest.raises(RuntimeError, match="after the episode ended"):
        env.step(zero_action())
    env.reset()
    env.step(zero_action())  # a new episode runs again


def test_a_fall_terminates():
    env = poet.WalkerEnv("flat", push_scale=0)
    env.reset(seed=0)
    terminated = False
    for _ in range(400):
        _, reward, terminated, truncated, info = env.step(np.array([1, -1, 1, -1], dtype=np.float32))
        if terminated or truncated:
            break
    assert terminated and not truncated
    assert info["fell"] and reward == -100


def test_step_before_reset_is_a_runtime_error():
    with pytest.raises(RuntimeError, match="before reset"):
        poet.WalkerEnv("flat").step(zero_action())


@pytest.mark.parametrize(
    "action, message",
    [
        (np.zeros(3, dtype=np.float32), "shape"),
        (np.zeros((1, 4), dtype=np.float32), "shape"),
        (np.zeros(4, dtype=np.int64), "floating-point"),
        (np.array([0, np.nan, 0, 0], dtype=np.float32), "not finite"),
        (np.array([0, 0, np.inf, 0]), "not finite"),
        ([0.0, 0.0, 0.0, 0.0], "numpy array"),
    ],
)
def test_bad_actions_are_value_errors(action, message):
    env = poet.WalkerEnv("flat")
    env.reset()
    with pytest.raises(ValueError, match=message):
        env.step(action)
    env.step(zero_action())  # the episode goes on


def test_courses_by_name_file_and_dict(tmp_path):
    definition = {
        "config": {"name": "mine", "ground_roughness": 2.0, "pit_gap": [], "stump_width": [],
                   "stump_height": [], "stump_float": [], "stair_height": [], "stair_width": [],
                   "stair_steps": []},
        "seed": 42,
    }
    from_dict = poet.WalkerEnv(definition)
    assert from_dict.seed == 42
    path = tmp_path / "mine.json"
    path.write_text(__import__("json").dumps(definition))
    from_file = poet.WalkerEnv(path)
    assert np.array_equal(from_dict.reset()[0], from_file.reset()[0])
    assert poet.WalkerEnv(str(path), seed=1).seed == 1


def cppn_course(weight):
    """A CPPN course (Enhanced POET): input -> sin hidden node -> output, and input -> output."""
    empty = {key: [] for key in ("pit_gap", "stump_width", "stump_height", "stump_float", "stair_height",
                                 "stair_width", "stair_steps")}
    genome = {
        "nodes": [{"id": 0, "role": "input"},
                  {"id": 1, "role": "output", "activation": "identity", "bias": 0.0},
                  {"id": 2, "role": "hidden", "activation": "sin", "bias": 0.1}],
        "connections": [{"from": 0, "to": 1, "weight": weight}, {"from": 0, "to": 2, "weight": 1.0},
                        {"from": 2, "to": 1, "weight": 0.5}],
        "scale": 1.0,
    }
    return {"config": {"ground_roughness": 0.0, **empty, "cppn": genome}, "seed": 7}


def test_a_cppn_course_is_walked_and_drawn():
    env = poet.WalkerEnv(cppn_course(0.4))
    obs, _ = env.reset()
    assert obs.shape == (24,)
    for _ in range(5):
        obs, reward, terminated, truncated, _ = env.step(zero_action())
    assert np.isfinite(reward)
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3
    # the genome draws the ground: another weight, another picture of the course
    steeper = poet.WalkerEnv(cppn_course(2.0))
    steeper.reset()
    env.reset()
    assert not np.array_equal(steeper.render(), env.render())


def test_a_hostile_genome_names_the_field():
    bad = cppn_course(0.4)
    bad["config"]["cppn"]["connections"][1]["weight"] = 1e308
    with pytest.raises(ValueError, match=r"cppn.connections\[1\].weight"):
        poet.WalkerEnv(bad)
    cycle = cppn_course(0.4)
    cycle["config"]["cppn"]["connections"].append({"from": 2, "to": 2, "weight": 1.0})
    with pytest.raises(ValueError, match="itself"):
        poet.WalkerEnv(cycle)


@pytest.mark.parametrize(
    "course, error, message",
    [
        ("no-such-course", ValueError, "not a named course"),
        ({"config": {"ground_roughness": "rough"}, "seed": 1}, ValueError, "course"),
        ({"config": {}, "seed": float("nan")}, ValueError, "course"),
        (3, TypeError, "course must be"),
    ],
)
def test_bad_courses_say_what_was_expected(course, error, message):
    with pytest.raises(error, match=message):
        poet.WalkerEnv(course)


def test_a_damaged_environment_file_gives_the_tools_message(tmp_path):
    path = tmp_path / "bad.json"
    path.write_text('{"config": {"ground_roughness": 1}')
    with pytest.raises(ValueError, match=str(path)):
        poet.WalkerEnv(path)


@pytest.mark.parametrize(
    "kwargs, error",
    [
        ({"seed": -1}, ValueError),
        ({"seed": 1_000_000}, ValueError),
        ({"seed": 1.5}, TypeError),
        ({"lidar": "sideways"}, ValueError),
        ({"push_scale": -1.0}, ValueError),
        ({"push_scale": float("nan")}, ValueError),
        ({"max_steps": 0}, ValueError),
    ],
)
def test_bad_settings_are_refused(kwargs, error):
    with pytest.raises(error):
        poet.WalkerEnv("flat", **kwargs)


def test_as_gymnasium_gives_boxes_of_the_bounds_and_delegates(monkeypatch):
    # gymnasium is not a dependency: a stand-in with its Env and spaces.Box shows what the wrapper builds
    import sys
    import types

    class Box:
        def __init__(self, low, high, dtype):
            self.low, self.high, self.dtype = low, high, dtype

    fake = types.ModuleType("gymnasium")
    fake.Env = type("Env", (), {})
    fake.spaces = types.SimpleNamespace(Box=Box)
    monkeypatch.setitem(sys.modules, "gymnasium", fake)
    gym_env = poet.as_gymnasium(poet.WalkerEnv("flat", seed=2))
    assert isinstance(gym_env, fake.Env)
    assert np.array_equal(gym_env.action_space.low, -np.ones(4)) and gym_env.action_space.dtype == np.float32
    assert gym_env.observation_space.low.shape == (poet.OBS_DIM,)
    obs, info = gym_env.reset(seed=4)
    assert info["seed"] == 4 and obs.shape == (poet.OBS_DIM,)
    assert len(gym_env.step([0.0, 0.0, 0.0, 0.0])) == 5
    with pytest.raises(TypeError):
        poet.as_gymnasium("flat")


def test_render_draws_the_current_frame():
    env = poet.WalkerEnv("hardcore-like", seed=3)
    with pytest.raises(RuntimeError, match="before reset"):
        env.render()
    env.reset()
    frame = env.render(width=240, height=160)
    assert frame.dtype == np.uint8 and frame.shape == (160, 240, 3)
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) >= 4  # sky, ground and the walker
    assert np.array_equal(env.render(width=240, height=160), frame)
    for _ in range(40):
        _, _, terminated, truncated, _ = env.step(np.array([0.5, -0.5, 0.5, -0.5], dtype=np.float32))
        if terminated or truncated:
            break
    assert not np.array_equal(env.render(width=240, height=160), frame)  # the last frame of an episode renders
    assert env.render().shape == (400, 600, 3)
    with pytest.raises(ValueError, match="width"):
        env.render(width=3)


def test_every_public_name_has_a_docstring():
    for name in poet.__all__:
        thing = getattr(poet, name)
        if callable(thing):
            assert thing.__doc__, name
            for member_name, member in vars(thing).items() if isinstance(thing, type) else []:
                if not member_name.startswith("_") and (callable(member) or isinstance(member, property)):
                    assert member.__doc__, f"{name}.{member_name}"
    for method in ("reset", "step"):
        assert getattr(poet.WalkerEnv, method).__doc__
