"""Episodes and parameter sweeps of vssim across a Dask cluster.

run_episodes(client, scene, seeds, duration) plays one episode per seed;
sweep(client, scene, variations, seeds, duration) plays every scene variation
with every seed. The episodes are cut into tasks, each task one
vssim.BatchWorld of consecutive seeds run by a Dask worker, and the results
come back as numpy arrays (Episodes) or as a table (a list of row dicts).
An episode's results are those of the same episode run alone in this
process, bit for bit. A task that fails (a bad scene variation, a policy
that raises, a world whose state went non-finite) is reported in its own
episodes' `error`, the others' results still come back.

client=None runs the same tasks here, one after the other, without Dask.
`import vssim` does not import this module; `distributed` (Debian:
python3-distributed) is imported only when a client is given. Units are SI
(m, s, rad, V, rad/s). See docs/distributed.md.
"""

import itertools
import json
import math
import numbers
import os
import pickle
import sys
import threading
import time as _time
from collections import OrderedDict

import numpy as np

from . import BatchWorld, World

__all__ = ["CACHE_SIZE", "EpisodeError", "Episodes", "SweepResult", "apply_variation", "clear_cache", "grid",
           "run_episodes", "sweep"]

# Idle BatchWorlds kept per process (each Dask worker holds its own).
CACHE_SIZE = 4
# At most this many control periods per episode (a guard against a typo such as duration=1e9).
MAX_PERIODS = 100_000_000
_COMMANDS = ("voltages", "wheel_speeds")


class EpisodeError(RuntimeError):
    """Raised by raise_errors=True when some episodes failed; `.results`
    holds everything gathered (Episodes or SweepResult)."""

    def __init__(self, message, results):
        super().__init__(message)
        self.results = results


# ---------------------------------------------------------------------------
# Arguments, checked in the caller's process before anything is submitted.

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


# ---------------------------------------------------------------------------
# Scene variations.

def grid(axes):
    """Every combination of values, as a list of variations: grid({"ball.vx":
    [0.5, 1.0], "robots.0.x": [-0.3, -0.2]}) gives four dicts of dotted key
    paths, the first key varying slowest."""
    if not isinstance(axes, dict) or not axes:
        raise TypeError("variations: expected a non-empty dict of dotted key paths to lists of values")
    keys = list(axes)
    values = []
    for k in keys:
        if not isinstance(k, str) or not k:
            raise TypeError(f"variations: keys must be dotted key paths such as 'ball.vx', got {k!r}")
        v = axes[k]
        if isinstance(v, (str, bytes, dict)) or not hasattr(v, "__iter__"):
            raise TypeError(f"variations[{k!r}]: expected a list of values, got {type(v).__name__}")
        v = list(v)
        if not v:
            raise ValueError(f"variations[{k!r}]: expected at least one value")
        values.append(v)
    return [dict(zip(keys, combo)) for combo in itertools.product(*values)]


def _set(node, parts, value, path):
    """Sets node[parts...] = value: a dict value merges into the dict there;
    '*' stands for every element of a list; missing object keys are created."""
    head, rest = parts[0], parts[1:]
    if isinstance(node, list):
        if head == "*":
            indices = range(len(node))
        else:
            try:
                indices = [int(head)]
            except ValueError:
                raise ValueError(f"{path}: '{head}' indexes a list: expected a number or *") from None
            if not 0 <= indices[0] < len(node):
                raise ValueError(f"{path}: index {indices[0]} is outside the list of {len(node)}")
        for i in indices:
            if rest:
                _set(node[i], rest, value, path)
            else:
                node[i] = _merge(node[i], value)
        return
    if not isinstance(node, dict):
        raise ValueError(f"{path}: '{head}' is inside a {type(node).__name__}, not an object")
    if rest:
        _set(node.setdefault(head, {}), rest, value, path)
    else:
        node[head] = _merge(node.get(head), value)


def _merge(old, new):
    if isinstance(old, dict) and isinstance(new, dict):
        out = dict(old)
        for k, v in new.items():
            out[k] = _merge(out.get(k), v)
        return out
    return json.loads(json.dumps(new))  # a copy


def apply_variation(scene, variation):
    """A copy of the scene dict with the variation applied: each dotted key path
    (e.g. "ball.vx", "robots.0.params.mass", "robots.*.params.mass") set to its
    value; a dict value merges into the object there. Raises ValueError."""
    out = json.loads(json.dumps(scene))
    for path, value in variation.items():
        if not isinstance(path, str) or not path or any(not p for p in path.split(".")):
            raise ValueError(f"{path!r}: expected a dotted key path such as 'ball.vx'")
        _set(out, path.split("."), value, path)
    return out


