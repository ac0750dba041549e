#!/usr/bin/python3
"""Throughput of the in-process Python module (docs/performance.md, "Worlds in
Python, in-process"):
steps per second and aggregate real-time factor of vssim.BatchWorld for 1,
16, 256 and 4096 worlds, on 1 and 2 threads, with and without the
observations copied out each step; a lone vssim.World; the cost of a Python
call; and, as the baseline measured in the same run, a client of `vssim
serve --lockstep` over loopback TCP (ground truth only, no images).

The workload: the 3 vs 3 kick-off on the official field (referee on, both
teams remote, so all six robots take Python's voltages), the `exact`
integrator at 1 ms, new uniform random voltages (+-7.4 V) for every robot
every 30 ms control step. Every world plays episodes of 3 s from the end of
the kick-off's stop; a batch of n worlds plays ceil(1024 / n) rounds, so
every configuration simulates the same 1024 or more episodes (the resets
between rounds are not timed).

    PYTHONPATH=build/python bench/python_batch_bench.py [--repeats 3] [--csv out.csv] [--vssim build/app/vssim]
"""

import argparse
import csv
import json
import os
import socket
import statistics
import struct
import subprocess
import sys
import tempfile
import time

import numpy as np

import vssim

CONTROL = 0.03      # s per control step
EPISODE = 3.0       # s of play per episode
MAX_VOLTAGE = 7.4   # V
STOP = 0.1          # s: the kick-off's stop (shortened), stepped before timing
EPISODES = 1024   # at least this many episodes per configuration


def scene(integrator="exact", blue="remote"):
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "resources", "scenes",
                           "vs_builtin_3v3.json")) as f:
        s = json.load(f)
    s["simulation"]["integrator"] = integrator
    s["game"] = {"referee": True, "yellow": "remote", "blue": blue, "stop_duration": STOP}
    return s


