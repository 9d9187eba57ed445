"""The environment's card (docs/reference/environment.md) against the walker: its spaces, the name and range of
every index, the info keys, the id, and its reward and episode end checked step by step on real episodes.
tests/docs/check_python_reference.py checks that the page is what its generator prints; this checks that what it
says is true."""

import pathlib
import re

import numpy as np
import pytest

import poet

CARD = pathlib.Path(__file__).resolve().parents[2] / "docs" / "reference" / "environment.md"
SOFT = 0.05  # radians by which a joint is taken to be at its limit (Box2D's limits are soft)


@pytest.fixture(scope="module")
def card():
    return CARD.read_text(encoding="utf-8")


def section(card, title):
    return card.split(f"## {title}\n", 1)[1].split("\n## ", 1)[0]


def table(text):
    """The rows of the first table in text whose first column is an index: (index, name, low, high)."""
    rows = []
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[0].isdigit():
            rows.append((int(cells[0]), cells[1].strip("`"), float(cells[-2]), float(cells[-1])))
    return rows


def box(card, space):
    return re.search(rf"\| {space} space \| `(Box\(.*\))` \|", card).group(1)


def gym_box(low, high):
    return f"Box({float(low[0])!r}, {float(high[0])!r}, {low.shape}, {low.dtype})"


def test_spaces_are_the_cards(card):
    env = poet.WalkerEnv("flat")
    assert env.observation_low.shape == env.observation_high.shape == (24,) == (poet.OBS_DIM,)
    assert env.action_low.shape == env.action_high.shape == (4,) == (poet.ACT_DIM,)
    for bounds in (env.observation_low, env.observation_high, env.action_low, env.action_high):
        assert bounds.dtype == np.float32 and len(set(bounds.tolist())) == 1
    assert box(card, "Observation") == gym_box(env.observation_low, env.observation_high) \
        == "Box(-inf, inf, (24,), float32)"
    assert box(card, "Action") == gym_box(env.action_low, env.action_high) == "Box(-1.0, 1.0, (4,), float32)"


def test_every_index_is_named_in_order(card):
    observations = table(section(card, "Observation space"))
    actions = table(section(card, "Action space"))
    assert [i for i, *_ in observations] == list(range(24)) and [i for i, *_ in actions] == list(range(4))
    assert tuple(name for _, name, _, _ in observations) == poet.OBSERVATION_NAMES
    assert tuple(name for _, name, _, _ in actions) == poet.ACTION_NAMES
    assert all((low, high) == (-1.0, 1.0) for _, _, low, high in actions)


def test_info_keys_and_id_are_the_cards(card):
    rows = [re.findall(r"`(\w+)`", line) + [line.rstrip().rstrip("|").rsplit("|", 1)[-1].strip()]
            for line in section(card, "Info").splitlines() if line.startswith("| `")]
    keys = [row[0] for row in rows]
    env = poet.WalkerEnv("flat")
    obs, reset_info = env.reset(seed=0)
    step_info = env.step(np.zeros(4, dtype=np.float32))[4]
    assert keys == list(reset_info) == list(step_info)
    _, vector_info = poet.VectorWalkerEnv("flat", 2).reset(seed=0)
    assert {row[0] for row in rows if row[-1] == "yes"} == set(vector_info)
    assert f"| Id | `{poet.WALKER_ID}`" in card
    assert re.search(r"## Version history\n\n- `([^`]+)`", card).group(1) == poet.WALKER_ID


def test_render_and_defaults_are_the_cards(card):
    env = poet.WalkerEnv("flat", render_mode="rgb_array")
    env.reset(seed=0)
    height, width, _ = env.render().shape
    assert f"{width} × {height} pixels" in section(card, "Rendering")
    assert f"{env.metadata['render_fps']} fps" in card and env.metadata["render_fps"] == 50
    assert f"default {poet.DEFAULT_MAX_STEPS}," in section(card, "Episode end")


