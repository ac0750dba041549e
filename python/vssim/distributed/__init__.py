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

The parts: arguments.py (checked before anything is submitted),
variations.py (grids of scene variations), worker.py (a task on a worker,
and the worlds each worker keeps), client.py (submit and gather),
results.py (Episodes, SweepResult, EpisodeError).
"""

from .client import run_episodes, sweep
from .results import EpisodeError, Episodes, SweepResult
from .variations import apply_variation, grid
from .worker import CACHE_SIZE, clear_cache

__all__ = ["CACHE_SIZE", "EpisodeError", "Episodes", "SweepResult", "apply_variation", "clear_cache", "grid",
           "run_episodes", "sweep"]
