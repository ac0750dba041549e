"""The tasks by name."""

from .go_to_ball import GoToBall
from .score_goal import ScoreGoal
from .task import Task

TASKS = {"GoToBall": GoToBall, "ScoreGoal": ScoreGoal}


def make_task(task):
    """A Task from its name ("GoToBall", "ScoreGoal") or a Task object."""
    if isinstance(task, Task):
        return task
    if isinstance(task, str) and task in TASKS:
        return TASKS[task]()
    raise ValueError(f"task: expected one of {sorted(TASKS)} or a vssim.env.Task, got {task!r}")
