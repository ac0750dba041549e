"""The episodes of n worlds under one task: actions in, observations and
rewards out, starts drawn from each world's own random generator. The single
and the vector environments are this with n = 1 and n = num_envs."""

import math
import numbers

import numpy as np

ACTION_TYPES = ("voltages", "wheel_speeds")


def free_wheel_speed(params):
    """A free wheel's steady speed at the battery's voltage, rad/s: the
    motor equations of model.md §2 (i = (e - K w)/R, tau = K i - J dw/dt -
    beta w) with no load (tau = 0) in steady state give w = K e / (K^2 +
    R beta); the right motor's. 71.6 rad/s for the default robot."""
    m = params["right"]
    return m["k"] * params["max_voltage"] / (m["k"] ** 2 + m["resistance"] * m["friction"])


class Episodes:
    """n worlds of a backend (backends.py) playing episodes of `task`.

    Actions are (n, 2) arrays in [-1, 1], [right, left] per world, for the
    task's robot: fractions of the battery's voltage (action_type
    "voltages") or of the free wheel speed, as targets of the on-board speed
    loop ("wheel_speeds"). Values outside [-1, 1] are clipped; NaN or
    infinite ones raise ValueError."""

    def __init__(self, task, backend, action_type="voltages", control_period=0.03):
        if action_type not in ACTION_TYPES:
            raise ValueError(f"action_type: expected one of {ACTION_TYPES}, got {action_type!r}")
        if (isinstance(control_period, bool) or not isinstance(control_period, numbers.Real)
                or not (math.isfinite(control_period) and control_period > 0)):
            raise ValueError(f"control_period: expected a positive finite number of seconds, got {control_period!r}")
        self.task = task
        self.backend = backend
        self.n = backend.n_worlds
        scene = backend.scene()
        task.configure(scene)
        params = scene["robots"][task.robot]["params"]
        self.wheel_speeds = action_type == "wheel_speeds"
        # What an action of 1 means: V, or rad/s.
        self.action_scale = free_wheel_speed(params) if self.wheel_speeds else params["max_voltage"]
        self.control_period = float(control_period)
        self.max_steps = max(1, math.ceil(task.max_episode_seconds / self.control_period - 1e-9))
        self.rngs = [np.random.default_rng() for _ in range(self.n)]
        self.steps = np.zeros(self.n, dtype=np.int64)
        self.returns = np.zeros(self.n)
        self.commands = np.zeros((self.n, backend.n_robots, 2))
        self.potential = np.zeros(self.n)

    def seed(self, i, seed):
        """World i's start generator from `seed` (None: from the OS's entropy)."""
        self.rngs[i] = np.random.default_rng(seed)

    def restart(self, i):
        """World i afresh at a start drawn from its generator (call observe() after)."""
        self.backend.reset(i)
        poses, ball = self.task.start(self.rngs[i])
        for robot, x, y, theta in poses:
            self.backend.place_robot(i, robot, x, y, theta)
        self.backend.place_ball(i, *ball)
        self.steps[i] = 0
        self.returns[i] = 0.0
        self.commands[i] = 0.0

    def observe(self):
        """(n, d) observations of the worlds as they are now; also takes the
        shaping potential from here."""
        robots, wheels, balls = self.backend.state()
        self.potential = self.task.potential(robots, balls)
        return self.task.observe(robots, wheels, balls)

    def check_actions(self, actions):
        """actions as an (n, 2) float64 array clipped to [-1, 1], or a ValueError."""
        try:
            a = np.asarray(actions, dtype=np.float64)
        except (TypeError, ValueError) as error:
            raise ValueError(f"action: expected numbers, shape ({self.n}, 2) [right, left]: {error}") from None
        if a.size != 2 * self.n:
            raise ValueError(f"action: expected {2 * self.n} numbers [right, left]"
                             f"{' per environment' if self.n > 1 else ''}, got shape {a.shape}")
        a = a.reshape(self.n, 2)
        bad = ~np.isfinite(a)
        if bad.any():
            world, side = np.argwhere(bad)[0]
            where = f"environment {world}: " if self.n > 1 else ""
            raise ValueError(f"action: {where}the {('right', 'left')[side]} value is {a[world, side]}")
        return np.clip(a, -1.0, 1.0)

    def advance(self, actions):
        """One control period with these (checked) actions: (observations,
        rewards, terminated, truncated) of every world."""
        self.commands[:, self.task.robot, :] = actions * self.action_scale
        self.backend.drive(self.commands, self.wheel_speeds)
        self.backend.step(self.control_period)
        before = self.potential
        robots, wheels, balls = self.backend.state()
        self.potential = self.task.potential(robots, balls)
        terminated, bonus = self.task.outcome(robots, balls)
        rewards = self.potential - before + bonus
        self.steps += 1
        self.returns += rewards
        truncated = (self.steps >= self.max_steps) & ~terminated
        return self.task.observe(robots, wheels, balls), rewards, terminated, truncated
