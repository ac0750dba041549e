#!/usr/bin/env python3
"""vssim.distributed on a Dask LocalCluster of two worker processes
(docs/distributed.md): episodes and sweeps give the numbers of the same
episodes run here with vssim.World, bit for bit; the tasks go to both
workers; a failing variation, policy or world is reported in its own rows
while the others succeed; bad arguments raise before anything is submitted.

Run by ctest with PYTHONPATH=<build>/python; by hand:
    PYTHONPATH=build/python /usr/bin/python3 tests/python_distributed_test.py
"""

import logging
import os
import threading
import time
import unittest

import distributed
import numpy as np

import vssim
import vssim.distributed as vd

SCENE = "vs_builtin_3v3"  # yellow remote (driven by the policy), blue built-in
CONTROL_DT = 0.03  # s


def law(robots, balls):
    """Voltages (n, n_robots, 2) from the state: turn towards the ball's y. Plain
    arithmetic only, so a batch and a lone world compute the same bits."""
    e = np.clip(5.0 * (balls[:, None, 1] - robots[:, :, 1]) + 0.1 * robots[:, :, 3], -1.0, 1.0)
    return np.stack([4.0 + 2.0 * e, 4.0 - 2.0 * e], axis=-1)


def policy(batch):
    return law(batch.robots, batch.balls)


def measure(batch):
    balls = batch.balls
    return {"ball_speed2": balls[:, 2] ** 2 + balls[:, 3] ** 2, "yellow_x": batch.robots[:, :3, 0]}


def local_episode(scene, seed, duration, drive=True):
    """The episode played here with one vssim.World, as run_episodes plays it."""
    w = vssim.World(scene, seed=seed)
    for _ in range(round(duration / CONTROL_DT)):
        if drive:
            w.set_voltages(law(w.robots[None], w.ball[None])[0])
        w.step(CONTROL_DT)
    return w


def physics_scene():
    """A ball rolling towards a robot on a 3v3 field, no game."""
    return {
        "field": {"type": "vsss_3v3"},
        "ball": {"x": -0.3, "y": 0.0},
        "robots": [{"team": "yellow", "x": 0.3, "y": 0.05}],
    }


def runaway_scene():
    """One robot with motors far too stiff for RK4 at 10 ms: driven, its state overflows."""
    motor = {"resistance": 0.001, "k": 100, "rotor_inertia": 0}
    return {
        "field": {"length": 100.0, "width": 100.0},
        "simulation": {"integrator": "rk4", "dt": 0.01},
        "ball": {"x": 40.0, "y": 40.0},
        "robots": [{"x": 0.0, "y": 0.0, "theta": 0.3,
                    "params": {"mass": 0.01, "inertia": 1e-7, "right": motor, "left": motor}}],
    }


def drive_second_world(batch):
    u = np.zeros((batch.n_worlds, batch.n_robots, 2))
    u[1] = 7.0
    return u


def refuse_fast_balls(batch):
    if batch.times[0] == 0.0 and (batch.balls[:, 2] > 0.8).any():
        raise RuntimeError("too fast")
    return None


class Recorder:
    """A stand-in client that records what would be submitted."""

    def __init__(self):
        self.calls = []

    def submit(self, *args, **kwargs):
        self.calls.append(("submit", args))

    def map(self, *args, **kwargs):
        self.calls.append(("map", args))
        return []


