#!/usr/bin/env python3
"""vssim.env (docs/python.md, "Gym-style environments"): the Gymnasium API
without Gymnasium installed, the two tasks' observations, rewards and ends
against independent computations from the world's state, actions as
voltages and as wheel speeds, the vector environment bit-identical to single
ones (worlds, rewards and observations), bad input, and registration when Gymnasium is importable (a stand-in
module).

Run by ctest with PYTHONPATH=<build>/python; by hand:
    PYTHONPATH=build/python /usr/bin/python3 tests/python_env_test.py
"""

import math
import os
import subprocess
import sys
import tempfile
import textwrap
import unittest

import numpy as np

import vssim
from vssim.env import GoToBall, ScoreGoal, VssimEnv, VssimVectorEnv


def point_segment(p, a, b):
    """Distance from point p to segment ab (2-vectors), m."""
    ab, ap = b - a, p - a
    t = min(1.0, max(0.0, float(np.dot(ap, ab) / np.dot(ab, ab))))
    return float(np.linalg.norm(ap - t * ab))


def gap(robot, ball, side=0.075, radius=0.02135):
    """The ball's surface to the robot's square, from its four edges (0 inside)."""
    x, y, theta = robot[:3]
    c, s = math.cos(theta), math.sin(theta)
    corners = [np.array([x + c * u - s * v, y + s * u + c * v])
               for u, v in ((side / 2, side / 2), (-side / 2, side / 2), (-side / 2, -side / 2), (side / 2, -side / 2))]
    p = np.asarray(ball[:2])
    local = np.array([c * (p[0] - x) + s * (p[1] - y), -s * (p[0] - x) + c * (p[1] - y)])
    if np.all(np.abs(local) <= side / 2):
        return 0.0
    d = min(point_segment(p, corners[k], corners[(k + 1) % 4]) for k in range(4))
    return max(d - radius, 0.0)


def steer_to_ball(obs):
    """A simple controller on GoToBall's observation: turn to the ball, drive."""
    angle = math.atan2(obs[1], obs[0])
    forward = 0.7 * max(math.cos(angle), 0.0)
    turn = 0.4 * max(-1.0, min(1.0, 2.0 * angle))
    return np.array([forward + turn, forward - turn])


