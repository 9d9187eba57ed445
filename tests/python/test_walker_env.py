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
    env = poet.WalkerEnv(cppn_course(0.4), render_mode="rgb_array")
    obs, _ = env.reset()
    assert obs.shape == (24,)
    for _ in range(5):
        obs, reward, terminated, truncated, _ = env.step(zero_action())
    assert np.isfinite(reward)
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3
    # the genome draws the ground: another weight, another picture of the course
    steeper = poet.WalkerEnv(cppn_course(2.0), render_mode="rgb_array")
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


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"seed": 2**200}, r"seed must be in \[0, 999999\], got 16069380442589902755419620923411626025"),
        ({"max_steps": 2**63}, r"max_steps must be in \[1, 2147483647\], got 9223372036854775808"),
        ({"width": 2**64}, r"width must be in \[16, 4096\]"),
        ({"height": -(2**64)}, r"height must be in \[16, 4096\]"),
    ],
)
def test_integers_past_what_cpp_holds_are_value_errors_with_the_range(kwargs, message):
    with pytest.raises(ValueError, match=message):
        poet.WalkerEnv("flat", **kwargs)


def test_a_seed_of_any_size_at_reset_is_a_value_error():
    env = poet.WalkerEnv("flat")
    for seed in (2**63, 2**200, -(2**64)):
        with pytest.raises(ValueError, match=r"seed must be in \[0, 999999\]"):
            env.reset(seed=seed)
    env.reset(seed=999999)
    assert env.seed == 999999


def test_render_draws_the_current_frame_in_the_mode_chosen_when_made():
    env = poet.WalkerEnv("hardcore-like", seed=3, render_mode="rgb_array", width=240, height=160)
    assert env.render_mode == "rgb_array" and env.render_mode in env.metadata["render_modes"]
    assert env.metadata["render_fps"] == 50  # the walker's 50 steps a second
    with pytest.raises(RuntimeError, match="before reset"):
        env.render()
    env.reset()
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.shape == (160, 240, 3)
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) >= 4  # sky, ground and the walker
    assert np.array_equal(env.render(), frame)
    for _ in range(40):
        _, _, terminated, truncated, _ = env.step(np.array([0.5, -0.5, 0.5, -0.5], dtype=np.float32))
        if terminated or truncated:
            break
    assert not np.array_equal(env.render(), frame)  # the last frame of an episode renders
    default = poet.WalkerEnv("flat", render_mode="rgb_array")
    default.reset()
    assert default.render().shape == (400, 600, 3)
    # without a render mode (Gymnasium's default), render() warns and returns None
    plain = poet.WalkerEnv("flat")
    plain.reset()
    assert plain.render_mode is None
    with pytest.warns(UserWarning, match="render_mode"):
        assert plain.render() is None


@pytest.mark.parametrize(
    "kwargs, error, message",
    [
        ({"render_mode": "human"}, ValueError, "render_mode"),
        ({"render_mode": 1}, ValueError, "render_mode"),
        ({"width": 3}, ValueError, "width"),
        ({"height": 5000}, ValueError, "height"),
        ({"width": 2.5}, TypeError, "width"),
    ],
)
def test_rendering_is_settled_when_the_env_is_made(kwargs, error, message):
    with pytest.raises(error, match=message):
        poet.WalkerEnv("flat", **kwargs)


def test_np_random_is_seeded_as_gymnasium_seeds_it():
    # gymnasium's env checker (check_reset_seed_determinism), written out: the same seed gives the same episode
    # start and the same generator, reset() without a seed leaves the generator alone, another seed changes it
    env = poet.WalkerEnv("hardcore-like")
    obs_1, _ = env.reset(seed=123)
    rng_1 = env.np_random.bit_generator.state
    obs_2, _ = env.reset()
    assert env.np_random.bit_generator.state == rng_1
    obs_3, _ = env.reset(seed=123)
    rng_3 = env.np_random.bit_generator.state
    obs_4, _ = env.reset()
    assert np.array_equal(obs_1, obs_3) and np.array_equal(obs_2, obs_4)
    assert rng_1 == rng_3 and env.np_random_seed == 123
    env.reset(seed=456)
    assert env.np_random.bit_generator.state != rng_1
    # gymnasium.utils.seeding.np_random(123)'s generator: PCG64 over SeedSequence(123)
    expected = np.random.Generator(np.random.PCG64(np.random.SeedSequence(123)))
    env.reset(seed=123)
    assert env.np_random.random() == expected.random()
    # unseeded: a generator from fresh entropy, made once
    fresh = poet.WalkerEnv("flat")
    assert fresh.np_random is fresh.np_random and isinstance(fresh.np_random_seed, int)
    with pytest.raises(ValueError):  # a seed the course cannot take leaves the generator as it was
        env.reset(seed=-1)
    assert env.np_random_seed == 123


def test_step_is_deterministic_after_a_seeded_reset():
    # gymnasium's check_step_determinism: the same seed and action give the same step, info included
    env = poet.WalkerEnv("hardcore-like")
    action = np.array([0.3, -0.8, 0.1, 0.9], dtype=np.float32)
    env.reset(seed=9)
    first = env.step(action)
    env.reset(seed=9)
    second = env.step(action)
    assert np.array_equal(first[0], second[0]) and first[1:4] == second[1:4] and first[4] == second[4]


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
