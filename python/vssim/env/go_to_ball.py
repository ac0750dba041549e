"""Task "GoToBall": drive robot yellow0 until it touches a ball lying still
somewhere on the field (docs/python.md, "Gym-style environments")."""

import math

import numpy as np

from .task import Task, gap_robot_ball, heading_features, to_robot_frame, uniform_pose

# The official 3 vs 3 field (1.50 x 1.30 m, walls and goals), one robot and the
# ball, no referee, the exact integrator (the fastest, docs/model.md).
_SCENE = {
    "version": 1,
    "field": {"type": "vsss_3v3"},
    "simulation": {"integrator": "exact", "dt": 0.001},
    "ball": {"x": 0.0, "y": 0.0},
    "robots": [{"name": "yellow0", "team": "yellow", "x": -0.3, "y": 0.0, "theta": 0.0}],
    "game": {"referee": False, "yellow": "remote", "blue": "idle"},
}

_REACHED = 0.005  # the gap (m) that counts as touching
_MARGIN = 0.1     # starts keep this far from the walls, m


class GoToBall(Task):
    """Observation (12 numbers, SI): the ball as the robot sees it (x ahead,
    y to the left, m), the robot's v (m/s) and omega (rad/s), its wheel
    speeds (right, left, rad/s), its x, y (m), cos and sin of its heading,
    and the ball's x, y (m).
    Reward: 10 per metre the gap to the ball shrinks (grows: negative), and
    10 on touching it (a gap under 5 mm), which ends the episode.
    Start: the robot anywhere at least 0.1 m from the walls, any heading, at
    rest; the ball at rest, at least 0.2 m from it. Truncated after 10 s."""

    name = "GoToBall"
    scene = _SCENE
    max_episode_seconds = 10.0
    observation_names = ("ball_ahead", "ball_left", "v", "omega", "wheel_right", "wheel_left",
                         "x", "y", "cos_theta", "sin_theta", "ball_x", "ball_y")
    observation_low = np.array([-2, -2, -2, -60, -200, -200, -0.85, -0.75, -1, -1, -0.85, -0.75], np.float32)
    observation_high = -observation_low

    def start(self, rng):
        xr = (-self.half_length + _MARGIN, self.half_length - _MARGIN)
        yr = (-self.half_width + _MARGIN, self.half_width - _MARGIN)
        x, y, theta = uniform_pose(rng, xr, yr)
        while True:
            bx, by = float(rng.uniform(*xr)), float(rng.uniform(*yr))
            if math.hypot(bx - x, by - y) >= 0.2:
                return [(0, x, y, theta)], (bx, by, 0.0, 0.0)

    def observe(self, robots, wheel_speeds, balls):
        r = robots[:, 0, :]
        return np.concatenate([to_robot_frame(robots, 0, balls), r[:, 3:5], wheel_speeds[:, 0, :], r[:, 0:2],
                               heading_features(robots, 0), balls[:, 0:2]], axis=1).astype(np.float32)

    def potential(self, robots, balls):
        return -10.0 * gap_robot_ball(robots, 0, balls, self.side, self.radius)

    def outcome(self, robots, balls):
        reached = gap_robot_ball(robots, 0, balls, self.side, self.radius) < _REACHED
        return reached, np.where(reached, 10.0, 0.0)
