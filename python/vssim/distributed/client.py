"""The client's side: cut the episodes into tasks, submit them, gather and
arrange the results (run_episodes, sweep)."""

import json
import math
import sys
import time as _time

import numpy as np

from .. import World
from .arguments import COMMANDS, _base_scene, _callable, _client, _count, _periods, _plain, _positive, _runs, _seeds
from .results import EpisodeError, Episodes, SweepResult, _row
from .variations import _flat, apply_variation, grid
from .worker import _run_task

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



def _options(duration, control_dt, policy, measure, command, worlds_per_task, threads, timeout):
    duration = _positive("duration", duration)
    control_dt = _positive("control_dt", control_dt)
    periods = _periods(duration, control_dt)
    if command not in COMMANDS:
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
