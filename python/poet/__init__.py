"""poet: the POET bipedal walker and its courses from Python.

WalkerEnv follows Gymnasium's API (reset/step, terminated and truncated) without depending on gymnasium;
Policy and evaluate give the numbers poet-eval prints; Run reads a run directory and start runs poet-coordinator.
The C++ core is poet._poet.

Attributes:
    OBS_DIM (int): the length of an observation.
    ACT_DIM (int): the length of an action.
    OBSERVATION_NAMES (tuple of str): the name of each observation index, in order (hull_angle, ..., lidar9).
    ACTION_NAMES (tuple of str): the name of each action index, in order (hip1_torque, ..., knee2_torque).
    DEFAULT_MAX_STEPS (int): the steps after which an episode is truncated unless max_steps says otherwise.
    DEFAULT_PUSH_SCALE (float): the bound of the walker's initial horizontal push, in newtons, unless push_scale
        says otherwise.
    WALKER_ID (str): the id under which, with gymnasium installed, `import poet` registers the walker.
    __version__ (str): the project's version.

Example:
    >>> poet.OBS_DIM, poet.ACT_DIM
    (24, 4)
    >>> poet.OBSERVATION_NAMES[:2], poet.ACTION_NAMES[0]
    (('hull_angle', 'hull_angular_velocity'), 'hip1_torque')
    >>> poet.DEFAULT_MAX_STEPS, poet.DEFAULT_PUSH_SCALE, poet.WALKER_ID
    (2000, 5.0, 'poet/Walker-v0')
"""

import json
import os
import warnings

import numpy as np

from . import _poet
from ._poet import ACT_DIM, ACTION_NAMES, DEFAULT_MAX_STEPS, DEFAULT_PUSH_SCALE, OBS_DIM, OBSERVATION_NAMES, Policy
from .launch import Coordinator, CoordinatorError, start

__all__ = ["WalkerEnv", "VectorWalkerEnv", "Policy", "evaluate", "evaluate_suite", "suite_names", "Run", "as_gymnasium",
           "start", "Coordinator", "CoordinatorError", "OBS_DIM", "ACT_DIM", "OBSERVATION_NAMES", "ACTION_NAMES",
           "DEFAULT_MAX_STEPS", "DEFAULT_PUSH_SCALE", "WALKER_ID"]

__version__ = _poet.__version__  # the project's version (CMakeLists.txt), compiled into the core

# Gymnasium's id for WalkerEnv: a change to the walker's observations, actions, rewards or episodes is a new version
# (VERSIONS in tools/reference/environment_card.py, shown on docs/reference/environment.md).
WALKER_ID = "poet/Walker-v0"


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

    def _reset(self, seed, options):
        if seed is not None:
            seed = _whole(seed, "seed")
        result = self._env.reset(seed, options)
        if seed is not None:
            self._np_random, self._np_random_seed = _seeded_generator(seed)
        return result

    @property
    def np_random(self):
        """numpy.random.Generator: seeded by reset(seed=...), else from fresh entropy at first use (Gymnasium's
        np_random). The walker's own randomness comes from the terrain seed, not from it."""
        if self._np_random is None:
            self._np_random, self._np_random_seed = _seeded_generator(None)
        return self._np_random

    @property
    def np_random_seed(self):
        """int: the seed np_random was made from (its entropy when none was given)."""
        if self._np_random is None:
            self._np_random, self._np_random_seed = _seeded_generator(None)
        return self._np_random_seed


def _seeded_generator(seed):
    """gymnasium.utils.seeding.np_random's generator: PCG64 over SeedSequence(seed), and the seed's entropy."""
    sequence = np.random.SeedSequence(seed)
    return np.random.Generator(np.random.PCG64(sequence)), sequence.entropy


