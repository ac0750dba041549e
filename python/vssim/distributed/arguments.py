"""The arguments of run_episodes and sweep, checked in the caller's process
before anything is submitted (docs/distributed.md)."""

import json
import math
import numbers
import os
import pickle

import numpy as np

from .. import World

# At most this many control periods per episode (a guard against a typo such as duration=1e9).
MAX_PERIODS = 100_000_000
COMMANDS = ("voltages", "wheel_speeds")

def _plain(value):
    """value with numpy scalars and arrays, and tuples, turned into JSON's types."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def _positive(name, value):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name}: expected a number of seconds, got {type(value).__name__}")
    value = float(value)
    if not math.isfinite(value) or value <= 0:
        raise ValueError(f"{name}: expected a positive finite number of seconds, got {value}")
    return value


def _count(name, value, least):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}: expected an int, got {type(value).__name__}")
    if value < least:
        raise ValueError(f"{name}: expected at least {least}, got {value}")
    return int(value)


def _seeds(seeds):
    if isinstance(seeds, (str, bytes, dict)) or isinstance(seeds, numbers.Number) or not hasattr(seeds, "__iter__"):
        raise TypeError(f"seeds: expected a sequence of ints such as range(1, 65), got {type(seeds).__name__}")
    out = []
    for s in seeds:
        if isinstance(s, bool) or not isinstance(s, numbers.Integral):
            raise TypeError(f"seeds: expected ints, got {s!r} ({type(s).__name__})")
        if not 0 <= s < 2**62:
            raise ValueError(f"seeds: expected 0 to 2**62 - 1, got {s}")
        out.append(int(s))
    if not out:
        raise ValueError("seeds: expected at least one seed")
    return out


def _periods(duration, control_dt):
    """The control periods of an episode: ceil(duration / control_dt), a ratio
    within 1e-9 of a whole number counting as whole."""
    q = duration / control_dt
    p = round(q) if abs(q - round(q)) <= 1e-9 * max(1.0, q) else math.ceil(q)
    p = max(1, int(p))
    if p > MAX_PERIODS:
        raise ValueError(f"duration / control_dt: at most {MAX_PERIODS} control periods, got {p}")
    return p


def _callable(name, f):
    """f pickled (by cloudpickle when there is one: lambdas and local functions too), or None."""
    if f is None:
        return None
    if not callable(f):
        raise TypeError(f"{name}: expected a callable or None, got {type(f).__name__}")
    try:
        import cloudpickle
        return cloudpickle.dumps(f)
    except ImportError:
        pass
    except Exception as e:
        raise TypeError(f"{name}: cannot be pickled for the workers: {e}") from e
    try:
        return pickle.dumps(f)
    except Exception as e:
        raise TypeError(f"{name}: cannot be pickled for the workers: {e}") from e


def _base_scene(scene):
    """The scene as a dict, checked: a dict as given, a file's JSON, or a
    built-in scene as vssim spells it out (World.scene_json). Raises the scene
    reader's ValueError, or TypeError."""
    if isinstance(scene, dict):
        scene = _plain(scene)
        try:
            json.dumps(scene)
        except (TypeError, ValueError) as e:
            raise TypeError(f"scene: not JSON data: {e}") from e
        World(scene).close()  # the reader's ValueError, naming the key
        return scene
    if isinstance(scene, os.PathLike):
        scene = os.fspath(scene)
    if not isinstance(scene, str):
        raise TypeError(f"scene: expected a path, a built-in scene's name or a dict, got {type(scene).__name__}")
    world = World(scene)  # the reader's ValueError: a bad file, no such file or built-in scene
    try:
        if os.path.isfile(scene):
            with open(scene, encoding="utf-8") as f:
                return json.load(f)
        return json.loads(world.scene_json())
    finally:
        world.close()


def _client(client):
    if client is not None and not callable(getattr(client, "submit", None)):
        raise TypeError(f"client: expected a distributed.Client or None (run here), got {type(client).__name__}")
    return client


def _runs(seeds, most):
    """seeds cut into runs a BatchWorld(n, scene, seed=first) plays: consecutive
    seeds from 1 up (world i plays first + i), or repeated 0s, at most `most`
    each. Returns (first, count, positions in seeds) per run."""
    runs = []
    for pos, s in enumerate(seeds):
        if runs:
            first, count, where = runs[-1]
            follows = s == 0 if first == 0 else s == first + count
            if follows and count < most:
                runs[-1] = (first, count + 1, where + [pos])
                continue
        runs.append((s, 1, [pos]))
    return runs