def reward_formula(card):
    """The card's reward: (forward coefficient, scale, angle coefficient, cost, torque, fall reward)."""
    text = section(card, "Reward")
    forward, scale, angle = re.search(r"shaping\(t\) = ([\d.]+) · x\(t\) / ([\d.]+) − ([\d.]+) · \|hull_angle",
                                      text).groups()
    cost, torque = re.search(r"− ([\d.]+) · ([\d.]+) · Σ_j min\(\|a_j\|, 1\)", text).groups()
    fall = re.search(r"reward\(t\)  = (-?[\d.]+) +if the walker fell", text).group(1)
    return tuple(float(v) for v in (forward, scale, angle, cost, torque, fall))


def episode(env, seed, act):
    """Every step of an episode: (obs before, action, obs, reward, terminated, truncated, info before, info)."""
    obs, info = env.reset(seed=seed)
    steps, done = [], False
    while not done:
        action = act(obs)
        new_obs, reward, terminated, truncated, new_info = env.step(action)
        steps.append((obs, action, new_obs, reward, terminated, truncated, info, new_info))
        obs, info, done = new_obs, new_info, terminated or truncated
    return steps


def check_episode(card, steps):
    forward, scale, angle, cost, torque, fall = reward_formula(card)
    finish_x = float(re.search(r"x > finish_x = ([\d.]+) m", card).group(1))
    ranges = table(section(card, "Observation space"))
    for before, action, obs, reward, terminated, truncated, info_before, info in steps:
        shaping = forward * info["x"] / scale - angle * abs(float(obs[0]))
        previous = forward * info_before["x"] / scale - angle * abs(float(before[0]))
        expected = shaping - previous - cost * torque * float(np.sum(np.minimum(np.abs(action.astype(np.float64)),
                                                                                  1)))
        assert reward == (fall if info["fell"] else pytest.approx(expected, abs=1e-6))
        assert terminated == (info["fell"] or info["finished"]) and not (terminated and truncated)
        if info["finished"]:
            assert info["x"] > finish_x - 1e-3
        for index, name, low, high in ranges:
            assert low <= obs[index] <= high, f"{name} = {obs[index]} outside [{low}, {high}]"
        for name in ("leg1_contact", "leg2_contact"):
            assert obs[poet.OBSERVATION_NAMES.index(name)] in (0.0, 1.0)
    return [step[2] for step in steps]


def joints_within_their_soft_limits(card, observations):
    """The share of steps whose hip and knee angles are within the card's limits (the knees' + 1), give or take
    SOFT radians."""
    hip = [float(v) for v in re.search(r"hips' limits are \[(\S+), (\S+)\] rad", card).groups()]
    knee = [float(v) + 1 for v in re.search(r"knees' \[(\S+), (\S+)\] rad", card).groups()]
    names = {"hip1_angle": hip, "hip2_angle": hip, "knee1_angle": knee, "knee2_angle": knee}
    within = [all(limits[0] - SOFT <= obs[poet.OBSERVATION_NAMES.index(n)] <= limits[1] + SOFT
                  for n, limits in names.items()) for obs in observations]
    return sum(within) / len(within)


def test_a_random_walker_falls_as_the_card_says(card):
    rng = np.random.default_rng(0)
    env = poet.WalkerEnv("hardcore-like")
    falls, observations = 0, []
    for seed in range(3):
        steps = episode(env, seed, lambda obs: rng.uniform(-1.5, 1.5, 4).astype(np.float32))  # beyond ±1: clipped
        observations += check_episode(card, steps)
        falls += steps[-1][-1]["fell"]
    assert falls, "no random walker fell: the fall's reward went unchecked"
    assert joints_within_their_soft_limits(card, observations) > 0.9


def test_a_trained_walker_finishes_and_is_truncated_as_the_card_says(card, walker_path):
    walker = poet.Policy.load(str(walker_path))
    steps = episode(poet.WalkerEnv("flat"), 0, walker.act)
    assert joints_within_their_soft_limits(card, check_episode(card, steps)) > 0.9
    assert steps[-1][-1]["finished"] and steps[-1][4], "the flat walker did not finish the flat course"
    steps = episode(poet.WalkerEnv("flat", max_steps=50), 0, walker.act)
    check_episode(card, steps)
    assert len(steps) == 50 and steps[-1][5] and steps[-1][-1]["steps"] == 50
