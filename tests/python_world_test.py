#!/usr/bin/env python3
"""vssim.World, the in-process Python module (docs/python.md).

Run by ctest with PYTHONPATH=<build>/python and VSSIM_BINARY=<build>/app/vssim;
by hand: PYTHONPATH=build/python VSSIM_BINARY=build/app/vssim \
    /usr/bin/python3 tests/python_world_test.py
"""

import csv
import json
import math
import os
import subprocess
import tempfile
import threading
import unittest

import numpy as np

import vssim


def free_robot_scene(params=None, integrator="rk4", ball=None):
    """One robot at the origin of a 100 m box: nothing to hit for seconds."""
    robot = {"name": "r", "team": "yellow", "x": 0.0, "y": 0.0, "theta": 0.3}
    if params:
        robot["params"] = params
    return {
        "field": {"length": 100.0, "width": 100.0},
        "simulation": {"integrator": integrator, "dt": 0.001},
        "ball": ball or {"x": 40.0, "y": 40.0},
        "robots": [robot],
    }


def steady_velocity(params, e_right, e_left):
    """u_inf = B^-1 K e for M u' + B u = K e (docs/model.md, model.md §2, eq. 7)."""
    rd, re = params["right"]["wheel_radius"], params["left"]["wheel_radius"]
    b = params["wheel_base"]
    tw = np.array([[rd / 2, re / 2], [rd / b, -re / b]])  # wheel speeds -> (v, omega)
    tw_inv_t = np.linalg.inv(tw).T
    damping = np.diag([m["k"] ** 2 / m["resistance"] + m["friction"] for m in (params["right"], params["left"])])
    gain = np.diag([m["k"] / m["resistance"] for m in (params["right"], params["left"])])
    B = np.diag([params["friction_linear"], params["friction_angular"]]) + tw_inv_t @ damping @ tw_inv_t.T
    K = tw_inv_t @ gain
    return np.linalg.solve(B, K @ np.array([e_right, e_left]))


def bits(a):
    return np.ascontiguousarray(a, dtype=np.float64).tobytes()


class Loading(unittest.TestCase):
    def test_builtin_name_path_and_dict(self):
        self.assertIn("kickoff_3v3", vssim.builtin_scenes())
        w = vssim.World("kickoff_3v3")
        self.assertEqual(w.n_robots, 6)
        self.assertEqual(w.robot_teams, ["yellow"] * 3 + ["blue"] * 3)
        self.assertEqual(len(w.robot_names), 6)
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
            f.write(w.scene_json())
        try:
            from pathlib import Path
            v = vssim.World(Path(f.name))
            self.assertEqual(v.robot_names, w.robot_names)
        finally:
            os.unlink(f.name)
        d = vssim.World(json.loads(w.scene_json()))
        self.assertEqual(bits(d.robots), bits(w.robots))
        self.assertEqual(vssim.World({}).n_robots, 0)

    def test_bad_seeds(self):
        for seed in (-1, 2**64):
            with self.assertRaisesRegex(ValueError, "seed: expected a whole number from 0 to 2\\^64 - 1"):
                vssim.World("kickoff_3v3", seed=seed)
        for seed in (0.5, False, None):
            with self.assertRaisesRegex(TypeError, "seed: expected a whole number >= 0"):
                vssim.World("kickoff_3v3", seed=seed)
        self.assertEqual(vssim.World("kickoff_3v3", seed=np.uint64(2**64 - 1)).seed, 2**64 - 1)

    def test_bad_scenes(self):
        with self.assertRaisesRegex(ValueError, "no_such_scene"):
            vssim.World("no_such_scene")
        with self.assertRaisesRegex(ValueError, r"robots\[0\]\.params\.right\.resistance"):
            vssim.World({"robots": [{"params": {"right": {"resistance": "x"}}}]})
        with self.assertRaisesRegex(ValueError, "simulation.dt"):
            vssim.World({"simulation": {"dt": -1}})
        with self.assertRaises(ValueError):  # NaN is no JSON
            vssim.World({"ball": {"x": float("nan")}})
        with self.assertRaises(TypeError):
            vssim.World(42)


