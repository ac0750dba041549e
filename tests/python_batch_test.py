#!/usr/bin/env python3
"""vssim.BatchWorld from Python (docs/python.md): n worlds stepped together
on a pool of threads, each bit-identical to a vssim.World run alone with the
same inputs, whatever the thread count; bad input raises; several Python
threads may call one BatchWorld at once (each call waits for the one running).

Run by ctest with PYTHONPATH=<build>/python; by hand:
    PYTHONPATH=build/python /usr/bin/python3 tests/python_batch_test.py
"""

import threading
import unittest

import numpy as np

import vssim

SCENE = "kickoff_3v3"  # the referee and the built-in teams: every world ticks


def remote_match():
    """The kick-off with both teams remote and a short opening stop, as a dict."""
    return {
        "field": {"type": "vsss_3v3"},
        "ball": {"x": 0.0, "y": 0.0},
        "robots": [
            {"team": "yellow", "x": -0.2, "y": 0.0}, {"team": "yellow", "x": -0.4, "y": 0.3},
            {"team": "yellow", "x": -0.6, "y": 0.0}, {"team": "blue", "x": 0.2, "y": 0.1},
            {"team": "blue", "x": 0.4, "y": -0.3}, {"team": "blue", "x": 0.6, "y": 0.0},
        ],
        "game": {"referee": True, "yellow": "remote", "blue": "remote", "stop_duration": 0.2},
    }


def inputs(n_worlds, n_robots, k):
    """Different voltages for every world, robot and control step k, V."""
    w = np.arange(n_worlds)[:, None, None]
    r = np.arange(n_robots)[None, :, None]
    side = np.array([1.0, -0.5])[None, None, :]
    return 5.0 * np.sin(0.7 * w + 1.3 * r + 0.2 * k) * side + 1.5


