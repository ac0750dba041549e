"""What a task is: its scene, how an episode starts, what the agent sees, and
its reward. Everything works on batches: state arrays of n worlds, as
vssim.BatchWorld gives them ((n, robots, 5) robots, (n, robots, 2) wheel
speeds, (n, 4) balls), so one task serves the single and the vector
environments alike.

The reward is potential-based shaping (Ng, Harada and Russell, 1999):
reward = potential(after) - potential(before) + bonus(after), which leaves the
best policy unchanged while giving a signal at every step."""

import math

import numpy as np


class Task:
    """Base of the tasks: subclasses set `name`, `scene`, `observation_names`,
    `observation_low`/`observation_high`, `max_episode_seconds`, and define
    start(), observe(), potential() and outcome()."""

    name = ""
    # The robot the agent drives (the scene's first, yellow0).
    robot = 0
    # The scene, as a dict in the scene-file format (docs/scenes.md).
    scene = None
    observation_names = ()
    observation_low = None
    observation_high = None
    max_episode_seconds = 10.0

    def configure(self, scene):
        """Reads the sizes the task needs from the complete scene (a dict, as
        World.scene_json() spells it out): the field's half length and width,
        its goals' width (m), the agent's robot's side and the ball's radius (m)."""
        field = scene["field"]
        self.half_length = 0.5 * field["length"]
        self.half_width = 0.5 * field["width"]
        self.goal_width = field.get("goal_width", 0.0)
        self.side = scene["robots"][self.robot]["params"]["side"]
        self.radius = scene["ball"]["radius"]

    def start(self, rng):
        """An episode's start drawn from rng (a numpy Generator): a list of
        (robot, x, y, theta) poses (m, m, rad; at rest) and the ball
        (x, y, vx, vy) (m, m/s)."""
        raise NotImplementedError

    def observe(self, robots, wheel_speeds, balls):
        """(n, observation size) float32 observations of n worlds."""
        raise NotImplementedError

    def potential(self, robots, balls):
        """(n,) shaping potential of n worlds (its differences are the reward)."""
        raise NotImplementedError

    def outcome(self, robots, balls):
        """(terminated, bonus): (n,) bool, whether each episode has ended, and
        (n,) float, the reward for how it ended (0 while it goes on)."""
        raise NotImplementedError


def to_robot_frame(robots, robot, points):
    """(n, 2) points (m, field frame) seen from robot `robot` of each world:
    x ahead of it, y to its left, m."""
    dx = points[:, 0] - robots[:, robot, 0]
    dy = points[:, 1] - robots[:, robot, 1]
    theta = np.ascontiguousarray(robots[:, robot, 2])  # (see heading_features)
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * dx + s * dy, -s * dx + c * dy], axis=1)


def gap_robot_ball(robots, robot, balls, side, radius):
    """(n,) distance between the ball's surface and robot `robot`'s square
    body of side `side` (m): 0 when they touch (or overlap)."""
    local = to_robot_frame(robots, robot, balls[:, :2])
    outside = np.maximum(np.abs(local) - 0.5 * side, 0.0)
    across, along = np.ascontiguousarray(outside[:, 0]), np.ascontiguousarray(outside[:, 1])  # (see below)
    return np.maximum(np.hypot(across, along) - radius, 0.0)


def heading_features(robots, robot):
    """(n, 2): cos and sin of the robot's heading."""
    # Contiguous copies, here and wherever numpy's cos, sin or hypot gets a
    # column of a batch: numpy may take another path for a strided view
    # than for a contiguous array and round the last bit differently (seen:
    # rewards of a vector environment and of a single one differing by 1e-15
    # in a few processes out of a hundred under load), and a batch's column
    # is strided where a single world's is not.
    theta = np.ascontiguousarray(robots[:, robot, 2])
    return np.stack([np.cos(theta), np.sin(theta)], axis=1)


def uniform_pose(rng, x_range, y_range):
    """(x, y, theta): uniform in the ranges (m) and in [-pi, pi) (rad)."""
    return (float(rng.uniform(*x_range)), float(rng.uniform(*y_range)), float(rng.uniform(-math.pi, math.pi)))