class Physics(unittest.TestCase):
    def test_free_robot_reaches_the_closed_form_steady_speed(self):
        w = vssim.World(free_robot_scene({"right": {"resistance": 10.0}, "left": {"resistance": 14.0, "k": 0.08}}))
        p = json.loads(w.scene_json())["robots"][0]["params"]
        for e in [(6.0, 6.0), (5.0, -3.0), (-2.0, 4.5)]:
            w.reset()
            w.set_voltages(np.array([e]))
            self.assertEqual(w.step(5.0), 5.0)
            expected = steady_velocity(p, *e)
            np.testing.assert_allclose(w.robots[0, 3:5], expected, rtol=1e-9, atol=1e-12)
            np.testing.assert_array_equal(w.voltages, [e])
            # Currents i = (e - K w_w)/R with the wheels at their steady speeds.
            wheels = w.wheel_speeds[0]
            np.testing.assert_allclose(
                w.currents[0],
                [(e[0] - p["right"]["k"] * wheels[0]) / p["right"]["resistance"],
                 (e[1] - p["left"]["k"] * wheels[1]) / p["left"]["resistance"]], rtol=1e-12, atol=1e-15)

    def test_voltages_are_clamped(self):
        w = vssim.World(free_robot_scene())
        w.set_voltages(0, 100.0, -100.0)
        np.testing.assert_array_equal(w.voltages, [[7.4, -7.4]])

    def test_wheel_speeds_through_the_speed_loop(self):
        w = vssim.World(free_robot_scene())
        w.set_wheel_speeds([[30.0, 30.0]])
        w.step(1.0)
        np.testing.assert_allclose(w.wheel_speeds[0], [30.0, 30.0], atol=0.05)

    def test_ball_decelerates_exponentially(self):
        for integrator in ("rk4", "exact"):
            w = vssim.World({"simulation": {"integrator": integrator},
                             "ball": {"x": -0.3, "y": 0.1, "vx": 0.4, "vy": -0.1, "mass": 0.046, "friction": 0.02}})
            c = 0.02 / 0.046
            for t in (0.25, 0.5, 1.0):
                w.step(t - w.time)
                decay = (1 - math.exp(-c * t)) / c
                np.testing.assert_allclose(w.ball, [-0.3 + 0.4 * decay, 0.1 - 0.1 * decay,
                                                    0.4 * math.exp(-c * t), -0.1 * math.exp(-c * t)],
                                           rtol=0, atol=1e-10, err_msg=integrator)

    def test_step_rounds_up_to_whole_steps(self):
        w = vssim.World(free_robot_scene())
        self.assertEqual(w.step(0.0101), 0.011)
        self.assertEqual(w.step_count, 11)
        w.step(1e-7)
        self.assertEqual(w.step_count, 12)
        self.assertEqual(w.step(0.03), 0.042)  # 0.03 s is 30 steps, not 31


class Determinism(unittest.TestCase):
    def run_match(self, world):
        rng = np.random.default_rng(7)
        states = []
        for k in range(40):
            world.set_voltages(rng.uniform(-7, 7, size=(world.n_robots, 2)))
            world.step(0.03)
            s = world.state()
            states.append(b"".join(bits(s[key]) for key in ("robots", "wheel_speeds", "currents", "voltages", "ball")))
        return states

    def test_two_worlds_and_a_reset_agree_bit_for_bit(self):
        scene = "vs_builtin_3v3"
        a, b = vssim.World(scene), vssim.World(scene)
        first = self.run_match(a)
        self.assertEqual(first, self.run_match(b))
        a.reset()
        self.assertEqual(a.time, 0.0)
        self.assertEqual(first, self.run_match(a))

    def test_threads_stepping_separate_worlds_agree(self):
        reference = self.run_match(vssim.World("vs_builtin_3v3"))
        results = [None, None]

        def run(i):
            results[i] = self.run_match(vssim.World("vs_builtin_3v3"))

        threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        self.assertEqual(results, [reference, reference])

    def test_one_world_used_from_two_threads_waits_for_the_step(self):
        w = vssim.World("kickoff_3v3")
        done = threading.Event()

        def stepper():
            for _ in range(200):
                w.step(0.05)
            done.set()

        t = threading.Thread(target=stepper)
        t.start()
        reads = 0
        while not done.is_set():
            s = w.state()  # a consistent copy, never a half-taken step
            self.assertEqual(s["time"], s["step_count"] * w.dt)
            w.set_voltages(np.zeros((6, 2)))
            reads += 1
        t.join()
        self.assertEqual(w.step_count, 10000)
        self.assertGreater(reads, 0)

    def test_agrees_with_vssim_run_csv(self):
        binary = os.environ.get("VSSIM_BINARY")
        if not binary or not os.path.exists(binary):
            self.skipTest("VSSIM_BINARY (build/app/vssim) not given")
        for scene, integrator in [("kickoff_3v3", "rk4"), ("robot_hits_ball", "exact"), ("speed_step", "rk4")]:
            out = subprocess.run([binary, "run", scene, "--duration", "1", "--sample", "1", "--integrator", integrator],
                                 check=True, capture_output=True, text=True).stdout
            rows = [r for r in csv.DictReader(out.splitlines()) if r["t"] == "1"]
            scene_json = json.loads(vssim.World(scene).scene_json())
            scene_json["simulation"]["integrator"] = integrator
            w = vssim.World(scene_json)
            w.step(1.0)
            self.assertEqual(w.time, 1.0)
            names = w.robot_names
            self.assertEqual([r["body"] for r in rows], names + ["ball"])
            for i, r in enumerate(rows[:-1]):
                got = list(w.robots[i]) + list(w.voltages[i]) + list(w.wheel_speeds[i]) + list(w.currents[i])
                keys = ["x", "y", "theta", "v", "omega", "e_right", "e_left", "omega_right", "omega_left",
                        "i_right", "i_left"]
                self.assertEqual(["%.17g" % x for x in got], [r[k] for k in keys], f"{scene} {names[i]}")
            bx, by, bvx, bvy = w.ball
            ball = rows[-1]
            self.assertEqual(["%.17g" % x for x in (bx, by, math.atan2(bvy, bvx), math.hypot(bvx, bvy))],
                             [ball[k] for k in ("x", "y", "theta", "v")], scene)