class WalkerEnv(_Episodes):
    """The bipedal walker on one course, with Gymnasium's conventions.

    An episode starts with reset and goes on with step until it is terminated (the walker fell or crossed the
    finish line) or truncated (max_steps steps were taken). Observations are float32 of shape (OBS_DIM,), actions
    float32 of shape (ACT_DIM,); the environment's card (docs/reference/environment.md) names every index and
    states the reward. A seed picks the course's terrain (and initial push); it stays for later episodes until
    another is given.

    Args:
        course (str, os.PathLike or dict): a named course ("flat", "hardcore-like", ...), an environment file's
            path, or a dict in the environment file's schema ({"config": {...}, "seed": s}).
        seed (int, optional): the terrain seed, in [0, 999999]; default: the file's own seed, else 0.
        render_mode (str, optional): "rgb_array" for render() to return frames; None for no rendering.
        lidar (str): which ground a lidar ray reports: "nearest" (the nearest hit) or "first" (the first Box2D
            reports, as the reference did).
        push_scale (float): the initial horizontal push F ~ U[-push_scale, push_scale) newtons; 0 for none.
        max_steps (int): the steps after which an episode is truncated, in [1, 1000000].
        width (int, optional): the frame's width in pixels, in [16, 4096]; default 600.
        height (int, optional): the frame's height in pixels, in [16, 4096]; default 400.

    Attributes:
        metadata (dict): Gymnasium's: "render_modes" (["rgb_array"]) and "render_fps" (50, the simulation's rate).
        render_mode (str or None): the render mode the env was made with.
        observation_low (numpy.ndarray): the observation space's lower bounds, float32 (read-only).
        observation_high (numpy.ndarray): the observation space's upper bounds, float32 (read-only).
        action_low (numpy.ndarray): the action space's lower bounds, float32, all -1 (read-only).
        action_high (numpy.ndarray): the action space's upper bounds, float32, all 1 (read-only).

    Raises:
        TypeError: an argument of the wrong type (a seed that is not an integer, a course that is not a name,
            path or dict).
        ValueError: an unknown course, an unreadable or damaged environment file, a number out of range, an
            unknown render mode or lidar rule (the message names the argument).

    Example:
        >>> env = poet.WalkerEnv("hardcore-like", seed=3, render_mode="rgb_array")
        >>> obs, info = env.reset()
        >>> obs.shape, obs.dtype
        ((24,), dtype('float32'))
        >>> obs, reward, terminated, truncated, info = env.step(np.zeros(4, dtype=np.float32))
        >>> sorted(info)
        ['fell', 'finished', 'seed', 'steps', 'x']
        >>> env.render().shape
        (400, 600, 3)
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

    def reset(self, *, seed=None, options=None):
        """Starts a new episode.

        Args:
            seed (int, optional): a terrain seed in [0, 999999] for this and later episodes; it also seeds
                np_random. None keeps the current seed.
            options (dict, optional): Gymnasium's reset options; the walker reads none.

        Returns:
            tuple: (obs, info): the first observation, float32 of shape (24,), and the info dict (seed, steps, x,
            finished, fell).

        Raises:
            TypeError: seed is not an integer.
            ValueError: seed is out of range, or options is neither None nor a dict.

        Example:
            >>> env = poet.WalkerEnv("flat")
            >>> obs, info = env.reset(seed=7)
            >>> info["seed"], info["steps"], env.seed
            (7, 0, 7)
        """
        return self._reset(seed, options)

    def step(self, action):
        """Takes one step of the episode.

        Args:
            action (numpy.ndarray): shape (ACT_DIM,) = (4,), of a floating-point dtype, every value finite: the hip
                and knee motors of each leg, each clipped to [-1, 1].

        Returns:
            tuple: (obs, reward, terminated, truncated, info): the observation (float32, shape (24,)), the
            step's reward (float), whether the walker fell or finished (bool), whether max_steps steps were taken
            without that (bool), and the info dict (seed, steps, x, finished, fell).

        Raises:
            ValueError: the action is not a numpy array of a floating-point dtype and shape (4,), or a value is not
                finite.
            RuntimeError: there is no episode: before reset, or after the episode ended.

        Example:
            >>> env = poet.WalkerEnv("flat", max_steps=100)
            >>> walker = poet.Policy.load("data/walkers/flat-walker.json")
            >>> obs, info = env.reset(seed=0)
            >>> terminated = truncated = False
            >>> while not (terminated or truncated):
            ...     obs, reward, terminated, truncated, info = env.step(walker.act(obs))
            >>> info["steps"], terminated, truncated
            (100, False, True)
        """
        return self._env.step(action)

    @property
    def seed(self):
        """int: the terrain seed of the current (or next) episode."""
        return self._env.seed

    @property
    def max_steps(self):
        """int: the steps after which an episode is truncated."""
        return self._env.max_steps

    def render(self):
        """The current frame: the walker on its course as the project's pictures draw it, the camera on the hull.

        Without a render mode, None and a warning (Gymnasium's rule: the mode is chosen when the env is made).

        Returns:
            numpy.ndarray or None: with render_mode "rgb_array", uint8 RGB of shape (height, width, 3); else None.

        Raises:
            RuntimeError: before the first reset.

        Example:
            >>> env = poet.WalkerEnv("flat", render_mode="rgb_array", width=300, height=200)
            >>> _ = env.reset(seed=1)
            >>> frame = env.render()
            >>> frame.shape, frame.dtype
            ((200, 300, 3), dtype('uint8'))
        """
        if self.render_mode is None:
            warnings.warn("render() without a render mode: make the env with render_mode='rgb_array'", stacklevel=2)
            return None
        return self._env.render()


def evaluate(policy, course, seeds, *, threads=1, lidar="nearest", push_scale=DEFAULT_PUSH_SCALE,
             max_steps=DEFAULT_MAX_STEPS):
    """The policy's episodes on one course, one per terrain seed: the numbers poet-eval prints, bit for bit.

    The result does not depend on `threads`.

    Args:
        policy (Policy): the policy that acts.
        course (str, os.PathLike or dict): a named course, an environment file's path or a dict in its schema
            (as WalkerEnv takes it).
        seeds (iterable of int): the terrain seeds, each in [0, 999999]: an episode each.
        threads (int): the threads that run the episodes, in [1, 4096].
        lidar (str): "nearest" or "first" (as WalkerEnv takes it).
        push_scale (float): the initial push's bound, newtons (as WalkerEnv takes it).
        max_steps (int): the steps after which an episode is truncated.

    Returns:
        dict: numpy arrays in the seeds' order: "return" (float64), "steps" (int64), "finished" and "fell" (bool).

    Raises:
        TypeError: policy is not a Policy, or a seed or count is not an integer.
        ValueError: an unknown course or lidar rule, a damaged environment file, a number out of range.

    Example:
        >>> walker = poet.Policy.load("data/walkers/flat-walker.json")
        >>> scores = poet.evaluate(walker, "flat", seeds=range(4), threads=2, max_steps=200)
        >>> sorted(scores), scores["return"].shape
        (['fell', 'finished', 'return', 'steps'], (4,))
    """
    if not isinstance(policy, Policy):
        raise TypeError(f"policy must be a poet.Policy, got {type(policy).__name__}")
    seeds = [_whole(s, "each seed") for s in seeds]
    return _poet._evaluate(policy, _course(course), seeds, _whole(threads, "threads"), lidar,
                           _number(push_scale, "push_scale"), _whole(max_steps, "max_steps"))


def suite_names():
    """The held-out test suites this build knows, for evaluate_suite and poet-eval --suite.

    Returns:
        list of str: the suites' names.

    Example:
        >>> poet.suite_names()
        ['poet-suite-v1']
    """
    return list(_poet._suite_names())


def evaluate_suite(policy, suite, *, threads=1, lidar="nearest", push_scale=DEFAULT_PUSH_SCALE,
                   max_steps=DEFAULT_MAX_STEPS):
    """The policy on a held-out test suite: poet-eval --suite --json's document, bit for bit.

    The result does not depend on `threads`.

    Args:
        policy (Policy): the policy that acts.
        suite (str): the suite's name, one of suite_names().
        threads (int): the threads that run the episodes, in [1, 4096].
        lidar (str): "nearest" or "first" (as WalkerEnv takes it).
        push_scale (float): the initial push's bound, newtons (as WalkerEnv takes it).
        max_steps (int): the steps after which an episode is truncated.

    Returns:
        dict: "suite", "episodes", "finished", "finished_fraction", "mean_return" and "groups", each group with its
        fraction finished and 95% interval, its mean return with its own, and every episode under "courses".

    Raises:
        TypeError: policy is not a Policy, suite not a string, or a count not an integer.
        ValueError: an unknown suite or lidar rule, a number out of range.

    Example:
        >>> walker = poet.Policy.load("data/walkers/flat-walker.json")
        >>> score = poet.evaluate_suite(walker, "poet-suite-v1", threads=2, max_steps=20)
        >>> score["suite"], score["episodes"]
        ('poet-suite-v1', 500)
    """
    if not isinstance(policy, Policy):
        raise TypeError(f"policy must be a poet.Policy, got {type(policy).__name__}")
    if not isinstance(suite, str):
        raise TypeError(f"suite must be a suite's name, got {type(suite).__name__}")
    return json.loads(_poet._evaluate_suite(policy, suite, _whole(threads, "threads"), lidar,
                                            _number(push_scale, "push_scale"), _whole(max_steps, "max_steps")))


def as_gymnasium(env):
    """A gymnasium.Env around a WalkerEnv, for a user who has gymnasium (this package does not depend on it).

    observation_space and action_space are Boxes of the env's bounds, reset seeds np_random through
    gymnasium.Env.reset, step and render are the env's. With gymnasium installed, gymnasium.make(WALKER_ID,
    course=...) makes one too.

    Args:
        env (WalkerEnv): the environment to wrap.

    Returns:
        gymnasium.Env: the wrapper, whose `walker` is env.

    Raises:
        TypeError: env is not a WalkerEnv.
        ImportError: gymnasium is not installed.

    Example:
        >>> wrapped = poet.as_gymnasium(poet.WalkerEnv("flat"))
        >>> wrapped.observation_space.shape, wrapped.action_space.shape
        ((24,), (4,))
        >>> obs, info = wrapped.reset(seed=4)
        >>> info["seed"]
        4
    """
    if not isinstance(env, WalkerEnv):
        raise TypeError(f"env must be a poet.WalkerEnv, got {type(env).__name__}")
    from .gymnasium_env import GymnasiumWalker  # imports gymnasium: only this function and make need it

    return GymnasiumWalker(walker=env)


class VectorWalkerEnv(_Episodes):
    """num_envs walkers stepped together on C++ threads (the GIL released), batched numpy in and out.

    Walker i runs courses[i % len(courses)]. Gymnasium's next-step autoreset: the step after a walker's episode
    ends resets it (its action is ignored) and reports its first observation with reward 0, neither terminated nor
    truncated. Each walker holds some 220 KB.

    Args:
        courses (str, os.PathLike, dict or list of them): the courses, each as WalkerEnv takes it.
        num_envs (int): how many walkers, in [1, 4096].
        threads (int): the threads that step them, in [1, 4096] (no more are started than walkers).
        lidar (str): "nearest" or "first" (as WalkerEnv takes it).
        push_scale (float): the initial push's bound, newtons (as WalkerEnv takes it).
        max_steps (int): the steps after which a walker's episode is truncated.

    Attributes:
        metadata (dict): Gymnasium's: "autoreset_mode" ("NextStep") and "render_modes" (none).
        single_observation_low (numpy.ndarray): one walker's observation bounds, as WalkerEnv.observation_low.
        single_observation_high (numpy.ndarray): as WalkerEnv.observation_high.
        single_action_low (numpy.ndarray): one walker's action bounds, as WalkerEnv.action_low.
        single_action_high (numpy.ndarray): as WalkerEnv.action_high.

    Raises:
        TypeError: an argument of the wrong type.
        ValueError: no courses, an unknown course or lidar rule, a number out of range, of any size.

    Example:
        >>> vec = poet.VectorWalkerEnv(["flat", "hardcore-like"], 8, threads=2)
        >>> obs, info = vec.reset(seed=0)
        >>> obs.shape, info["seed"].tolist()
        ((8, 24), [0, 1, 2, 3, 4, 5, 6, 7])
        >>> obs, rewards, terminated, truncated, info = vec.step(np.zeros((8, 4), dtype=np.float32))
        >>> rewards.shape, terminated.dtype, sorted(info)
        ((8,), dtype('bool'), ['fell', 'finished', 'seed', 'steps'])
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

    def reset(self, *, seed=None, options=None):
        """Starts a new episode for every walker.

        Args:
            seed (int, optional): walker i gets terrain seed seed + i, so seed is at most 999999 - (num_envs - 1);
                it also seeds np_random. None: each walker keeps its course's seed.
            options (dict, optional): Gymnasium's reset options; the walkers read none.

        Returns:
            tuple: (obs, info): the first observations, float32 of shape (num_envs, 24), and the info dict of
            arrays of num_envs (seed, steps, finished, fell).

        Raises:
            TypeError: seed is not an integer.
            ValueError: seed is out of range, or options is neither None nor a dict.

        Example:
            >>> vec = poet.VectorWalkerEnv("flat", 4)
            >>> obs, info = vec.reset(seed=10)
            >>> obs.shape, info["seed"].tolist()
            ((4, 24), [10, 11, 12, 13])
        """
        return self._reset(seed, options)

    def step(self, actions):
        """Takes one step of every walker; a walker whose episode ended at the last step is reset instead.

        Args:
            actions (numpy.ndarray): shape (num_envs, 4), of a floating-point dtype, every value finite: row i is
                walker i's action.

        Returns:
            tuple: (obs, rewards, terminated, truncated, info): observations (float32, (num_envs, 24)), rewards
            (float64), terminated and truncated (bool), each an array of num_envs, and the info dict of arrays
            (seed, steps, finished, fell).

        Raises:
            ValueError: actions not a numpy array of a floating-point dtype and shape (num_envs, 4), or a value not
                finite.
            RuntimeError: before the first reset.

        Example:
            >>> vec = poet.VectorWalkerEnv("flat", 2)
            >>> _ = vec.reset(seed=0)
            >>> obs, rewards, terminated, truncated, info = vec.step(np.zeros((2, 4)))
            >>> info["steps"].tolist()
            [1, 1]
        """
        return self._env.step(actions)

    @property
    def num_envs(self):
        """int: how many walkers step together."""
        return self._env.num_envs


