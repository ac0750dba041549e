"""Gym-style environments on vssim's in-process worlds (docs/python.md,
"Gym-style environments").

    VssimEnv(task, action_type, control_period)          one vssim.World
    VssimVectorEnv(task, num_envs, action_type, ...)    a vssim.BatchWorld

Tasks: "GoToBall" (drive robot yellow0 to the ball) and "ScoreGoal" (score
against vssim's built-in goalkeeper). Actions as voltages or as wheel speeds
through the on-board speed loop. With Gymnasium importable the environments
are gymnasium.Env / gymnasium.vector.VectorEnv subclasses and are
registered as "vssim/GoToBall-v0" and "vssim/ScoreGoal-v0"; without it
(Debian 12 has no Gymnasium) they keep the same API."""

from .base import HAVE_GYMNASIUM
from .go_to_ball import GoToBall
from .registration import register_environments
from .score_goal import ScoreGoal
from .single import VssimEnv
from .task import Task
from .tasks import TASKS, make_task
from .vector import VssimVectorEnv

register_environments()

__all__ = ["HAVE_GYMNASIUM", "GoToBall", "ScoreGoal", "Task", "TASKS", "VssimEnv", "VssimVectorEnv", "make_task",
           "register_environments"]
