"""What run_episodes and sweep return: Episodes (arrays), SweepResult
(rows), and EpisodeError for raise_errors=True."""


import numpy as np



class EpisodeError(RuntimeError):
    """Raised by raise_errors=True when some episodes failed; `.results`
    holds everything gathered (Episodes or SweepResult)."""

    def __init__(self, message, results):
        super().__init__(message)
        self.results = results


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
