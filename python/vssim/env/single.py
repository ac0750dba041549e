"""One world as a Gymnasium-style environment (docs/python.md, "Gym-style
environments")."""

import numpy as np

from .. import World
from .backends import WorldBatch
from .base import Env
from .episodes import Episodes
from .spaces import box
from .tasks import make_task


class VssimEnv(Env):
    """A task (GoToBall, ScoreGoal) on one vssim.World.

    VssimEnv(task="GoToBall", action_type="voltages", control_period=0.03,
    render_mode=None): `task` is a task name or a Task object; actions are
    (2,) arrays in [-1, 1], [right, left], fractions of the battery's voltage
    or (action_type="wheel_speeds") of the free wheel speed, for the on-board
    speed loop; every step lasts control_period seconds of simulated time.
    step() returns (obs, reward, terminated, truncated, info), the Gymnasium
    API. render_mode "rgb_array": render() gives the overhead camera's
    image, (480, 640, 3) uint8 RGB."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 33}

    def __init__(self, task="GoToBall", action_type="voltages", control_period=0.03, render_mode=None):
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode: expected None or 'rgb_array', got {render_mode!r}")
        self.task = make_task(task)
        self.render_mode = render_mode
        self._world = World(self.task.scene)
        self._episodes = Episodes(self.task, WorldBatch(self._world), action_type, control_period)
        self.action_type = action_type
        self.control_period = self._episodes.control_period
        self.action_scale = self._episodes.action_scale
        self.max_episode_steps = self._episodes.max_steps
        self.action_space = box(-1.0, 1.0, (2,))
        self.observation_space = box(self.task.observation_low, self.task.observation_high)
        self._started = False

    @property
    def world(self):
        """The vssim.World under the environment (read it; don't step it)."""
        return self._world

    def reset(self, *, seed=None, options=None):
        """A new episode, its start drawn from the environment's generator
        (seeded by `seed` when given): (observation, info)."""
        super().reset(seed=seed)
        self._episodes.rngs[0] = self.np_random
        self._episodes.restart(0)
        self._started = True
        return self._episodes.observe()[0], {"time": 0.0}

    def step(self, action):
        if not self._started:
            raise RuntimeError("step() before reset(): call reset() to start an episode")
        actions = self._episodes.check_actions(action)
        obs, reward, terminated, truncated = self._episodes.advance(actions)
        info = {"time": round(float(self._episodes.steps[0] * self.control_period), 9)}
        if terminated[0] or truncated[0]:
            self._started = False
            info["episode_return"] = float(self._episodes.returns[0])
            info["episode_length"] = int(self._episodes.steps[0])
        return obs[0], float(reward[0]), bool(terminated[0]), bool(truncated[0]), info

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        return np.ascontiguousarray(self._world.camera_image()[..., ::-1])

    def close(self):
        self._world.close()