class Game(unittest.TestCase):
    def test_kickoff_then_a_goal_by_placing_the_ball(self):
        w = vssim.World("kickoff_3v3")
        self.assertTrue(w.game["referee"])
        self.assertEqual(w.phase, "stop")
        self.assertEqual(w.last_call["call"], "kickoff")
        self.assertEqual(w.score, (0, 0))
        self.assertEqual(w.half, 1)
        w.step(4.5)
        self.assertEqual(w.phase, "game_on")
        # Yellow attacks the goal at x > 0: the ball well inside it.
        w.place_ball(0.80, 0.0)
        w.step(0.05)
        self.assertEqual(w.score, (1, 0))
        self.assertEqual(w.game["goals"], {"yellow": 1, "blue": 0})
        self.assertEqual(w.phase, "stop")
        self.assertEqual(w.last_call["call"], "kickoff")
        self.assertEqual(w.last_call["team"], "blue")
        self.assertIn("goal", w.last_call["reason"])
        self.assertEqual([c["call"] for c in w.calls], ["kickoff", "kickoff"])

    def test_robots_held_at_zero_volts_during_stop(self):
        w = vssim.World("kickoff_3v3")
        w.set_voltages(np.full((6, 2), 5.0))
        w.step(0.1)
        self.assertEqual(w.phase, "stop")
        np.testing.assert_array_equal(w.voltages, np.zeros((6, 2)))

    def test_remote_team_takes_voltages_once_the_game_is_on(self):
        w = vssim.World("vs_builtin_3v3")  # yellow remote, blue built-in
        e = np.tile([3.0, 2.0], (6, 1))
        w.set_voltages(e)
        w.step(0.1)
        np.testing.assert_array_equal(w.voltages[:3], np.zeros((3, 2)))
        w.step(4.5)
        self.assertEqual(w.phase, "game_on")
        np.testing.assert_array_equal(w.voltages[:3], e[:3])


class Camera(unittest.TestCase):
    def test_image_shape_and_the_ball_where_it_is(self):
        w = vssim.World("kickoff_3v3")
        field = json.loads(w.scene_json())["field"]
        img = w.camera_image()
        self.assertEqual(img.shape, (480, 640, 3))
        self.assertEqual(img.dtype, np.uint8)
        h, wd = img.shape[:2]
        scale = min((wd - 40) / (field["length"] + 2 * field["goal_depth"]), (h - 40) / field["width"])
        for x, y in [(0.3, 0.2), (-0.5, -0.4)]:
            w.place_ball(x, y)
            img = w.camera_image()
            b, g, r = (img[..., k].astype(int) for k in range(3))
            orange = (b < 60) & (abs(g - 128) < 40) & (r > 200)  # BGR (0, 128, 255)
            rows, cols = np.nonzero(orange)
            self.assertGreater(len(rows), 50)
            self.assertAlmostEqual(cols.mean() + 0.5, wd / 2 + scale * x, delta=1.0)
            self.assertAlmostEqual(rows.mean() + 0.5, h / 2 - scale * y, delta=1.0)

    def test_a_scene_camera_renders_through_its_lens_and_noise(self):
        scene = json.loads(vssim.World("kickoff_3v3").scene_json())
        scene["camera"] = {"preset": "realistic"}
        w = vssim.World(scene)
        ideal = vssim.World("kickoff_3v3").camera_image()
        first = w.camera_image()
        # The same state gives the same bytes; the realistic image is not the ideal one.
        self.assertTrue(np.array_equal(first, w.camera_image()))
        self.assertFalse(np.array_equal(first, ideal))
        # Vignetting: the image's corners are darker than the ideal camera's
        # (the same grey outside the walls there).
        corners = [(2, 2), (2, 637), (477, 2), (477, 637)]
        for r, c in corners:
            self.assertLess(first[r - 2:r + 3, c - 2:c + 3].mean(), ideal[r - 2:r + 3, c - 2:c + 3].mean() - 10)
        # The sensor noise changes from step to step (drawn from the step
        # number): a region where nothing moves differs, by about the noise.
        w.step(0.001)
        second = w.camera_image()
        still = (slice(380, 440), slice(150, 250))  # bare floor, bottom left
        difference = second[still].astype(float) - first[still].astype(float)
        self.assertGreater(np.abs(difference).mean(), 1.0)
        self.assertAlmostEqual(difference.std() / np.sqrt(2), 3.0, delta=0.5)


