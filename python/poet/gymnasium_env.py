"""The walker as a gymnasium.Env, for users who have gymnasium (this package does not depend on it): imported by
poet only when gymnasium is importable, which registers WALKER_ID so that gymnasium.make creates walkers by name.

    env = gymnasium.make("poet/Walker-v0", course="hardcore-like", render_mode="rgb_array")
"""

import gymnasium
import numpy as np

from . import DEFAULT_MAX_STEPS, DEFAULT_PUSH_SCALE, WALKER_ID, WalkerEnv


class GymnasiumWalker(gymnasium.Env):
    """A poet.WalkerEnv as a gymnasium.Env: Box spaces of its bounds, reset seeding np_random through
    gymnasium.Env.reset, render by render_mode. Keyword arguments are WalkerEnv's; `walker` wraps an existing one."""

    metadata = WalkerEnv.metadata

    def __init__(self, course="flat", *, seed=None, render_mode=None, lidar="nearest", push_scale=DEFAULT_PUSH_SCALE,
                 max_steps=DEFAULT_MAX_STEPS, width=None, height=None, walker=None):
        if walker is None:
            walker = WalkerEnv(course, seed=seed, render_mode=render_mode, lidar=lidar, push_scale=push_scale,
                               max_steps=max_steps, width=width, height=height)
        elif not isinstance(walker, WalkerEnv):
            raise TypeError(f"walker must be a poet.WalkerEnv, got {type(walker).__name__}")
        self.walker = walker
        self.render_mode = walker.render_mode
        self.observation_space = gymnasium.spaces.Box(walker.observation_low, walker.observation_high,
                                                      dtype=np.float32)
        self.action_space = gymnasium.spaces.Box(walker.action_low, walker.action_high, dtype=np.float32)

    def reset(self, *, seed=None, options=None):
        """gymnasium.Env.reset's seeding of np_random, then the walker's reset: (obs, info)."""
        super().reset(seed=seed, options=options)
        return self.walker.reset(seed=seed, options=options)

    def step(self, action):
        """The walker's step: (obs, reward, terminated, truncated, info)."""
        return self.walker.step(np.asarray(action, dtype=np.float32))

    def render(self):
        """The current frame (render_mode "rgb_array"), or None without a render mode."""
        return self.walker.render()


def register():
    """Registers WALKER_ID (course and WalkerEnv's options as make's keyword arguments; the walker truncates its
    own episodes at max_steps, so no TimeLimit is added). Registering twice is harmless."""
    if WALKER_ID not in gymnasium.registry:
        gymnasium.register(id=WALKER_ID, entry_point=f"{__name__}:GymnasiumWalker", kwargs={"course": "flat"})
