"""poet: the POET bipedal walker and its courses from Python.

WalkerEnv follows Gymnasium's API (reset/step, terminated and truncated) without depending on gymnasium;
Policy and evaluate give the numbers poet-eval prints. The C++ core is poet._poet.
"""

import json
import os
import warnings

import numpy as np

from . import _poet
from ._poet import ACT_DIM, DEFAULT_MAX_STEPS, DEFAULT_PUSH_SCALE, OBS_DIM, Policy
from .launch import Coordinator, CoordinatorError, start

__all__ = ["WalkerEnv", "VectorWalkerEnv", "Policy", "evaluate", "evaluate_suite", "suite_names", "Run", "as_gymnasium", "start", "Coordinator", "CoordinatorError", "OBS_DIM", "ACT_DIM"]


def _course(course):
    """A named course, an environment file (path) or a dict in the environment file's schema."""
    if isinstance(course, dict):
        try:
            text = json.dumps(course, allow_nan=False)
        except (TypeError, ValueError) as error:
            raise ValueError(f"course: not an environment definition ({error})") from None
        return _poet._course_from_json_text(text)
    if isinstance(course, (str, os.PathLike)):
        return _poet._course_from_name_or_file(os.fspath(course))
    raise TypeError(
        "course must be a course name, an environment file's path or a dict "
        f"{{'config': {{...}}, 'seed': s}}, got {type(course).__name__}"
    )


def _whole(value, name):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    return int(value)


def _optional_whole(value, name):
    return None if value is None else _whole(value, name)


def _number(value, name):
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise TypeError(f"{name} must be a number, got {type(value).__name__}")
    return float(value)


def _read_only(array):
    """The bounds are shared by every environment: no one may change them in place."""
    array.setflags(write=False)
    return array


class _Episodes:
    """reset and step of an environment of the C++ core (self._env), with the seed's type checked, and Gymnasium's
    np_random: a generator seeded as gymnasium.Env.reset seeds it, for wrappers and users (the walker's own
    randomness, its course and initial push, comes from the terrain seed)."""

    _np_random = None
    _np_random_seed = None

    def reset(self, *, seed=None, options=None):
        """A new episode: (obs, info). A seed picks the terrain (and initial push) for this and later episodes,
        and seeds np_random; options must be None or a dict (none are read)."""
        if seed is not None:
            seed = _whole(seed, "seed")
        result = self._env.reset(seed, options)
        if seed is not None:
            self._np_random, self._np_random_seed = _seeded_generator(seed)
        return result

    def step(self, action):
        """One step: (obs, reward, terminated, truncated, info). RuntimeError outside an episode, ValueError for
        an action of the wrong shape or dtype or not finite."""
        return self._env.step(action)

    @property
    def np_random(self):
        """numpy Generator: seeded by reset(seed=...), otherwise from fresh entropy at first use (Gymnasium's
        np_random)."""
        if self._np_random is None:
            self._np_random, self._np_random_seed = _seeded_generator(None)
        return self._np_random

    @property
    def np_random_seed(self):
        """The seed np_random was made from (its entropy when none was given)."""
        if self._np_random is None:
            self._np_random, self._np_random_seed = _seeded_generator(None)
        return self._np_random_seed


def _seeded_generator(seed):
    """gymnasium.utils.seeding.np_random's generator: PCG64 over SeedSequence(seed), and the seed's entropy."""
    sequence = np.random.SeedSequence(seed)
    return np.random.Generator(np.random.PCG64(sequence)), sequence.entropy


