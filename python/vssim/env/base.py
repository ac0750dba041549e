"""The base classes the environments stand on: Gymnasium's when it is
importable (so they are real gymnasium.Env / VectorEnv), else small
stand-ins with the same behaviour for what vssim's environments use."""

import numpy as np

try:  # Gymnasium is not in Debian 12; use it when it is installed
    import gymnasium as _gym
    import gymnasium.vector as _gym_vector
except ImportError:  # pragma: no cover - depends on the machine
    _gym = None

HAVE_GYMNASIUM = _gym is not None


class _Closable:
    """What Gymnasium's Env and VectorEnv both have: render_mode, spec,
    close(), unwrapped and the context manager."""

    render_mode = None
    spec = None

    def close(self):
        pass

    @property
    def unwrapped(self):
        return self

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


class _Env(_Closable):
    """The part of gymnasium.Env the environments use: np_random, reset's
    seeding, close(), the context manager, unwrapped."""

    metadata = {"render_modes": []}
    _np_random = None

    @property
    def np_random(self):
        if self._np_random is None:
            self._np_random = np.random.default_rng()
        return self._np_random

    @np_random.setter
    def np_random(self, rng):
        self._np_random = rng

    def reset(self, *, seed=None, options=None):
        if seed is not None:
            self._np_random = np.random.default_rng(seed)


class _VectorEnv(_Closable):
    """The part of gymnasium.vector.VectorEnv the environments use."""

    metadata = {}


Env = _gym.Env if HAVE_GYMNASIUM else _Env
VectorEnv = _gym_vector.VectorEnv if HAVE_GYMNASIUM else _VectorEnv
