"""Box spaces: gymnasium.spaces.Box when Gymnasium is importable, else a
small stand-in with the same members (low, high, shape, dtype, sample(),
contains(), seed()), so the environments keep one API without Gymnasium."""

import numpy as np

try:  # Gymnasium is not in Debian 12; use it when it is installed
    from gymnasium.spaces import Box as _GymBox
except ImportError:  # pragma: no cover - depends on the machine
    _GymBox = None


class _Box:
    """A box of real numbers low <= x <= high, elementwise."""

    def __init__(self, low, high, shape=None, dtype=np.float32, seed=None):
        self.dtype = np.dtype(dtype)
        if shape is None:
            shape = np.shape(low)
        self.shape = tuple(int(d) for d in shape)
        self.low = np.broadcast_to(np.asarray(low, dtype=self.dtype), self.shape).copy()
        self.high = np.broadcast_to(np.asarray(high, dtype=self.dtype), self.shape).copy()
        if np.any(self.low > self.high):
            raise ValueError("Box: low must not exceed high")
        self._rng = np.random.default_rng(seed)

    def seed(self, seed=None):
        self._rng = np.random.default_rng(seed)
        return [seed]

    def sample(self):
        """Uniform in the box (unbounded sides: standard normal around the bound)."""
        low = np.where(np.isfinite(self.low), self.low, -1.0)
        high = np.where(np.isfinite(self.high), self.high, 1.0)
        x = self._rng.uniform(low, high, self.shape)
        x = np.where(np.isfinite(self.low) | np.isfinite(self.high), x, self._rng.standard_normal(self.shape))
        return x.astype(self.dtype)

    def contains(self, x):
        x = np.asarray(x)
        return x.shape == self.shape and bool(np.all(x >= self.low) and np.all(x <= self.high))

    __contains__ = contains

    def __repr__(self):
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


def box(low, high, shape=None, dtype=np.float32):
    """A Box space of `shape` (or low's shape) between low and high."""
    if _GymBox is not None:
        if shape is None:
            shape = np.shape(low)
        return _GymBox(low=np.broadcast_to(np.asarray(low, dtype), shape),
                       high=np.broadcast_to(np.asarray(high, dtype), shape), dtype=dtype)
    return _Box(low, high, shape, dtype)


def batched(space, n):
    """The space of n stacked samples of `space` (a vector environment's)."""
    return box(np.broadcast_to(space.low, (n,) + space.shape), np.broadcast_to(space.high, (n,) + space.shape),
               dtype=space.dtype)