class WalkerEnv(_Episodes):
    """The bipedal walker on one course, with Gymnasium's conventions.

    reset(seed=None, options=None) -> (obs, info); step(action) -> (obs, reward, terminated, truncated, info).
    obs is float32 of shape (24,), action float32 of shape (4,). terminated: the walker fell or crossed the
    finish line; truncated: max_steps steps were taken. A seed picks the course's terrain (and initial push); it
    stays for later episodes until another is given. info holds seed, steps, x (the hull's position), finished
    and fell. render_mode "rgb_array" makes render() return frames of width × height pixels (600 × 400 unless
    given).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 50}
    observation_low = _read_only(np.full(OBS_DIM, -np.inf, dtype=np.float32))
    observation_high = _read_only(np.full(OBS_DIM, np.inf, dtype=np.float32))
    action_low = _read_only(np.full(ACT_DIM, -1.0, dtype=np.float32))
    action_high = _read_only(np.full(ACT_DIM, 1.0, dtype=np.float32))

    def __init__(self, course, *, seed=None, render_mode=None, lidar="nearest", push_scale=DEFAULT_PUSH_SCALE,
                 max_steps=DEFAULT_MAX_STEPS, width=None, height=None):
        if seed is not None:
            seed = _whole(seed, "seed")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or one of {self.metadata['render_modes']}, got {render_mode!r}")
        if not isinstance(lidar, str):
            raise TypeError(f"lidar must be 'nearest' or 'first', got {type(lidar).__name__}")
        self.render_mode = render_mode
        self._env = _poet._WalkerEnv(_course(course), seed, lidar, _number(push_scale, "push_scale"),
                                     _whole(max_steps, "max_steps"), _optional_whole(width, "width"),
                                     _optional_whole(height, "height"))

    @property
    def seed(self):
        """The terrain seed of the current (or next) episode."""
        return self._env.seed

    @property
    def max_steps(self):
        """Steps after which an episode is truncated."""
        return self._env.max_steps

    def render(self):
        """With render_mode "rgb_array", the current frame as uint8 RGB of shape (height, width, 3): the walker on
        its course as the project's pictures draw it (the camera follows the hull); RuntimeError before reset.
        Without a render mode, None and a warning (Gymnasium's rule: the mode is chosen when the env is made)."""
        if self.render_mode is None:
            warnings.warn("render() without a render mode: make the env with render_mode='rgb_array'", stacklevel=2)
            return None
        return self._env.render()


def evaluate(policy, course, seeds, *, threads=1, lidar="nearest", push_scale=DEFAULT_PUSH_SCALE,
             max_steps=DEFAULT_MAX_STEPS):
    """The policy's episodes on the course, one per terrain seed, on `threads` threads.

    Returns a dict of numpy arrays in the seeds' order: "return" (float64), "steps" (int64), "finished" and
    "fell" (bool) — the numbers poet-eval prints, bit for bit. The result does not depend on `threads`.
    """
    if not isinstance(policy, Policy):
        raise TypeError(f"policy must be a poet.Policy, got {type(policy).__name__}")
    seeds = [_whole(s, "each seed") for s in seeds]
    return _poet._evaluate(policy, _course(course), seeds, _whole(threads, "threads"), lidar,
                           _number(push_scale, "push_scale"), _whole(max_steps, "max_steps"))


def suite_names():
    """The names of the held-out test suites this build knows, for evaluate_suite and poet-eval --suite."""
    return list(_poet._suite_names())


def evaluate_suite(policy, suite, *, threads=1, lidar="nearest", push_scale=DEFAULT_PUSH_SCALE,
                   max_steps=DEFAULT_MAX_STEPS):
    """The policy on the held-out test suite named `suite` (one of suite_names()), on `threads` threads.

    Returns poet-eval --suite --json's document, bit for bit: "suite", "episodes", "finished",
    "finished_fraction", "mean_return" and "groups", each group with its fraction finished and 95% interval,
    its mean return with its own and every episode under "courses". The result does not depend on `threads`.
    """
    if not isinstance(policy, Policy):
        raise TypeError(f"policy must be a poet.Policy, got {type(policy).__name__}")
    if not isinstance(suite, str):
        raise TypeError(f"suite must be a suite's name, got {type(suite).__name__}")
    return json.loads(_poet._evaluate_suite(policy, suite, _whole(threads, "threads"), lidar,
                                            _number(push_scale, "push_scale"), _whole(max_steps, "max_steps")))


def as_gymnasium(env):
    """A gymnasium.Env around a WalkerEnv, for a user who has gymnasium (this package does not depend on it):
    observation_space and action_space are Boxes of the env's bounds, reset seeds np_random through
    gymnasium.Env.reset, step and render are the env's. With gymnasium installed, gymnasium.make("poet/Walker-v0",
    course=...) makes one too."""
    if not isinstance(env, WalkerEnv):
        raise TypeError(f"env must be a poet.WalkerEnv, got {type(env).__name__}")
    from .gymnasium_env import GymnasiumWalker  # imports gymnasium: only this function and make need it

    return GymnasiumWalker(walker=env)


class VectorWalkerEnv(_Episodes):
    """num_envs walkers stepped together on `threads` C++ threads (the GIL released), batched numpy in and out.

    reset(seed=None) -> (obs (num_envs, 24) float32, info); step(actions (num_envs, 4)) -> (obs, rewards,
    terminated, truncated, info), each an array of num_envs. Walker i runs courses[i % len(courses)]; a seed gives
    walker i seed + i, so it is at most 999999 - (num_envs - 1). Gymnasium's next-step autoreset: the step after a
    walker's episode ends resets it (its action is ignored) and reports its first observation with reward 0, neither
    terminated nor truncated. info holds arrays seed, steps, finished and fell. num_envs is at most 4096 (each
    walker holds some 220 KB) and threads at most 4096; integers out of range, of any size, are ValueError.
    """

    metadata = {"autoreset_mode": "NextStep", "render_modes": []}  # gymnasium.vector.AutoresetMode.NEXT_STEP

    def __init__(self, courses, num_envs, *, threads=1, lidar="nearest", push_scale=DEFAULT_PUSH_SCALE,
                 max_steps=DEFAULT_MAX_STEPS):
        if isinstance(courses, (str, dict, os.PathLike)):
            courses = [courses]
        courses = [_course(c) for c in courses]
        self._env = _poet._VectorWalkerEnv(courses, _whole(num_envs, "num_envs"), _whole(threads, "threads"),
                                           lidar, _number(push_scale, "push_scale"), _whole(max_steps, "max_steps"))
        self.single_observation_low = WalkerEnv.observation_low
        self.single_observation_high = WalkerEnv.observation_high
        self.single_action_low = WalkerEnv.action_low
        self.single_action_high = WalkerEnv.action_high

    @property
    def num_envs(self):
        """How many walkers step together."""
        return self._env.num_envs


class Run:
    """A run directory, read-only: live or finished, it takes no lock and writes nothing. A live run is read as
    of its last checkpoint, as poet-report reads it.

    pairs, events, pair_stats, levels and annecs are pandas DataFrames (pandas is imported when one is asked for);
    report is poet-report's JSON document as a dict; encoding(pair) and theta(pair) give a pair's environment
    (the environment file's dict) and its θ; config is the run's config in protobuf text format. ValueError, with
    the report's message, for a directory that is not a readable run.
    """

    def __init__(self, path):
        if not isinstance(path, (str, os.PathLike)):
            raise TypeError(f"path must be a run directory's path, got {type(path).__name__}")
        self.path = os.fspath(path)
        view = _poet._read_run(self.path)
        self.report = json.loads(view["report"])
        self.config = view["config"]
        self.live = view["live"]
        self.next_iteration = view["next_iteration"]
        self._events = json.loads(view["events"])
        self._pair_stats = view["pair_stats"]
        self._pairs = {p["id"]: p for p in view["pairs"]}

    def _pair(self, pair):
        try:
            return self._pairs[_whole(pair, "pair")]
        except KeyError:
            raise ValueError(f"no pair {pair} in {self.path}") from None

    def encoding(self, pair):
        """The pair's environment as a dict in the environment file's schema ({"config": {...}, "seed": s})."""
        return json.loads(self._pair(pair)["env"])

    def theta(self, pair, *, best=False):
        """The pair's θ (or the best θ it has had) as a float64 array."""
        return self._pair(pair)["best_theta" if best else "theta"].copy()

    @property
    def pairs(self):
        """A row per pair ever created, as poet-report lists them."""
        import pandas as pd

        return pd.DataFrame(self.report["pairs"]).set_index("id")

    @property
    def events(self):
        """A row per event the checkpoint has seen (events.jsonl), fields as columns."""
        import pandas as pd

        return pd.DataFrame(self._events)

    @property
    def pair_stats(self):
        """A row per ES step (pair_stats.csv), the rows the checkpoint has seen, as the report read them (their
        size and CRC-32 checked against the checkpoint)."""
        import io

        import pandas as pd

        return pd.read_csv(io.BytesIO(self._pair_stats))

    @property
    def levels(self):
        """poet-report's metrics per difficulty level: created, passed the MC, admitted, solved, iterations to
        solve, and when each was first reached."""
        import pandas as pd

        rows = []
        for level in self.report["levels"]:
            row = {k: v for k, v in level.items() if not isinstance(v, dict) and v is not None}
            for k, v in level["iterations_to_solve"].items():
                row[f"iterations_to_solve_{k}"] = v
            for first in ("first_created", "first_admitted", "first_solved"):
                row[f"{first}_iteration"] = level[first]["iteration"] if level[first] else None
            rows.append(row)
        return pd.DataFrame(rows).set_index("level")

    @property
    def annecs(self):
        """ANNECS at the end of each iteration in both of its peers' definitions, at_admission and at_archiving
        (report["annecs"] states each): a row per iteration, as the run's annecs.csv holds them."""
        import pandas as pd

        frame = pd.DataFrame(self.report["annecs"]["over_time"], columns=["iteration", "at_admission", "at_archiving"])
        return frame.set_index("iteration")


def _register_with_gymnasium():
    """Registers poet/Walker-v0 when gymnasium is importable, so that gymnasium.make finds it after `import poet`."""
    import importlib.util

    if importlib.util.find_spec("gymnasium") is not None:
        from .gymnasium_env import register

        register()


_register_with_gymnasium()
