#!/usr/bin/python3
"""Scaling of vssim.distributed from one to two Dask workers (docs/distributed.md).

The same episodes (kickoff_3v3, both teams built-in) are played on a
LocalCluster of 1 worker process, then of 2 (one thread each, BatchWorld
threads=1), several times each after a warm-up run; prints the median wall
time, the throughput in episode-seconds of simulated time per second of wall
time, and the ratio of the two. The machine's other load adds noise.

    PYTHONPATH=build/python bench/python_distributed_bench.py [--episodes 64] [--duration 20]
"""

import argparse
import logging
import statistics
import time

from distributed import Client, LocalCluster

import vssim.distributed as vd


def measure(workers, args):
    """Wall times, s, of args.repeats runs on a LocalCluster of `workers` processes."""
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        run = lambda: vd.run_episodes(client, args.scene, range(1, args.episodes + 1), args.duration,
                                      worlds_per_task=args.worlds_per_task, raise_errors=True)
        run()  # warm-up: the workers import vssim and build their worlds
        walls = []
        for _ in range(args.repeats):
            start = time.perf_counter()
            eps = run()
            walls.append(time.perf_counter() - start)
        used = len(set(eps.workers))
    return walls, used


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scene", default="kickoff_3v3")
    p.add_argument("--episodes", type=int, default=64)
    p.add_argument("--duration", type=float, default=20.0, help="simulated s per episode")
    p.add_argument("--worlds-per-task", type=int, default=8)
    p.add_argument("--repeats", type=int, default=5)
    args = p.parse_args()
    sim = args.episodes * args.duration  # episode-seconds of simulated time per run
    print(f"{args.episodes} episodes of {args.scene}, {args.duration:g} s each, "
          f"{args.worlds_per_task} per task, {args.repeats} runs per cluster")
    rates = {}
    for workers in (1, 2):
        walls, used = measure(workers, args)
        wall = statistics.median(walls)
        rates[workers] = sim / wall
        print(f"{workers} worker(s) ({used} used): median wall {wall:.3f} s "
              f"(min {min(walls):.3f}, max {max(walls):.3f}), {rates[workers]:.0f} episode-s/s")
    print(f"speed-up 2 workers / 1 worker: {rates[2] / rates[1]:.2f}")


if __name__ == "__main__":
    main()
