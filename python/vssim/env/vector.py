"""n worlds of a task as one vectorized Gymnasium-style environment, stepped
together in C++ by a vssim.BatchWorld (docs/python.md, "Gym-style
environments")."""

import numbers

import numpy as np

from .. import BatchWorld
from .backends import BatchOfWorlds
from .base import VectorEnv
from .episodes import Episodes
from .spaces import batched, box
from .tasks import make_task


class VssimVectorEnv(VectorEnv):
    """num_envs copies of a task on one vssim.BatchWorld (threads=0: every
    core).

    Actions are (num_envs, 2) arrays; step() returns (obs, rewards,
    terminated, truncated, infos) with a leading num_envs axis. An
    environment whose episode ends is reset in the same step: its row of
    obs is the new episode's first observation, and infos holds
    "final_observation" (num_envs, d) with the last observation of the
    episode that ended, "episode_return" and "episode_length", each valid
    where the mask "_final_observation" is true. Environment i behaves, bit
    for bit, as a VssimEnv reset with seed + i."""

    def __init__(self, task="GoToBall", num_envs=16, action_type="voltages", control_period=0.03, threads=0):
        if not isinstance(num_envs, numbers.Integral) or isinstance(num_envs, bool) or num_envs < 1:
            raise ValueError(f"num_envs: expected a whole number >= 1, got {num_envs!r}")
        self.task = make_task(task)
        self.batch = BatchWorld(int(num_envs), self.task.scene, threads=threads)
        self._episodes = Episodes(self.task, BatchOfWorlds(self.batch), action_type, control_period)
        self.num_envs = int(num_envs)
        self.action_type = action_type
        self.control_period = self._episodes.control_period
        self.action_scale = self._episodes.action_scale
        self.max_episode_steps = self._episodes.max_steps
        self.single_action_space = box(-1.0, 1.0, (2,))
        self.single_observation_space = box(self.task.observation_low, self.task.observation_high)
        self.action_space = batched(self.single_action_space, self.num_envs)
        self.observation_space = batched(self.single_observation_space, self.num_envs)
        self._started = False

    def reset(self, *, seed=None, options=None):
        """Every environment afresh: seed None (from the OS's entropy), an int
        (environment i from seed + i) or a sequence of num_envs ints or
        Nones. Returns (obs, infos)."""
        if seed is None or isinstance(seed, numbers.Integral):
            seeds = [None if seed is None else int(seed) + i for i in range(self.num_envs)]
        else:
            seeds = list(seed)
            if len(seeds) != self.num_envs:
                raise ValueError(f"seed: expected {self.num_envs} seeds, got {len(seeds)}")
        for i, s in enumerate(seeds):
            self._episodes.seed(i, s)
            self._episodes.restart(i)
        self._started = True
        return self._episodes.observe(), {}

    def step(self, actions):
        if not self._started:
            raise RuntimeError("step() before reset(): call reset() first")
        a = self._episodes.check_actions(actions)
        obs, rewards, terminated, truncated = self._episodes.advance(a)
        done = terminated | truncated
        infos = {}
        if done.any():
            infos = {"final_observation": obs.copy(), "_final_observation": done.copy(),
                     "episode_return": np.where(done, self._episodes.returns, 0.0),
                     "episode_length": np.where(done, self._episodes.steps, 0)}
            for i in np.flatnonzero(done):
                self._episodes.restart(i)
            obs = self._episodes.observe()
        return obs, rewards, terminated, truncated, infos

    def close(self):
        self.batch = None