def _flat(variation):
    """The variation's values by dotted key path, nested dicts spread out: the table's columns."""
    out = {}
    for k, v in variation.items():
        if isinstance(v, dict) and v:
            for k2, v2 in _flat(v).items():
                out[f"{k}.{k2}"] = v2
        else:
            out[k] = v
    return out


# ---------------------------------------------------------------------------
# The worker's side: one task plays one BatchWorld.

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
                batch.reset(i)  # its episode is over; a NaN world would only slow the steps down
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


# ---------------------------------------------------------------------------
# The client's side: submit, gather, arrange.

def _label(seeds):
    if len(seeds) == 1:
        return f"seed {seeds[0]}"
    if seeds[0] == seeds[-1]:
        return f"seed {seeds[0]} ({len(seeds)} episodes)"
    return f"seeds {seeds[0]}..{seeds[-1]}"


def _specs(scene, seeds, periods, opts, label, most):
    """The task specs of one scene and its seeds, with the positions of their episodes."""
    key = json.dumps(scene, sort_keys=True)
    specs = []
    for first, count, where in _runs(seeds, most):
        run = [seeds[p] for p in where]
        specs.append(({"scene": scene, "key": key, "n": count, "seed": first, "seeds": run, "periods": periods,
                       "label": f"{label}{_label(run)}", **opts}, where))
    return specs


def _gather(client, specs, progress, timeout):
    """Runs every spec (on the cluster, or here for client None); returns the
    results in spec order. A task that Dask itself lost becomes an error."""
    total = len(specs)
    results = [None] * total
    deadline = None if timeout is None else _time.monotonic() + timeout

    def report(done):
        if callable(progress):
            progress(done, total)
        elif progress:
            print(f"vssim.distributed: {done}/{total} tasks done", file=sys.stderr, flush=True)

    if client is None:
        for i, spec in enumerate(specs):
            if deadline is not None and _time.monotonic() > deadline:
                results[i] = {"error": f"{spec['label']}: not run: the timeout of {timeout} s passed"}
                continue
            results[i] = _run_task(spec)
            report(i + 1)
        return results

    import distributed

    futures = client.map(_run_task, specs, pure=False)
    index = {f.key: i for i, f in enumerate(futures)}
    pending = set(futures)
    done_count = 0
    try:
        while pending:
            left = None if deadline is None else deadline - _time.monotonic()
            if left is not None and left <= 0:
                break
            try:
                done, pending = distributed.wait(list(pending), timeout=left, return_when="FIRST_COMPLETED")
            except TimeoutError:
                break
            for f in done:
                i = index[f.key]
                if f.status == "finished":
                    results[i] = f.result()
                else:
                    try:
                        why = f"{type(f.exception()).__name__}: {f.exception()}"
                    except Exception as e:
                        why = f"{f.status} ({type(e).__name__}: {e})"
                    results[i] = {"error": f"{specs[i]['label']}: the task failed in Dask: {why}"}
                done_count += 1
                report(done_count)
    finally:
        if pending:
            client.cancel(list(pending))
    for f in pending:
        i = index[f.key]
        results[i] = {"error": f"{specs[i]['label']}: not finished within the timeout of {timeout} s (cancelled)"}
    return results


def _records(spec, result):
    """One dict per episode of a task's result."""
    n = spec["n"]
    recs = []
    for i in range(n):
        error = result.get("error") or (result.get("world_errors") or [None] * n)[i]
        ok = error is None
        recs.append({
            "seed": spec["seeds"][i],
            "score": result["score"][i] if ok else np.array([-1, -1], dtype=np.int64),
            "ball": result["ball"][i] if ok else np.full(4, np.nan),
            "robots": result["robots"][i] if ok else None,
            "time": float(result["time"][i]) if ok else math.nan,
            "steps": int(result["steps"]) if ok else -1,
            "measures": {k: v[i] for k, v in result.get("measures", {}).items()} if ok else {},
            "worker": result.get("worker", ""),
            "pid": result.get("pid", -1),
            "cached": bool(result.get("cached", False)),
            "error": error,
        })
    return recs


def _row(rec):
    """A table row of an episode record."""
    row = {"seed": rec["seed"], "score_yellow": int(rec["score"][0]), "score_blue": int(rec["score"][1])}
    for name, v in zip(("ball_x", "ball_y", "ball_vx", "ball_vy"), rec["ball"]):
        row[name] = float(v)
    row["time"] = rec["time"]
    row["steps"] = rec["steps"]
    for name, v in rec["measures"].items():
        row[name] = v.item() if isinstance(v, np.generic) or (isinstance(v, np.ndarray) and v.ndim == 0) else v
    row["robot_states"] = rec["robots"]
    row["worker"] = rec["worker"]
    row["pid"] = rec["pid"]
    row["cached"] = rec["cached"]
    row["error"] = rec["error"]
    return row