class TestSingleEnv(unittest.TestCase):
    def test_api_and_spaces(self):
        env = VssimEnv("GoToBall")
        self.assertEqual(env.action_space.shape, (2,))
        self.assertEqual(env.observation_space.shape, (12,))
        obs, info = env.reset(seed=3)
        self.assertEqual(obs.shape, (12,))
        self.assertEqual(obs.dtype, np.float32)
        self.assertTrue(env.observation_space.contains(obs))
        self.assertEqual(info["time"], 0.0)
        result = env.step(np.zeros(2))
        self.assertEqual(len(result), 5)
        obs, reward, terminated, truncated, info = result
        self.assertIsInstance(reward, float)
        self.assertIsInstance(terminated, bool)
        self.assertIsInstance(truncated, bool)
        self.assertAlmostEqual(info["time"], 0.03)
        self.assertEqual(env.world.time, 0.03)
        self.assertEqual(ScoreGoal.observation_low.shape, (len(ScoreGoal.observation_names),))
        self.assertEqual(GoToBall.observation_low.shape, (len(GoToBall.observation_names),))

    def test_seeds_give_the_same_episode(self):
        def episode(seed):
            env = VssimEnv("GoToBall")
            obs, _ = env.reset(seed=seed)
            trace = [obs]
            for k in range(40):
                obs, reward, *_ = env.step([math.sin(0.3 * k), math.cos(0.2 * k)])
                trace.append(np.append(obs, reward))
            return trace

        a, b, c = episode(5), episode(5), episode(6)
        for x, y in zip(a, b):
            self.assertTrue(np.array_equal(x, y))
        self.assertFalse(np.array_equal(a[0], c[0]))

    def test_go_to_ball_start_and_observation(self):
        env = VssimEnv("GoToBall")
        for seed in range(20):
            obs, _ = env.reset(seed=seed)
            robot, ball = env.world.robots[0], env.world.ball
            self.assertTrue(np.all(np.abs(robot[:2]) <= [0.65, 0.55]), robot)
            self.assertTrue(np.all(np.abs(ball[:2]) <= [0.65, 0.55]), ball)
            self.assertGreaterEqual(math.hypot(*(ball[:2] - robot[:2])), 0.2)
            self.assertTrue(np.all(robot[3:] == 0.0) and np.all(ball[2:] == 0.0))
        # Drive a while, then check every observation from the world's state.
        for k in range(15):
            obs, *_ = env.step([0.8, 0.3])
        x, y, theta, v, omega = env.world.robots[0]
        bx, by = env.world.ball[:2]
        ahead = (bx - x) * math.cos(theta) + (by - y) * math.sin(theta)
        left = -(bx - x) * math.sin(theta) + (by - y) * math.cos(theta)
        expected = [ahead, left, v, omega, *env.world.wheel_speeds[0], x, y, math.cos(theta), math.sin(theta), bx, by]
        np.testing.assert_allclose(obs, np.float32(expected), rtol=1e-6, atol=1e-6)
        self.assertGreater(v, 0.1)

    def test_go_to_ball_rewards_telescope_and_touching_ends(self):
        env = VssimEnv("GoToBall")
        obs, _ = env.reset(seed=11)
        start_gap = gap(env.world.robots[0], env.world.ball)
        total, steps = 0.0, 0
        while True:
            obs, reward, terminated, truncated, info = env.step(steer_to_ball(obs))
            total += reward
            steps += 1
            if terminated or truncated:
                break
        self.assertTrue(terminated, "the controller reaches the ball")
        end_gap = gap(env.world.robots[0], env.world.ball)
        self.assertLess(end_gap, 0.005)
        # Potential-based: the rewards add up to 10 per metre closed, plus 10.
        self.assertAlmostEqual(total, 10.0 * (start_gap - end_gap) + 10.0, places=9)
        self.assertAlmostEqual(info["episode_return"], total, places=12)
        self.assertEqual(info["episode_length"], steps)
        with self.assertRaisesRegex(RuntimeError, "reset"):
            env.step([0.0, 0.0])

    def test_truncation_after_ten_seconds(self):
        env = VssimEnv("GoToBall")
        env.reset(seed=2)
        self.assertEqual(env.max_episode_steps, 334)  # ceil(10 s / 30 ms)
        for k in range(env.max_episode_steps):
            _, reward, terminated, truncated, info = env.step([0.0, 0.0])
            self.assertFalse(terminated)
            self.assertEqual(reward, 0.0)  # standing still: no progress, no reward
            self.assertEqual(truncated, k == env.max_episode_steps - 1)

    def test_actions_as_voltages_and_as_wheel_speeds(self):
        env = VssimEnv("GoToBall", action_type="voltages")
        env.reset(seed=1)
        env.step([1.0, -0.5])
        np.testing.assert_array_equal(env.world.voltages[0], [7.4, -3.7])
        env.step([3.0, -9.0])  # clipped to [-1, 1]
        np.testing.assert_array_equal(env.world.voltages[0], [7.4, -7.4])

        env = VssimEnv("GoToBall", action_type="wheel_speeds")
        # The free wheel speed of the default robot: K e / (K^2 + R beta).
        self.assertAlmostEqual(env.action_scale, 0.09 * 7.4 / (0.09 ** 2 + 12 * 1e-4), places=12)
        env.reset(seed=4)
        env.world.place_robot(0, 0.0, 0.0, 0.0)  # room to spin on the spot
        for _ in range(20):
            env.step([0.3, -0.3])
        np.testing.assert_allclose(env.world.wheel_speeds[0], [0.3 * env.action_scale, -0.3 * env.action_scale],
                                   rtol=0.01)

    def test_score_goal_goals_agree_with_the_referee(self):
        env = VssimEnv("ScoreGoal")
        obs, _ = env.reset(seed=0)
        self.assertEqual(obs.shape, (18,))
        keeper = env.world.robots[1]
        self.assertAlmostEqual(keeper[0], 0.68)
        # The same shot, in this task and in a World with the referee on.
        shot = (0.4, 0.1, 2.0, 0.0)
        refereed = dict(ScoreGoal.scene)
        refereed["game"] = {"referee": True, "yellow": "remote", "blue": "idle", "stop_duration": 0.0}
        judge = vssim.World(refereed)
        judge.step(0.03)  # the kick-off's zero-length stop
        env.world.place_robot(1, 0.6, 0.55, 0.0)  # the keeper out of the way
        judge.place_robot(1, 0.6, 0.55, 0.0)
        env.world.place_ball(*shot)
        judge.place_ball(*shot)
        def potential():  # ScoreGoal's, from the state
            bx, by = env.world.ball[:2]
            return -10.0 * math.hypot(max(0.75 - bx, 0.0), by) - 2.0 * gap(env.world.robots[0], env.world.ball)

        for k in range(30):
            before = potential()
            _, reward, terminated, truncated, _ = env.step([0.0, 0.0])
            judge.step(0.03)
            self.assertEqual(terminated, judge.score[0] == 1, f"step {k}")
            if k > 0:  # (the first step's "before" is the env's, from before the placements)
                self.assertAlmostEqual(reward, potential() - before + (10.0 if terminated else 0.0), places=9)
            if terminated:
                break
        self.assertTrue(terminated)

        env.reset(seed=0)
        env.world.place_ball(-0.5, 0.0, -2.0, 0.0)  # into yellow's own goal
        env.step([0.0, 0.0])
        for _ in range(30):
            before = potential()
            _, reward, terminated, *_ = env.step([0.0, 0.0])
            if terminated:
                break
        self.assertTrue(terminated)
        self.assertAlmostEqual(reward, potential() - before - 10.0, places=9)

    def test_the_builtin_goalkeeper_guards(self):
        env = VssimEnv("ScoreGoal")
        env.reset(seed=0)
        env.world.place_ball(0.3, 0.25)
        for _ in range(40):
            env.step([0.0, 0.0])
        self.assertGreater(env.world.robots[1][1], 0.05)  # it moved across towards the ball's side

    def test_render(self):
        env = VssimEnv("GoToBall", render_mode="rgb_array")
        env.reset(seed=0)
        image = env.render()
        self.assertEqual(image.shape, (480, 640, 3))
        self.assertEqual(image.dtype, np.uint8)
        np.testing.assert_array_equal(image, env.world.camera_image()[..., ::-1])
        self.assertIsNone(VssimEnv("GoToBall").render())

    def test_bad_input(self):
        with self.assertRaisesRegex(ValueError, "task: expected one of"):
            VssimEnv("Dribble")
        with self.assertRaisesRegex(ValueError, "action_type"):
            VssimEnv("GoToBall", action_type="torques")
        self.assertEqual(VssimEnv("GoToBall", control_period=np.float32(0.03)).control_period, float(np.float32(0.03)))
        for period in (0, -0.03, float("nan"), float("inf"), "fast", True):
            with self.assertRaisesRegex(ValueError, "control_period"):
                VssimEnv("GoToBall", control_period=period)
        with self.assertRaisesRegex(ValueError, "render_mode"):
            VssimEnv("GoToBall", render_mode="human")
        env = VssimEnv("GoToBall")
        with self.assertRaisesRegex(RuntimeError, "before reset"):
            env.step([0.0, 0.0])
        env.reset(seed=0)
        with self.assertRaisesRegex(ValueError, r"expected 2 numbers"):
            env.step([1.0, 2.0, 3.0])
        with self.assertRaisesRegex(ValueError, "the left value is nan"):
            env.step([0.0, float("nan")])
        with self.assertRaisesRegex(ValueError, "numbers"):
            env.step(["a", "b"])
        self.assertEqual(env.world.time, 0.0)  # nothing was stepped
        env.step([0.5, 0.5])
        self.assertGreater(env.world.time, 0.0)