class TestDistributed(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                               dashboard_address=None, silence_logs=logging.ERROR)
        cls.client = distributed.Client(cls.cluster)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.cluster.close()

    def test_episodes_equal_in_process_runs(self):
        seeds = [1, 2, 3, 4, 5, 6, 7, 8, 0, 0, 20, 21, 5]  # runs of consecutive seeds, zeros, a repeat
        duration = 6.0  # s: the kick-off's 4 s stop, then play
        got = vd.run_episodes(self.client, SCENE, seeds, duration, policy, measure, control_dt=CONTROL_DT,
                              worlds_per_task=3)
        self.assertEqual(len(got), len(seeds))
        self.assertTrue(got.ok.all(), got.errors)
        np.testing.assert_array_equal(got.seeds, seeds)
        for i, seed in enumerate(seeds):
            w = local_episode(SCENE, seed, duration)
            np.testing.assert_array_equal(got.robots[i], w.robots, err_msg=f"seed {seed}")
            np.testing.assert_array_equal(got.ball[i], w.ball, err_msg=f"seed {seed}")
            np.testing.assert_array_equal(got.score[i], w.score, err_msg=f"seed {seed}")
            self.assertEqual(got.time[i], w.time)
            self.assertEqual(got.steps[i], w.step_count)
            np.testing.assert_array_equal(got.measures["ball_speed2"][i], w.ball[2] ** 2 + w.ball[3] ** 2)
            np.testing.assert_array_equal(got.measures["yellow_x"][i], w.robots[:3, 0])
        # The seeds change the episodes (the referee's placements) and the policy drives yellow.
        self.assertFalse(np.array_equal(got.robots[0], got.robots[1]))
        np.testing.assert_array_equal(got.robots[8], got.robots[9])  # seed 0 twice
        np.testing.assert_array_equal(got.robots[4], got.robots[12])  # seed 5 twice
        # Both worker processes played episodes, none of them this process.
        self.assertEqual(len(set(got.workers)), 2, got.workers)
        self.assertEqual(len(set(got.pids.tolist())), 2)
        self.assertNotIn(os.getpid(), got.pids.tolist())
        # Again, on worlds the workers may have cached: the same numbers.
        again = vd.run_episodes(self.client, SCENE, seeds, duration, policy, measure, worlds_per_task=3)
        np.testing.assert_array_equal(again.robots, got.robots)
        np.testing.assert_array_equal(again.ball, got.ball)
        np.testing.assert_array_equal(again.measures["yellow_x"], got.measures["yellow_x"])
        rows = got.rows()
        self.assertEqual(rows[3]["seed"], 4)
        self.assertEqual(rows[3]["ball_vy"], got.ball[3, 3])
        self.assertIsNone(rows[3]["error"])

    def test_worlds_are_cached_and_reset(self):
        vd.clear_cache()
        first = vd.run_episodes(None, SCENE, range(1, 5), 5.0, policy, worlds_per_task=2)
        second = vd.run_episodes(None, SCENE, range(1, 5), 5.0, policy, worlds_per_task=2)
        self.assertFalse(first.cached.any())
        self.assertTrue(second.cached.all())
        self.assertEqual(first.workers, ["local"] * 4)
        np.testing.assert_array_equal(first.robots, second.robots)
        np.testing.assert_array_equal(first.ball, second.ball)

    def test_sweep_grid(self):
        vxs, vys, seeds = [0.2, 0.5, 1.0], [0.0, 0.3], [1, 2]
        duration = 0.9  # s: 30 control periods
        rows = vd.sweep(self.client, physics_scene(), {"ball.vx": vxs, "ball.vy": vys}, seeds, duration,
                        worlds_per_task=1)
        self.assertEqual(len(rows), len(vxs) * len(vys) * len(seeds))
        self.assertEqual(rows.failed, [])
        k = 0
        for vx in vxs:  # the first key varies slowest, then the seeds
            for vy in vys:
                for seed in seeds:
                    row = rows[k]
                    self.assertEqual((row["variation"], row["ball.vx"], row["ball.vy"], row["seed"]),
                                     (k // len(seeds), vx, vy, seed))
                    scene = physics_scene()
                    scene["ball"].update(vx=vx, vy=vy)
                    w = local_episode(scene, seed, duration, drive=False)
                    self.assertEqual([row["ball_x"], row["ball_y"], row["ball_vx"], row["ball_vy"]],
                                     w.ball.tolist(), f"row {k}")
                    np.testing.assert_array_equal(row["robot_states"], w.robots)
                    self.assertEqual(row["time"], w.time)
                    k += 1
        # The observable follows the variation: a faster ball gets further.
        xs = [r["ball_x"] for r in rows if r["ball.vy"] == 0.0 and r["seed"] == 1]
        self.assertEqual(xs, sorted(xs))
        self.assertGreater(xs[-1] - xs[0], 0.3)
        self.assertEqual(len({r["worker"] for r in rows}), 2)

    def test_failures_are_reported_in_their_rows(self):
        variations = [
            {"ball.vx": 0.5},
            {"robots.*.params.mass": -0.2},  # the scene reader refuses it on the worker
            {"ball": {"z": 0.1}},  # an unknown key
            {"robots.5.x": 0.0},  # no such robot: refused before submitting
            {"ball.vx": 0.9},  # the policy raises
            {"ball.vy": -0.4},
        ]
        seeds = [1, 2, 3]
        rows = vd.sweep(self.client, physics_scene(), variations, seeds, 0.3, refuse_fast_balls,
                        worlds_per_task=2)
        self.assertEqual(len(rows), 18)
        by_variation = {}
        for r in rows:
            by_variation.setdefault(r["variation"], []).append(r)
        for v in (0, 5):
            for r in by_variation[v]:
                self.assertIsNone(r["error"])
                self.assertTrue(np.isfinite(r["ball_x"]))
        expected = {
            1: r"variation 1 .*seeds? \d.*: the scene: ValueError: .*robots\[0\]\.params\.mass: must be between",
            2: r"variation 2 .*: the scene: ValueError: .*ball\.z: unknown key",
            3: r"variation 3 .*: the variation: robots\.5\.x: index 5 is outside the list of 1",
            4: r"variation 4 .*: the policy at t = 0 s: RuntimeError: too fast",
        }
        for v, pattern in expected.items():
            self.assertEqual([r["seed"] for r in by_variation[v]], seeds)
            for r in by_variation[v]:
                self.assertRegex(r["error"], pattern)
                self.assertTrue(np.isnan(r["ball_x"]))
                self.assertEqual(r["score_yellow"], -1)
        self.assertEqual(len(rows.failed), 12)
        with self.assertRaisesRegex(vd.EpisodeError, "12 of 18 episodes failed") as caught:
            vd.sweep(self.client, physics_scene(), variations, seeds, 0.3, refuse_fast_balls, raise_errors=True)
        self.assertEqual(len(caught.exception.results), 18)

    def test_a_non_finite_world_fails_alone(self):
        got = vd.run_episodes(self.client, runaway_scene(), [1, 2, 3], 0.3, drive_second_world)
        self.assertEqual(got.ok.tolist(), [True, False, True])
        self.assertRegex(got.errors[1], r"seeds 1\.\.3, on tcp://.*, seed 2: the state of robot 0 went non-finite")
        w = local_episode(runaway_scene(), 1, 0.3, drive=False)
        np.testing.assert_array_equal(got.robots[0], w.robots)
        np.testing.assert_array_equal(got.robots[2], w.robots)
        self.assertTrue(np.isnan(got.robots[1]).all())
        self.assertEqual(got.steps[1], -1)

    def test_progress_and_timeout(self):
        seen = []
        vd.run_episodes(self.client, SCENE, range(1, 7), 0.3, worlds_per_task=2,
                        progress=lambda done, total: seen.append((done, total)))
        self.assertEqual(seen, [(1, 3), (2, 3), (3, 3)])

        def slow(batch):
            time.sleep(0.02)
            return None

        start = time.monotonic()
        got = vd.run_episodes(self.client, SCENE, [1, 2], 1.0, slow, worlds_per_task=1, timeout=0.3)
        self.assertLess(time.monotonic() - start, 5.0)
        for e in got.errors:
            self.assertRegex(e, r"not finished within the timeout of 0.3 s")

    def test_bad_arguments_raise_before_submitting(self):
        rec = Recorder()
        good = dict(scene=SCENE, seeds=[1, 2], duration=1.0)
        cases = [
            (ValueError, "duration: expected a positive finite", dict(duration=0.0)),
            (ValueError, "duration: expected a positive finite", dict(duration=-1.0)),
            (ValueError, "duration: expected a positive finite", dict(duration=float("nan"))),
            (ValueError, "duration: expected a positive finite", dict(duration=float("inf"))),
            (TypeError, "duration: expected a number", dict(duration="1")),
            (ValueError, "control_dt: expected a positive finite", dict(control_dt=0.0)),
            (ValueError, "duration / control_dt: at most", dict(duration=1e9)),
            (ValueError, "seeds: expected at least one seed", dict(seeds=[])),
            (TypeError, "seeds: expected ints", dict(seeds=[1, 2.5])),
            (TypeError, "seeds: expected ints", dict(seeds=[True])),
            (TypeError, "seeds: expected a sequence", dict(seeds=5)),
            (ValueError, "seeds: expected 0 to", dict(seeds=[-1])),
            (ValueError, "no such file or built-in scene", dict(scene="no_such_scene")),
            (ValueError, r"ball\.x: expected a number", dict(scene={"ball": {"x": "a"}})),
            (TypeError, "scene: expected a path", dict(scene=3)),
            (TypeError, "policy: expected a callable", dict(policy=3)),
            (TypeError, "policy: cannot be pickled", dict(policy=lambda b, lock=threading.Lock(): None)),
            (TypeError, "measure: expected a callable", dict(measure="x")),
            (ValueError, "command: expected 'voltages' or 'wheel_speeds'", dict(command="torque")),
            (ValueError, "worlds_per_task: expected at least 1", dict(worlds_per_task=0)),
            (ValueError, "threads: expected at least 0", dict(threads=-1)),
            (ValueError, "timeout: expected a positive", dict(timeout=0)),
        ]
        for error, pattern, change in cases:
            with self.subTest(change=change):
                with self.assertRaisesRegex(error, pattern):
                    vd.run_episodes(rec, **{**good, **change})
        for error, pattern, variations in [
            (TypeError, "variations: expected a dict", []),
            (TypeError, "variations: expected a non-empty dict", {}),
            (TypeError, r"variations\['ball.vx'\]: expected a list", {"ball.vx": 0.3}),
            (ValueError, r"variations\['ball.vx'\]: expected at least one", {"ball.vx": []}),
            (TypeError, r"variations\[1\]: expected a dict", [{"ball.vx": 0.1}, 0.2]),
        ]:
            with self.subTest(variations=variations):
                with self.assertRaisesRegex(error, pattern):
                    vd.sweep(rec, SCENE, variations, [1], 1.0)
        with self.assertRaisesRegex(TypeError, "client: expected a distributed.Client"):
            vd.run_episodes("tcp://127.0.0.1:8786", **good)
        self.assertEqual(rec.calls, [])


if __name__ == "__main__":
    unittest.main()
