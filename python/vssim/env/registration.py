"""Registration with Gymnasium, when it is importable: gymnasium.make(
"vssim/GoToBall-v0", action_type="wheel_speeds") makes a VssimEnv (and
gymnasium.make_vec one VssimVectorEnv where Gymnasium supports vector entry
points)."""

import inspect

from .base import HAVE_GYMNASIUM


def register_environments():
    """Registers "vssim/<task>-v0" for every task; returns the ids (none
    without Gymnasium). Registering twice is harmless."""
    if not HAVE_GYMNASIUM:
        return []
    import gymnasium

    from .tasks import TASKS

    ids = []
    vector_entry = "vector_entry_point" in inspect.signature(gymnasium.register).parameters
    for name in TASKS:
        env_id = f"vssim/{name}-v0"
        ids.append(env_id)
        if env_id in gymnasium.registry:
            continue
        kwargs = {"id": env_id, "entry_point": "vssim.env.single:VssimEnv", "kwargs": {"task": name}}
        if vector_entry:
            kwargs["vector_entry_point"] = "vssim.env.vector:VssimVectorEnv"
        gymnasium.register(**kwargs)
    return ids
