"""vssim in-process: the simulator of IEEE Very Small Size Soccer robots.

World(scene) runs one scene (a file, a built-in name such as "kickoff_3v3",
or a dict in the scene-file format) with its referee and built-in teams,
stepped from Python with the GIL released; BatchWorld(n, scene) runs n
copies on a pool of threads. See docs/python.md. vssim.distributed (imported
on its own, with Dask) spreads episodes and sweeps over a cluster.
"""

from ._vssim import BatchWorld, World, builtin_scenes, __version__

__all__ = ["BatchWorld", "World", "builtin_scenes", "__version__"]