class BadInput(unittest.TestCase):
    def setUp(self):
        self.w = vssim.World("kickoff_3v3")

    def test_arrays(self):
        w = self.w
        with self.assertRaisesRegex(ValueError, r"shape \(6, 2\).*got \(5, 2\)"):
            w.set_voltages(np.zeros((5, 2)))
        with self.assertRaisesRegex(ValueError, r"got \(12,\)"):
            w.set_voltages(np.zeros(12))
        with self.assertRaises(ValueError):
            w.set_wheel_speeds(np.zeros((6, 3)))
        with self.assertRaises((TypeError, ValueError)):
            w.set_voltages("volts")
        with self.assertRaises((TypeError, ValueError)):
            w.set_voltages([[object(), 1]] * 6)
        w.set_voltages(np.zeros((6, 2), dtype=np.int32))  # convertible: fine
        w.set_voltages([[1, 2]] * 6)
        w.set_voltages(np.zeros((6, 2), dtype=np.float32)[:, ::-1])  # not contiguous: fine

    def test_nan_names_robot_and_side(self):
        e = np.zeros((6, 2))
        e[4, 1] = np.nan
        with self.assertRaisesRegex(ValueError, r"robot 4 \(blue1\): the left voltage is nan"):
            self.w.set_voltages(e)
        with self.assertRaisesRegex(ValueError, r"robot 2 .*right wheel speed is inf"):
            self.w.set_wheel_speeds(2, float("inf"), 0.0)

    def test_unknown_robot(self):
        w = self.w
        for robot in (6, -1, 2**40, -2**62):
            with self.assertRaisesRegex(IndexError, f"robot {robot} does not exist"):
                w.set_voltages(robot, 1.0, 1.0)
            with self.assertRaises(IndexError):
                w.set_wheel_speeds(robot, 1.0, 1.0)
            with self.assertRaises(IndexError):
                w.place_robot(robot, 0.0, 0.0, 0.0)

    def test_step(self):
        for seconds in (0.0, -1.0, float("nan"), float("inf"), 1e300):
            with self.assertRaises(ValueError, msg=seconds):
                self.w.step(seconds)
        with self.assertRaises(TypeError):
            self.w.step("1")
        self.assertEqual(self.w.step_count, 0)

    def test_placements(self):
        w = self.w
        with self.assertRaisesRegex(ValueError, "would not lie inside"):
            w.place_ball(0.9, 0.0)
        with self.assertRaisesRegex(ValueError, "would not lie inside"):
            w.place_robot(0, 0.74, 0.4, 0.0)  # through the end wall beside the goal
        with self.assertRaises(ValueError):
            w.place_ball(float("nan"), 0.0)
        with self.assertRaises(ValueError):
            w.place_ball(0.0, 0.0, 100.0, 0.0)
        w.place_robot(0, 0.1, 0.2, 0.3)
        np.testing.assert_array_equal(w.robots[0], [0.1, 0.2, 0.3, 0.0, 0.0])

    def test_closed(self):
        with vssim.World("kickoff_3v3") as w:
            w.step(0.01)
        self.assertTrue(w.closed)
        for call in (lambda: w.step(0.1), lambda: w.robots, lambda: w.camera_image(), lambda: w.reset(),
                     lambda: w.set_voltages(0, 1.0, 1.0)):
            with self.assertRaisesRegex(RuntimeError, "closed"):
                call()

    def test_non_finite_state_raises(self):
        # Motors far too stiff for RK4 at 10 ms (as test_cli's runaway scene): the state overflows.
        motor = {"resistance": 0.001, "k": 100, "rotor_inertia": 0}
        scene = free_robot_scene({"mass": 0.01, "inertia": 1e-7, "right": motor, "left": motor})
        scene["simulation"]["dt"] = 0.01
        w = vssim.World(scene)
        w.set_voltages(0, 7.0, 7.0)
        with self.assertRaisesRegex(RuntimeError, "non-finite"):
            for _ in range(100):
                w.step(0.1)
        with self.assertRaises(RuntimeError):
            w.step(0.1)
        w.reset()
        w.step(0.01)
        self.assertEqual(w.step_count, 1)


if __name__ == "__main__":
    unittest.main()