class TestBatchWorld(unittest.TestCase):
    def run_batch(self, scene, n, threads, steps=30, seed=0, wheel=False):
        batch = vssim.BatchWorld(n, scene, threads=threads, seed=seed)
        for k in range(steps):
            u = inputs(n, batch.n_robots, k)
            if wheel:
                batch.set_wheel_speeds(8.0 * u)
            else:
                batch.set_voltages(u)
            batch.step(0.03)
        return batch

    def test_each_world_matches_a_lone_world(self):
        for scene, seed in ((remote_match(), 0), (SCENE, 7)):
            batch = self.run_batch(scene, 4, threads=2, seed=seed)
            for i in range(4):
                world = vssim.World(scene, seed=0 if seed == 0 else seed + i)
                for k in range(30):
                    world.set_voltages(inputs(4, world.n_robots, k)[i])
                    world.step(0.03)
                self.assertTrue(np.array_equal(batch.robots[i], world.robots), f"world {i}")
                self.assertTrue(np.array_equal(batch.balls[i], world.ball), f"world {i}")
                self.assertEqual(tuple(batch.scores[i]), tuple(world.score))
                self.assertEqual(batch.times[i], world.time)

    def test_steps_between_ticks_match_a_lone_world(self):
        # 15 ms control periods with 10 ms game ticks: the batch takes whole
        # steps (15), as World.step does, and stays bit-identical to it.
        batch = vssim.BatchWorld(2, SCENE, threads=2, seed=4)
        world = vssim.World(SCENE, seed=5)
        for k in range(300):
            self.assertEqual(batch.step(0.015), 15)
            world.step(0.015)
        self.assertEqual(batch.times[1], world.time)
        self.assertTrue(np.array_equal(batch.robots[1], world.robots))
        self.assertTrue(np.array_equal(batch.balls[1], world.ball))

    def test_thread_count_changes_nothing(self):
        one = self.run_batch(remote_match(), 5, threads=1, wheel=True)
        three = self.run_batch(remote_match(), 5, threads=3, wheel=True)
        self.assertTrue(np.array_equal(one.robots, three.robots))
        self.assertTrue(np.array_equal(one.balls, three.balls))
        # The worlds differ from each other (their inputs do).
        self.assertFalse(np.array_equal(one.robots[0], one.robots[1]))

    def test_shapes_and_reset(self):
        batch = self.run_batch(remote_match(), 3, threads=0, steps=10)
        self.assertEqual(batch.robots.shape, (3, 6, 5))
        self.assertEqual(batch.balls.shape, (3, 4))
        self.assertEqual(batch.scores.shape, (3, 2))
        fresh = vssim.World(remote_match())
        batch.reset(1)
        self.assertTrue(np.array_equal(batch.robots[1], fresh.robots))
        self.assertEqual(batch.times[1], 0.0)
        self.assertGreater(batch.times[0], 0.0)
        batch.reset_all()
        self.assertTrue(np.all(batch.times == 0.0))

    def test_placement_and_wheel_speeds_match_a_lone_world(self):
        # The same placements and wheel-speed targets given to world 1 of a
        # batch and to a lone World give the same states, bit for bit.
        batch = vssim.BatchWorld(3, remote_match(), threads=2)
        world = vssim.World(remote_match())
        batch.place_robot(1, 2, 0.1, -0.2, 1.0, v=0.3, omega=-2.0)
        world.place_robot(2, 0.1, -0.2, 1.0, v=0.3, omega=-2.0)
        batch.place_ball(1, -0.3, 0.25, vx=1.5, vy=-0.5)
        world.place_ball(-0.3, 0.25, vx=1.5, vy=-0.5)
        targets = np.zeros((3, 6, 2))
        targets[1] = np.linspace(-30.0, 40.0, 12).reshape(6, 2)
        batch.set_wheel_speeds(targets)
        world.set_wheel_speeds(targets[1])
        self.assertTrue(np.array_equal(batch.robots[1], world.robots))
        for _ in range(20):
            batch.step(0.03)
            world.step(0.03)
        self.assertTrue(np.array_equal(batch.robots[1], world.robots))
        self.assertTrue(np.array_equal(batch.balls[1], world.ball))
        self.assertTrue(np.array_equal(batch.wheel_speeds[1], world.wheel_speeds))
        self.assertEqual(batch.wheel_speeds.shape, (3, 6, 2))
        # The other worlds were not moved.
        self.assertTrue(np.array_equal(batch.robots[0], batch.robots[2]))
        # The clock: dt and each world's steps.
        self.assertEqual(batch.dt, 0.001)
        self.assertEqual(batch.step_counts.tolist(), [600, 600, 600])
        np.testing.assert_array_equal(batch.times, batch.step_counts * batch.dt)
        # The scene every world plays, spelled out.
        self.assertEqual(batch.scene_json(), world.scene_json())

    def test_bad_placements(self):
        batch = vssim.BatchWorld(2, remote_match(), threads=1)
        before = batch.robots
        with self.assertRaisesRegex(ValueError, r"world 1, robot 0 at \(0\.9, 0\) m.*would not lie inside"):
            batch.place_robot(1, 0, 0.9, 0.0, 0.0)
        with self.assertRaisesRegex(ValueError, "world 0, robot 3: x, y, theta, v and omega must be finite"):
            batch.place_robot(0, 3, float("nan"), 0.0, 0.0)
        with self.assertRaisesRegex(ValueError, r"\|v\| must be at most"):
            batch.place_robot(0, 3, 0.0, 0.0, 0.0, v=50.0)
        with self.assertRaises(IndexError):
            batch.place_robot(2, 0, 0.0, 0.0, 0.0)
        with self.assertRaises(IndexError):
            batch.place_robot(0, 6, 0.0, 0.0, 0.0)
        with self.assertRaisesRegex(ValueError, "world 1, the ball at .* would not lie inside"):
            batch.place_ball(1, 0.0, 0.7)
        with self.assertRaisesRegex(ValueError, "world 1, the ball: its speed must be at most"):
            batch.place_ball(1, 0.0, 0.0, vx=100.0)
        with self.assertRaisesRegex(ValueError, "finite"):
            batch.place_ball(0, 0.0, float("inf"))
        self.assertTrue(np.array_equal(batch.robots, before))

    def test_a_world_that_blows_up_is_frozen_alone(self):
        # Motors far too stiff for RK4 at 10 ms: driven, world 1 overflows to
        # NaN; it then stays where it stopped (no more steps, which on NaN
        # would be slow and meaningless) while world 0 goes on, until reset.
        motor = {"resistance": 0.001, "k": 100, "rotor_inertia": 0}
        scene = {"field": {"length": 100.0, "width": 100.0}, "simulation": {"integrator": "rk4", "dt": 0.01},
                 "ball": {"x": 40.0, "y": 40.0},
                 "robots": [{"x": 0.0, "y": 0.0, "theta": 0.3,
                             "params": {"mass": 0.01, "inertia": 1e-7, "right": motor, "left": motor}}]}
        batch = vssim.BatchWorld(2, scene, threads=2)
        u = np.zeros((2, 1, 2))
        u[1] = 7.0
        batch.set_voltages(u)
        for _ in range(20):
            batch.step(0.03)
        self.assertFalse(np.all(np.isfinite(batch.robots[1])))
        frozen = batch.times[1]
        self.assertLess(frozen, batch.times[0])
        for _ in range(5):
            batch.step(0.03)
        self.assertEqual(batch.times[1], frozen)
        self.assertAlmostEqual(batch.times[0], 25 * 0.03)
        batch.reset(1)
        self.assertTrue(np.all(np.isfinite(batch.robots[1])))
        batch.step(0.03)
        self.assertAlmostEqual(batch.times[1], 0.03)

    def test_bad_input(self):
        batch = vssim.BatchWorld(2, remote_match(), threads=1)
        with self.assertRaisesRegex(ValueError, r"expected shape \(2, 6, 2\)"):
            batch.set_voltages(np.zeros((2, 6)))
        with self.assertRaises(TypeError):
            batch.set_voltages("volts")
        bad = np.zeros((2, 6, 2))
        bad[1, 3, 0] = np.nan
        with self.assertRaisesRegex(ValueError, "world 1, robot 3: the right voltage is nan"):
            batch.set_voltages(bad)
        bad[1, 3, 0] = 0.0
        bad[0, 5, 1] = -np.inf
        with self.assertRaisesRegex(ValueError, "world 0, robot 5: the left wheel speed is -inf"):
            batch.set_wheel_speeds(bad)
        for seconds in (0.0, -1.0, float("nan"), float("inf")):
            with self.assertRaises(ValueError):
                batch.step(seconds)
        with self.assertRaises(IndexError):
            batch.reset(2)
        with self.assertRaises(ValueError):
            vssim.BatchWorld(0, remote_match())
        with self.assertRaises(ValueError):
            vssim.BatchWorld(2, {"robots": [{"team": "purple"}]})
        with self.assertRaises(ValueError):
            vssim.BatchWorld(2, remote_match(), threads=-1)
        with self.assertRaisesRegex(ValueError, "seed: expected a whole number from 0 to 2\\^64 - 1, got -1"):
            vssim.BatchWorld(2, remote_match(), seed=-1)
        for seed in (1.5, True, "7"):
            with self.assertRaisesRegex(TypeError, "seed: expected a whole number"):
                vssim.BatchWorld(2, remote_match(), seed=seed)
        with self.assertRaisesRegex(ValueError, r"1e\+300 s is too long"):
            batch.step(1e300)
        # Still usable after all of that.
        batch.set_voltages(np.ones((2, 6, 2)))
        self.assertGreater(batch.step(0.03), 0)