def run_batch(n, threads, observe, integrator="exact"):
    """(world-seconds simulated, wall seconds, control steps) for >= 256 episodes."""
    batch = vssim.BatchWorld(n, scene(integrator), threads=threads)
    rng = np.random.default_rng(n)
    rounds = -(-EPISODES // n)
    steps = int(round(EPISODE / CONTROL))
    wall = 0.0
    for _ in range(rounds):
        batch.reset_all()
        batch.step(STOP)
        volts = rng.uniform(-MAX_VOLTAGE, MAX_VOLTAGE, (steps, n, batch.n_robots, 2))
        t = time.perf_counter()
        for k in range(steps):
            batch.set_voltages(volts[k])
            batch.step(CONTROL)
            if observe:
                _ = (batch.robots, batch.wheel_speeds, batch.balls, batch.scores)
        wall += time.perf_counter() - t
    return rounds * n * steps * CONTROL, wall, rounds * steps


def run_world(observe):
    """A lone vssim.World: 512 episodes."""
    world = vssim.World(scene())
    rng = np.random.default_rng(1)
    steps = int(round(EPISODE / CONTROL))
    wall = 0.0
    for _ in range(512):
        world.reset()
        world.step(STOP)
        volts = rng.uniform(-MAX_VOLTAGE, MAX_VOLTAGE, (steps, world.n_robots, 2))
        t = time.perf_counter()
        for k in range(steps):
            world.set_voltages(volts[k])
            world.step(CONTROL)
            if observe:
                _ = (world.robots, world.wheel_speeds, world.ball, world.score)
        wall += time.perf_counter() - t
    return 512 * steps * CONTROL, wall, 512 * steps


def call_overhead():
    """Median seconds per call on an idle world (one robot at rest, no referee)."""
    idle = {"robots": [{"x": 0.0}], "simulation": {"integrator": "exact"}}
    world = vssim.World(idle)
    batch = vssim.BatchWorld(1, idle, threads=1)
    zeros_w, zeros_b = np.zeros((1, 2)), np.zeros((1, 1, 2))
    calls = {
        "World.step(0.001)": lambda: world.step(0.001),
        "World.set_voltages(array)": lambda: world.set_voltages(zeros_w),
        "World.robots": lambda: world.robots,
        "BatchWorld(1).step(0.001)": lambda: batch.step(0.001),
        "BatchWorld(1).set_voltages(array)": lambda: batch.set_voltages(zeros_b),
        "BatchWorld(1).robots": lambda: batch.robots,
    }
    out = {}
    for name, call in calls.items():
        samples = []
        for _ in range(7):
            t = time.perf_counter()
            for _ in range(2000):
                call()
            samples.append((time.perf_counter() - t) / 2000)
        out[name] = statistics.median(samples)
    return out


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run_tcp(vssim_binary, steps=2000):
    """A lockstep client of `vssim serve --lockstep` (yellow, ground truth
    only): voltages for its three robots, then a 30 ms step, waiting for the
    REPLY; blue is idle (0 V). (world-seconds, wall seconds, steps)."""
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(scene(blue="idle"), f)
        path = f.name
    port = free_port()
    server = subprocess.Popen([vssim_binary, "serve", path, "--lockstep", "--port", str(port)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        for _ in range(100):
            try:
                sock = socket.create_connection(("127.0.0.1", port), timeout=10)
                break
            except OSError:
                time.sleep(0.05)
        else:
            raise RuntimeError("vssim serve did not start")
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        buffer = bytearray()

        def send(kind, payload):
            sock.sendall(struct.pack(">IB", len(payload) + 1, kind) + payload)

        def receive():
            while True:
                if len(buffer) >= 4:
                    length = struct.unpack(">I", buffer[:4])[0]
                    if len(buffer) >= 4 + length:
                        kind, payload = buffer[4], bytes(buffer[5:4 + length])
                        del buffer[:4 + length]
                        return kind, payload
                chunk = sock.recv(65536)
                if not chunk:
                    raise RuntimeError("vssim serve closed the connection")
                buffer.extend(chunk)

        send(0x01, json.dumps({"protocol": 1, "role": "yellow", "name": "bench", "images": "none",
                               "state": True}).encode())
        while receive()[0] != 0x81:
            pass
        rng = np.random.default_rng(2)

        def one_step(i):
            volts = rng.uniform(-MAX_VOLTAGE, MAX_VOLTAGE, (3, 2))
            send(0x02, struct.pack(">B", 3) + b"".join(struct.pack(">Bdd", r, *volts[r]) for r in range(3)))
            send(0x03, json.dumps({"command": "step", "id": i, "duration": CONTROL}).encode())
            while True:
                kind, payload = receive()
                if kind == 0x83:
                    _ = np.array([[b["x"], b["y"]] for b in json.loads(payload)["robots"]])
                elif kind == 0x84 and json.loads(payload).get("id") == i:
                    return
                elif kind == 0x85:
                    raise RuntimeError(payload.decode())

        one_step(1)  # through the stop
        for i in range(2, 2 + int(STOP / CONTROL) + 1):
            one_step(i)
        t = time.perf_counter()
        for i in range(100, 100 + steps):
            one_step(i)
        return steps * CONTROL, time.perf_counter() - t, steps
    finally:
        server.terminate()
        server.wait(timeout=10)
        os.unlink(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3, help="runs of each configuration; medians (default 3)")
    parser.add_argument("--csv", help="write every run here")
    parser.add_argument("--vssim", default=os.path.join("build", "app", "vssim"), help="the vssim program (TCP)")
    parser.add_argument("--sizes", default="1,16,256,4096", help="batch sizes (default 1,16,256,4096)")
    parser.add_argument("--label", default="", help="a label for this build's rows in the CSV (e.g. before, after)")
    parser.add_argument("--no-observations", action="store_true",
                        help="only the runs without observations (for builds whose BatchWorld lacks wheel_speeds)")
    parser.add_argument("--no-tcp", action="store_true", help="leave out the TCP lockstep baseline")
    args = parser.parse_args()
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    sizes = [int(x) for x in args.sizes.split(",")]

    rows = []

    def record(config, n, threads, observe, result):
        world_seconds, wall, steps = result
        rows.append({"label": args.label, "config": config, "worlds": n, "threads": threads, "observations": observe,
                     "world_seconds": world_seconds, "wall_seconds": wall, "control_steps": steps,
                     "world_steps_per_second": world_seconds / CONTROL / wall,
                     "realtime_factor": world_seconds / wall})
        print(f"  {config:10s} n={n:5d} threads={threads} obs={int(observe)}: "
              f"{world_seconds / wall:9,.0f}x real time, {world_seconds / CONTROL / wall:9,.0f} world-steps/s",
              flush=True)

    print(f"python {sys.version.split()[0]}, vssim {vssim.__version__}, {os.cpu_count()} cores", flush=True)
    for r in range(args.repeats):
        print(f"run {r + 1} of {args.repeats}", flush=True)
        if os.path.exists(args.vssim) and not args.no_tcp:
            record("tcp", 1, 1, True, run_tcp(args.vssim))
        observations = (False,) if args.no_observations else (False, True)
        for observe in observations:
            record("world", 1, 1, observe, run_world(observe))
        for n in sizes:
            for threads in (1, 2):
                if n == 1 and threads == 2:
                    continue
                for observe in observations:
                    record("batch", n, threads, observe, run_batch(n, threads, observe))
        record("batch_rk4", 256, 1, False, run_batch(256, 1, False, "rk4"))

    print("\nmedians:")
    keys = sorted({(r["config"], r["worlds"], r["threads"], r["observations"]) for r in rows},
                  key=lambda k: (k[0], k[1], k[2], k[3]))
    for key in keys:
        xs = [r["realtime_factor"] for r in rows if (r["config"], r["worlds"], r["threads"], r["observations"]) == key]
        print(f"  {key[0]:10s} n={key[1]:5d} threads={key[2]} obs={int(key[3])}: {statistics.median(xs):9,.0f}x"
              f" (runs {', '.join(f'{x:,.0f}' for x in xs)})")
    print("\nPython call overhead (idle world, medians):")
    for name, seconds in call_overhead().items():
        print(f"  {name:36s} {seconds * 1e6:6.2f} us")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main()