class TestVectorEnv(unittest.TestCase):
    def test_bit_identical_to_single_envs_through_resets(self):
        for task, action_type in (("GoToBall", "voltages"), ("ScoreGoal", "wheel_speeds")):
            n = 3
            vec = VssimVectorEnv(task, num_envs=n, action_type=action_type, threads=2)
            singles = [VssimEnv(task, action_type=action_type) for _ in range(n)]
            obs, _ = vec.reset(seed=20)
            self.assertEqual(obs.shape, (n, vec.single_observation_space.shape[0]))
            for i, env in enumerate(singles):
                self.assertTrue(np.array_equal(env.reset(seed=20 + i)[0], obs[i]))
            rng = np.random.default_rng(0)
            ended = 0
            for k in range(500):
                # Drive to the ball with noise: episodes end (touch, goal) and restart.
                actions = np.array([steer_to_ball(o if task == "GoToBall" else o[12:14]) for o in obs])
                actions += rng.normal(0.0, 0.3, actions.shape)
                obs, rewards, terminated, truncated, infos = vec.step(actions)
                for i, env in enumerate(singles):
                    o, r, te, tr, info = env.step(actions[i])
                    where = f"{task} step {k} env {i}"
                    self.assertEqual((te, tr), (terminated[i], truncated[i]), where)
                    self.assertEqual(r, rewards[i], where)
                    if te or tr:
                        ended += 1
                        self.assertTrue(infos["_final_observation"][i])
                        self.assertTrue(np.array_equal(infos["final_observation"][i], o), where)
                        self.assertEqual(infos["episode_return"][i], info["episode_return"], where)
                        self.assertEqual(infos["episode_length"][i], info["episode_length"])
                        o, _ = env.reset()
                    # The worlds: bit for bit (both at the new episode's start after an end).
                    self.assertTrue(np.array_equal(vec.batch.robots[i], env.world.robots), where)
                    self.assertTrue(np.array_equal(vec.batch.balls[i], env.world.ball), where)
                    self.assertTrue(np.array_equal(obs[i], o), where)
            self.assertGreater(ended, 3, task)

    def test_spaces_and_bad_input(self):
        vec = VssimVectorEnv("GoToBall", num_envs=4, threads=1)
        self.assertEqual(vec.action_space.shape, (4, 2))
        self.assertEqual(vec.observation_space.shape, (4, 12))
        with self.assertRaisesRegex(RuntimeError, "reset"):
            vec.step(np.zeros((4, 2)))
        obs, _ = vec.reset(seed=[1, 2, 3, None])
        self.assertTrue(vec.observation_space.contains(obs))
        with self.assertRaisesRegex(ValueError, "expected 4 seeds"):
            vec.reset(seed=[1, 2])
        with self.assertRaisesRegex(ValueError, "expected 8 numbers"):
            vec.step(np.zeros((3, 2)))
        bad = np.zeros((4, 2))
        bad[2, 0] = np.inf
        with self.assertRaisesRegex(ValueError, "environment 2: the right value is inf"):
            vec.step(bad)
        for n in (0, -1, 2.5, True):
            with self.assertRaisesRegex(ValueError, "num_envs"):
                VssimVectorEnv("GoToBall", num_envs=n)
        # Seeds as an int: environment i from seed + i.
        a, _ = vec.reset(seed=7)
        b, _ = VssimVectorEnv("GoToBall", num_envs=4).reset(seed=[7, 8, 9, 10])
        self.assertTrue(np.array_equal(a, b))