class TestBatchWorldFromSeveralThreads(unittest.TestCase):
    """One thread steps while another resets, places, commands and reads: each
    call waits for the one running (the GIL is released in step and
    reset_all), so nothing crashes and no read shows a half-taken step."""

    STEPS = 1000  # step(0.05) calls of the stepping thread: 50 steps of 1 ms each

    def run_alongside(self, batch, other):
        """Runs other() over and over while a second thread steps `batch` STEPS
        times; returns how many times other() ran (at least once)."""
        done = threading.Event()
        failure = []

        def stepper():
            try:
                for _ in range(self.STEPS):
                    self.assertEqual(batch.step(0.05), 50)
            except BaseException as e:  # reported by the main thread
                failure.append(e)
            finally:
                done.set()

        t = threading.Thread(target=stepper)
        t.start()
        calls = 0
        try:
            while not done.is_set() or calls == 0:
                other()
                calls += 1
        finally:
            done.wait()
            t.join()
        if failure:
            raise failure[0]
        return calls

    def test_reset_place_command_and_read_while_another_thread_steps(self):
        n = 4
        batch = vssim.BatchWorld(n, remote_match(), threads=2)
        zeros = np.zeros((n, batch.n_robots, 2))
        fresh = vssim.World(remote_match())
        k = [0]

        def other():
            i = 1 + k[0] % (n - 1)  # world 0 is left to the stepping thread alone
            k[0] += 1
            batch.reset(i)
            batch.place_robot(i, 2, 0.1, -0.2, 1.0, v=0.3)
            batch.place_ball(i, -0.3, 0.25, vx=1.5)
            batch.set_voltages(zeros)  # 0 V: what every robot has anyway
            batch.set_wheel_speeds(zeros)
            steps = batch.step_counts
            times = batch.times
            robots, balls, wheels = batch.robots, batch.balls, batch.wheel_speeds
            # Whole steps of 0.05 s only: never a world caught in the middle of one.
            self.assertTrue(np.all(steps % 50 == 0), steps)
            np.testing.assert_allclose(np.round(times / 0.05) * 0.05, times, rtol=0, atol=1e-9)
            self.assertTrue(np.all(np.isfinite(robots)) and np.all(np.isfinite(balls)) and np.all(np.isfinite(wheels)))
            self.assertEqual(batch.scores.shape, (n, 2))
            self.assertEqual(batch.dt, 0.001)

        self.assertGreater(self.run_alongside(batch, other), 0)
        # World 0 was only stepped (at 0 V): the lone World stepped as often, bit for bit.
        world = vssim.World(remote_match())
        for _ in range(self.STEPS):
            world.step(0.05)
        self.assertEqual(batch.step_counts[0], 50 * self.STEPS)
        self.assertTrue(np.array_equal(batch.robots[0], world.robots))
        self.assertTrue(np.array_equal(batch.balls[0], world.ball))
        # With no step running, a reset world is exactly the scene's start.
        for i in range(n):
            batch.reset(i)
            self.assertTrue(np.array_equal(batch.robots[i], fresh.robots))
            self.assertTrue(np.array_equal(batch.balls[i], fresh.ball))
            self.assertEqual(batch.step_counts[i], 0)

    def test_reset_all_while_another_thread_steps(self):
        # Every world is reset and stepped together, so every read finds them
        # all on the same whole step of 0.05 s.
        batch = vssim.BatchWorld(6, remote_match(), threads=2)

        def other():
            batch.reset_all()
            for steps in (batch.step_counts, np.round(batch.times / batch.dt).astype(np.int64)):
                self.assertTrue(np.all(steps == steps[0]), steps)
                self.assertEqual(steps[0] % 50, 0)

        self.assertGreater(self.run_alongside(batch, other), 0)
        batch.reset_all()
        fresh = vssim.World(remote_match())
        for i in range(6):
            self.assertTrue(np.array_equal(batch.robots[i], fresh.robots))


if __name__ == "__main__":
    unittest.main()