class Run:
    """A run directory, read-only: live or finished, it takes no lock and writes nothing.

    A live run is read as of its last checkpoint, as poet-report reads it. pairs, events, pair_stats, levels and
    annecs are pandas DataFrames (pandas is imported when one is asked for).

    Args:
        path (str or os.PathLike): the run directory.

    Attributes:
        path (str): the run directory, as given.
        report (dict): poet-report --json's document.
        config (str): the run's config in protobuf text format.
        live (bool): whether a coordinator held the run's lock when it was read.
        next_iteration (int): the iteration the run resumes at.

    Raises:
        TypeError: path is not a path.
        ValueError: the directory is not a readable run (the report's message).

    Example:
        >>> import pathlib, tempfile
        >>> work = tempfile.TemporaryDirectory()
        >>> config = pathlib.Path(work.name, "tiny.textproto")
        >>> _ = config.write_text("seed: 5 iterations: 2 es { perturbations: 3 } walker { max_steps: 100 }")
        >>> poet.start(config, pathlib.Path(work.name, "run"), threads=1).wait(progress=False)
        0
        >>> run = poet.Run(pathlib.Path(work.name, "run"))
        >>> run.live, run.next_iteration, list(run.pairs.index)
        (False, 2, [0])
        >>> run.theta(0).shape, sorted(run.encoding(0))
        ((2804,), ['config', 'seed'])
        >>> work.cleanup()
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
        """A pair's environment.

        Args:
            pair (int): the pair's id.

        Returns:
            dict: the environment in the environment file's schema ({"config": {...}, "seed": s}).

        Raises:
            TypeError: pair is not an integer.
            ValueError: the run has no such pair.
        """
        return json.loads(self._pair(pair)["env"])

    def theta(self, pair, *, best=False):
        """A pair's θ.

        Args:
            pair (int): the pair's id.
            best (bool): the best θ the pair has had instead of its current one.

        Returns:
            numpy.ndarray: θ, float64, a copy.

        Raises:
            TypeError: pair is not an integer.
            ValueError: the run has no such pair.
        """
        return self._pair(pair)["best_theta" if best else "theta"].copy()

    @property
    def pairs(self):
        """pandas.DataFrame: a row per pair ever created, as poet-report lists them, indexed by id."""
        import pandas as pd

        return pd.DataFrame(self.report["pairs"]).set_index("id")

    @property
    def events(self):
        """pandas.DataFrame: a row per event the checkpoint has seen (events.jsonl), fields as columns."""
        import pandas as pd

        return pd.DataFrame(self._events)

    @property
    def pair_stats(self):
        """pandas.DataFrame: a row per ES step (pair_stats.csv), the rows the checkpoint has seen, as the report
        read them (their size and CRC-32 checked against the checkpoint)."""
        import io

        import pandas as pd

        return pd.read_csv(io.BytesIO(self._pair_stats))

    @property
    def levels(self):
        """pandas.DataFrame: poet-report's metrics per difficulty level: created, passed the MC, admitted, solved,
        iterations to solve, and when each was first reached."""
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
        """pandas.DataFrame: ANNECS at the end of each iteration in both of its peers' definitions, at_admission
        and at_archiving (report["annecs"] states each): a row per iteration, as the run's annecs.csv holds them."""
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