class TestGymnasiumRegistration(unittest.TestCase):
    def test_with_a_gymnasium_importable(self):
        # A stand-in gymnasium package (Debian 12 has none): the environments
        # must subclass its Env and VectorEnv and register both tasks.
        with tempfile.TemporaryDirectory() as tmp:
            pkg = os.path.join(tmp, "gymnasium")
            os.makedirs(os.path.join(pkg, "spaces"))
            os.makedirs(os.path.join(pkg, "vector"))
            with open(os.path.join(pkg, "__init__.py"), "w") as f:
                f.write(textwrap.dedent("""
                    registry = {}
                    class Env:
                        _np_random = None
                        def reset(self, *, seed=None, options=None):
                            import numpy as np
                            if seed is not None:
                                self._np_random = np.random.default_rng(seed)
                        @property
                        def np_random(self):
                            import numpy as np
                            if self._np_random is None:
                                self._np_random = np.random.default_rng()
                            return self._np_random
                    def register(id, entry_point, kwargs=None, vector_entry_point=None):
                        registry[id] = (entry_point, kwargs, vector_entry_point)
                    """))
            with open(os.path.join(pkg, "spaces", "__init__.py"), "w") as f:
                f.write("class Box:\n    def __init__(self, low, high, dtype):\n"
                        "        self.low, self.high, self.dtype, self.shape = low, high, dtype, low.shape\n")
            with open(os.path.join(pkg, "vector", "__init__.py"), "w") as f:
                f.write("class VectorEnv:\n    pass\n")
            script = textwrap.dedent("""
                import gymnasium, numpy as np
                from vssim.env import VssimEnv, VssimVectorEnv, HAVE_GYMNASIUM
                assert HAVE_GYMNASIUM
                assert issubclass(VssimEnv, gymnasium.Env)
                assert issubclass(VssimVectorEnv, gymnasium.vector.VectorEnv)
                assert sorted(gymnasium.registry) == ["vssim/GoToBall-v0", "vssim/ScoreGoal-v0"], gymnasium.registry
                entry, kwargs, vector = gymnasium.registry["vssim/ScoreGoal-v0"]
                assert entry == "vssim.env.single:VssimEnv" and kwargs == {"task": "ScoreGoal"}, entry
                assert vector == "vssim.env.vector:VssimVectorEnv"
                env = VssimEnv("GoToBall")
                assert isinstance(env.action_space, gymnasium.spaces.Box)
                a, _ = env.reset(seed=3)
                b, _ = VssimEnv("GoToBall").reset(seed=3)
                assert np.array_equal(a, b)
                print("ok")
                """)
            path = os.pathsep.join([tmp, os.environ.get("PYTHONPATH", "")])
            out = subprocess.run([sys.executable, "-c", script], env=dict(os.environ, PYTHONPATH=path),
                                 capture_output=True, text=True, timeout=60)
            self.assertEqual(out.returncode, 0, out.stderr)
            self.assertEqual(out.stdout.strip(), "ok")


if __name__ == "__main__":
    unittest.main()
