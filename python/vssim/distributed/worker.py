"""The worker's side: one task plays one BatchWorld of consecutive seeds;
each worker process keeps idle BatchWorlds between tasks
(docs/distributed.md, "How the workers keep their worlds")."""

import os
import pickle
import sys
import threading
from collections import OrderedDict

import numpy as np

from .. import BatchWorld

# Idle BatchWorlds kept per process (each Dask worker holds its own).
CACHE_SIZE = 4

_cache = OrderedDict()  # (scene JSON, n, seed, threads) -> an idle BatchWorld
_cache_lock = threading.Lock()


def clear_cache():
    """Frees this process's cached worlds (client.run(clear_cache) frees every worker's)."""
    with _cache_lock:
        _cache.clear()


def _checkout(key, scene, n, seed, threads):
    """A BatchWorld of the scene at its start, from the cache (reset) or new; and whether cached."""
    with _cache_lock:
        batch = _cache.pop(key, None)
    if batch is not None:
        batch.reset_all()
        return batch, True
    return BatchWorld(n, scene, threads=threads, seed=seed), False


def _checkin(key, batch):
    with _cache_lock:
        _cache[key] = batch
        _cache.move_to_end(key)
        while len(_cache) > CACHE_SIZE:
            _cache.popitem(last=False)


def _worker_address():
    """This Dask worker's address, or "local" outside a worker."""
    dist = sys.modules.get("distributed")
    if dist is not None:
        try:
            return dist.get_worker().address
        except Exception:
            pass
    return "local"


def _non_finite(batch):
    """Per world: None, or which body's state is not finite ("the ball", "robot 2")."""
    ball_ok = np.isfinite(batch.balls).all(axis=1)
    robot_ok = np.isfinite(batch.robots).all(axis=2)  # (n_worlds, n_robots)
    out = [None] * batch.n_worlds
    for i in np.flatnonzero(~ball_ok | ~robot_ok.all(axis=1)):
        out[i] = "the ball" if not ball_ok[i] else f"robot {np.flatnonzero(~robot_ok[i])[0]}"
    return out


def _run_task(spec):
    """Plays spec's episodes; returns their results and errors (never raises)."""
    n = spec["n"]
    out = {"worker": _worker_address(), "pid": os.getpid(), "cached": False, "error": None,
           "world_errors": [None] * n, "steps": 0, "measures": {}}
    where = f"{spec['label']}, on {out['worker']} (pid {out['pid']})"
    stage = "the scene"
    batch = None
    try:
        policy = pickle.loads(spec["policy"]) if spec["policy"] is not None else None
        measure = pickle.loads(spec["measure"]) if spec["measure"] is not None else None
        key = (spec["key"], n, spec["seed"], spec["threads"])
        batch, out["cached"] = _checkout(key, spec["scene"], n, spec["seed"], spec["threads"])
        drive = batch.set_voltages if spec["command"] == "voltages" else batch.set_wheel_speeds
        dead = np.zeros(n, dtype=bool)
        for k in range(spec["periods"]):
            t = k * spec["control_dt"]
            if policy is not None:
                stage = f"the policy at t = {t:.6g} s"
                u = policy(batch)
                if u is not None:
                    stage = f"the policy's {spec['command']} at t = {t:.6g} s"
                    u = np.array(u, dtype=np.float64)
                    if dead.any() and u.shape == (n, batch.n_robots, 2):
                        u[dead] = 0.0  # a failed world's commands do not matter
                    drive(u)
            stage = f"the step at t = {t:.6g} s"
            out["steps"] += batch.step(spec["control_dt"])
            for i, body in enumerate(_non_finite(batch)):
                if body is None:
                    continue
                if not dead[i]:
                    dead[i] = True
                    out["world_errors"][i] = (
                        f"{where}, seed {spec['seeds'][i]}: the state of {body} went non-finite by "
                        f"t = {t + spec['control_dt']:.6g} s (parameters too stiff for the integrator at this dt?)")
                batch.reset(i)  # its episode is over; reset, it hands the policy finite states again
        if measure is not None:
            stage = "measure"
            m = measure(batch)
            if not isinstance(m, dict):
                m = {"measure": m}
            for name, value in m.items():
                a = np.asarray(value)
                if a.ndim == 0 or a.shape[0] != n:
                    raise ValueError(f"measure()[{name!r}]: expected an array of shape (n_worlds={n}, ...), "
                                     f"got shape {a.shape}")
                out["measures"][str(name)] = a
        out.update(score=batch.scores.astype(np.int64), ball=batch.balls, robots=batch.robots, time=batch.times)
    except Exception as e:
        out["error"] = f"{where}: {stage}: {type(e).__name__}: {e}"
    finally:
        if batch is not None:
            _checkin(key, batch)
    return out
