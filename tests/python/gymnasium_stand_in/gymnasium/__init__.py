"""A stand-in for gymnasium (not in Debian), put on the path of a child process by test_gymnasium.py: the parts
poet's registration and wrapper use, with gymnasium 1.x's rules for them — Env.reset seeds np_random through
utils.seeding.np_random, spaces.Box holds its bounds' dtype and shape, register adds to registry, make imports the
entry point ("module:attr") and calls it with the spec's keyword arguments updated by make's, and sets env.spec."""

import importlib
import types

import numpy as np


def _np_random(seed=None):
    sequence = np.random.SeedSequence(seed)
    return np.random.Generator(np.random.PCG64(sequence)), sequence.entropy


utils = types.SimpleNamespace(seeding=types.SimpleNamespace(np_random=_np_random))


class Env:
    metadata = {"render_modes": []}
    render_mode = None
    spec = None
    _np_random = None
    _np_random_seed = None

    def reset(self, *, seed=None, options=None):
        if seed is not None:
            self._np_random, self._np_random_seed = _np_random(seed)

    @property
    def np_random(self):
        if self._np_random is None:
            self._np_random, self._np_random_seed = _np_random()
        return self._np_random

    @property
    def unwrapped(self):
        return self

    def close(self):
        pass


class Box:
    def __init__(self, low, high, dtype=np.float32):
        self.dtype = np.dtype(dtype)
        self.low = np.asarray(low, dtype=self.dtype)
        self.high = np.asarray(high, dtype=self.dtype)
        self.shape = self.low.shape

    def contains(self, x):
        x = np.asarray(x)
        return x.shape == self.shape and x.dtype == self.dtype and bool(np.all(x >= self.low) & np.all(x <= self.high))


spaces = types.SimpleNamespace(Box=Box)


class EnvSpec:
    def __init__(self, id, entry_point, kwargs):
        self.id, self.entry_point, self.kwargs = id, entry_point, dict(kwargs)

    def make(self, **kwargs):
        return make(self.id, **{**self.kwargs, **kwargs})


registry = {}


def register(id, entry_point, kwargs=None, **_):
    registry[id] = EnvSpec(id, entry_point, kwargs or {})


def make(id, **kwargs):
    spec = registry[id]
    module, attr = spec.entry_point.split(":")
    arguments = {**spec.kwargs, **kwargs}
    env = getattr(importlib.import_module(module), attr)(**arguments)
    env.spec = EnvSpec(id, spec.entry_point, arguments)
    return env
