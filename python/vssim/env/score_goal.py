"""Task "ScoreGoal": robot yellow0 must put the ball in the blue goal (at
x > 0), guarded by vssim's built-in goalkeeper (blue0; docs/game.md, "The
built-in team") (docs/python.md, "Gym-style environments")."""

import math

import numpy as np

from .task import Task, gap_robot_ball, heading_features, to_robot_frame, uniform_pose

_SCENE = {
    "version": 1,
    "field": {"type": "vsss_3v3"},
    "simulation": {"integrator": "exact", "dt": 0.001},
    "ball": {"x": 0.2, "y": 0.0},
    "robots": [
        {"name": "yellow0", "team": "yellow", "x": -0.3, "y": 0.0, "theta": 0.0},
        {"name": "blue0", "team": "blue", "x": 0.68, "y": 0.0, "theta": math.pi},
    ],
    # No referee: no kick-off stop, no fouls; the goal is this task's to see.
    # The built-in team still plays: its only robot keeps the goal.
    "game": {"referee": False, "yellow": "remote", "blue": "builtin"},
}

_KEEPER = 1


class ScoreGoal(Task):
    """Observation (18 numbers, SI): the robot's x, y (m), cos and sin of its
    heading, v (m/s), omega (rad/s), wheel speeds (right, left, rad/s); the
    ball's x, y (m), vx, vy (m/s); the ball as the robot sees it (x ahead, y
    to the left, m); the goalkeeper's x, y (m), cos and sin of its heading.
    Reward: 10 per metre the ball comes closer to the centre of the blue
    goal's line (or, past the line, to the goal's middle), 2 per metre the robot comes closer to the ball; +10 for a
    goal, -10 for an own goal (a goal: the whole ball past the goal line
    between the posts, the referee's rule), either of which ends the episode.
    Start: the ball at rest in x 0 to 0.45 m, y -0.4 to 0.4 m; the robot at
    rest behind it (x from -0.6 m to 0.1 m short of the ball, y -0.5 to
    0.5 m, any heading); the goalkeeper on its line. Truncated after 15 s."""

    name = "ScoreGoal"
    scene = _SCENE
    max_episode_seconds = 15.0
    observation_names = ("x", "y", "cos_theta", "sin_theta", "v", "omega", "wheel_right", "wheel_left",
                         "ball_x", "ball_y", "ball_vx", "ball_vy", "ball_ahead", "ball_left",
                         "keeper_x", "keeper_y", "keeper_cos_theta", "keeper_sin_theta")
    observation_low = np.array([-0.85, -0.75, -1, -1, -2, -60, -200, -200, -0.85, -0.75, -20, -20, -2, -2,
                                -0.85, -0.75, -1, -1], np.float32)
    observation_high = -observation_low

    def start(self, rng):
        bx, by = float(rng.uniform(0.0, 0.45)), float(rng.uniform(-0.4, 0.4))
        x, y, theta = uniform_pose(rng, (-0.6, bx - 0.1), (-0.5, 0.5))
        keeper = (_KEEPER, self.half_length - 0.07, 0.0, math.pi)
        return [(0, x, y, theta), keeper], (bx, by, 0.0, 0.0)

    def observe(self, robots, wheel_speeds, balls):
        r = robots[:, 0, :]
        return np.concatenate([r[:, 0:2], heading_features(robots, 0), r[:, 3:5], wheel_speeds[:, 0, :], balls,
                               to_robot_frame(robots, 0, balls), robots[:, _KEEPER, 0:2],
                               heading_features(robots, _KEEPER)], axis=1).astype(np.float32)

    def potential(self, robots, balls):
        across = np.maximum(self.half_length - balls[:, 0], 0.0)
        to_goal = np.hypot(across, np.ascontiguousarray(balls[:, 1]))  # contiguous: see task.heading_features
        to_ball = gap_robot_ball(robots, 0, balls, self.side, self.radius)
        return -10.0 * to_goal - 2.0 * to_ball

    def goals(self, balls):
        """(n,) +1 where the ball is in the blue goal, -1 in the yellow goal,
        0 elsewhere (game/src/pitch.cpp's goalScoredIn)."""
        between_posts = np.abs(balls[:, 1]) < 0.5 * self.goal_width
        side = np.where(balls[:, 0] > self.half_length + self.radius, 1,
                        np.where(balls[:, 0] < -self.half_length - self.radius, -1, 0))
        return np.where(between_posts, side, 0)

    def outcome(self, robots, balls):
        goal = self.goals(balls)
        return goal != 0, 10.0 * goal.astype(np.float64)