def _frame(rows):
    try:
        import pandas
    except ImportError:
        raise ImportError("a DataFrame needs pandas (Debian: python3-pandas); the rows are plain dicts") from None
    return pandas.DataFrame(rows)


class Episodes:
    """Results of run_episodes, one entry per seed in the order given.

    seeds (n,) int; score (n, 2) int goals of yellow, blue; ball (n, 4) x, y
    (m), vx, vy (m/s); robots (n, n_robots, 5) x, y (m), theta (rad), v (m/s),
    omega (rad/s); time (n,) simulated s; steps (n,) steps of dt; measures
    {name: (n, ...) array} from measure(batch); errors: list of str or None;
    ok (n,) bool; workers, pids: who played each episode; cached (n,) bool:
    the worker reused a cached world. A failed episode holds NaN, -1 for score
    and steps, and NaN in its measures.
    """

    def __init__(self, records, n_robots):
        n = len(records)
        self.seeds = np.array([r["seed"] for r in records], dtype=np.int64)
        self.score = np.array([r["score"] for r in records], dtype=np.int64).reshape(n, 2)
        self.ball = np.array([r["ball"] for r in records], dtype=np.float64).reshape(n, 4)
        self.robots = np.full((n, n_robots, 5), np.nan)
        for i, r in enumerate(records):
            if r["robots"] is not None:
                self.robots[i] = r["robots"]
        self.time = np.array([r["time"] for r in records], dtype=np.float64)
        self.steps = np.array([r["steps"] for r in records], dtype=np.int64)
        self.errors = [r["error"] for r in records]
        self.ok = np.array([e is None for e in self.errors], dtype=bool)
        self.workers = [r["worker"] for r in records]
        self.pids = np.array([r["pid"] for r in records], dtype=np.int64)
        self.cached = np.array([r["cached"] for r in records], dtype=bool)
        self.measures = {}
        names = list(dict.fromkeys(k for r in records for k in r["measures"]))
        for name in names:
            ok_values = [np.asarray(r["measures"][name]) for r in records if name in r["measures"]]
            shape = ok_values[0].shape
            if any(v.shape != shape for v in ok_values):  # differing shapes: one array per episode
                a = np.empty(n, dtype=object)
                for i, r in enumerate(records):
                    a[i] = r["measures"].get(name)
            else:
                dtype = np.result_type(*ok_values)
                if len(ok_values) < n and not np.issubdtype(dtype, np.inexact):
                    dtype = np.float64  # room for the failed episodes' NaN
                a = np.full((n,) + shape, np.nan, dtype=dtype) if np.issubdtype(dtype, np.inexact) \
                    else np.empty((n,) + shape, dtype=dtype)
                for i, r in enumerate(records):
                    if name in r["measures"]:
                        a[i] = r["measures"][name]
            self.measures[name] = a
        self._records = records

    def __len__(self):
        return len(self.seeds)

    def __repr__(self):
        return f"<vssim.distributed.Episodes: {len(self)} episodes, {int((~self.ok).sum())} failed>"

    def rows(self):
        """One dict per episode: seed, score_yellow, score_blue, ball_x, ...,
        time, steps, the measures, robot_states, worker, pid, cached, error."""
        return [_row(r) for r in self._records]

    def frame(self):
        """rows() as a pandas DataFrame (needs pandas)."""
        return _frame(self.rows())


class SweepResult(list):
    """The rows of a sweep (a list of dicts), one per (variation, seed): the
    variation's index and values (by dotted key path), then the columns of
    Episodes.rows(), error last (None when the episode ran)."""

    @property
    def failed(self):
        """The rows whose episode failed."""
        return [r for r in self if r["error"] is not None]

    def frame(self):
        """The rows as a pandas DataFrame (needs pandas)."""
        return _frame(self)


def _options(duration, control_dt, policy, measure, command, worlds_per_task, threads, timeout):
    duration = _positive("duration", duration)
    control_dt = _positive("control_dt", control_dt)
    periods = _periods(duration, control_dt)
    if command not in _COMMANDS:
        raise ValueError(f"command: expected 'voltages' or 'wheel_speeds', got {command!r}")
    most = _count("worlds_per_task", worlds_per_task, 1)
    threads = _count("threads", threads, 0)
    if timeout is not None:
        timeout = _positive("timeout", timeout)
    opts = {"control_dt": control_dt, "command": command, "threads": threads,
            "policy": _callable("policy", policy), "measure": _callable("measure", measure)}
    return periods, most, opts, timeout


def _raise(errors, total, results):
    bad = [e for e in errors if e is not None]
    if bad:
        raise EpisodeError(f"{len(bad)} of {total} episodes failed; the first: {bad[0]}", results)


def run_episodes(client, scene, seeds, duration, policy=None, measure=None, *, control_dt=0.03,
                 command="voltages", worlds_per_task=8, threads=1, raise_errors=False, progress=False,
                 timeout=None):
    """Plays one episode of `scene` per seed on the cluster; returns Episodes.

    client: a distributed.Client, or None to run here without Dask.
    scene: a path, a built-in scene's name or a dict in the scene format.
    seeds: ints >= 0, one episode each (the Match seed; 0: no jitter); runs
    of consecutive seeds share a task's BatchWorld, up to worlds_per_task.
    duration: s; an episode is ceil(duration / control_dt) control periods.
    policy(batch): called at the start of every period of control_dt s with
    the task's vssim.BatchWorld; returns (n_worlds, n_robots, 2) commands
    ([right, left] V, or rad/s with command="wheel_speeds") or None (none
    given: the scene's own teams play). It is pickled (cloudpickle): each
    task has a fresh copy.
    measure(batch): called at the end; returns {name: (n_worlds, ...) array}
    (or one array, named "measure").
    threads: the BatchWorld's threads per task (0: every core of the worker).
    raise_errors: raise EpisodeError if any episode failed (after gathering).
    progress: True prints "done/total tasks" to stderr; a callable gets (done, total).
    timeout: s of wall time for the whole run (None: no limit); unfinished
    tasks are cancelled and reported as errors.
    """
    client = _client(client)
    periods, most, opts, timeout = _options(duration, control_dt, policy, measure, command, worlds_per_task,
                                            threads, timeout)
    seeds = _seeds(seeds)
    base = _base_scene(scene)
    with World(base) as w:
        n_robots = w.n_robots
    specs = _specs(base, seeds, periods, opts, "", most)
    results = _gather(client, [s for s, _ in specs], progress, timeout)
    records = [None] * len(seeds)
    for (spec, where), result in zip(specs, results):
        for pos, rec in zip(where, _records(spec, result)):
            records[pos] = rec
    episodes = Episodes(records, n_robots)
    if raise_errors:
        _raise(episodes.errors, len(episodes), episodes)
    return episodes


def sweep(client, scene, variations, seeds, duration, policy=None, measure=None, *, control_dt=0.03,
          command="voltages", worlds_per_task=8, threads=1, raise_errors=False, progress=False, timeout=None):
    """Plays every scene variation with every seed; returns a SweepResult
    (a list of row dicts; .frame() gives a pandas DataFrame).

    variations: a dict of dotted key paths to lists of values, played as
    their grid (grid()), or a list of variations, each a dict of dotted key
    paths to values ({"ball.vx": 0.5, "robots.*.params.mass": 0.2}; a dict
    value merges into the object there: {"ball": {"vx": 0.5}}). A variation
    applies to the scene as a dict: a dict as given, a file's JSON, or a
    built-in scene as vssim spells it out (every parameter, inertia included).
    A variation the scene reader refuses fails its own rows only.
    The other arguments are run_episodes'.
    """
    client = _client(client)
    periods, most, opts, timeout = _options(duration, control_dt, policy, measure, command, worlds_per_task,
                                            threads, timeout)
    seeds = _seeds(seeds)
    if isinstance(variations, dict):
        variations = grid(variations)
    elif isinstance(variations, (list, tuple)) and variations:
        for i, v in enumerate(variations):
            if not isinstance(v, dict):
                raise TypeError(f"variations[{i}]: expected a dict of dotted key paths to values, "
                                f"got {type(v).__name__}")
    else:
        raise TypeError("variations: expected a dict of dotted key paths to lists of values, "
                        "or a non-empty list of dicts")
    variations = [_plain(v) for v in variations]
    base = _base_scene(scene)
    rows = SweepResult()
    specs = []  # (spec, row positions)
    for vi, variation in enumerate(variations):
        head = {"variation": vi, **_flat(variation)}
        label = f"variation {vi} {json.dumps(variation)}, "
        try:
            patched = apply_variation(base, variation)
        except ValueError as e:
            for s in seeds:
                rows.append({**head, **_row(_failed_record(s, f"{label}{_label(seeds)}: the variation: {e}"))})
            continue
        first = len(rows)
        rows.extend([None] * len(seeds))
        for spec, where in _specs(patched, seeds, periods, opts, label, most):
            specs.append((spec, [first + p for p in where], head))
    results = _gather(client, [s for s, _, _ in specs], progress, timeout)
    for (spec, where, head), result in zip(specs, results):
        for pos, rec in zip(where, _records(spec, result)):
            rows[pos] = {**head, **_row(rec)}
    if raise_errors:
        _raise([r["error"] for r in rows], len(rows), rows)
    return rows


def _failed_record(seed, error):
    return {"seed": seed, "score": np.array([-1, -1]), "ball": np.full(4, np.nan), "robots": None,
            "time": math.nan, "steps": -1, "measures": {}, "worker": "", "pid": -1, "cached": False,
            "error": error}
