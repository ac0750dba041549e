"""Scene variations: grids of values at dotted key paths, applied to a
scene dict (docs/distributed.md, "sweep")."""

import itertools
import json


def grid(axes):
    """Every combination of values, as a list of variations: grid({"ball.vx":
    [0.5, 1.0], "robots.0.x": [-0.3, -0.2]}) gives four dicts of dotted key
    paths, the first key varying slowest."""
    if not isinstance(axes, dict) or not axes:
        raise TypeError("variations: expected a non-empty dict of dotted key paths to lists of values")
    keys = list(axes)
    values = []
    for k in keys:
        if not isinstance(k, str) or not k:
            raise TypeError(f"variations: keys must be dotted key paths such as 'ball.vx', got {k!r}")
        v = axes[k]
        if isinstance(v, (str, bytes, dict)) or not hasattr(v, "__iter__"):
            raise TypeError(f"variations[{k!r}]: expected a list of values, got {type(v).__name__}")
        v = list(v)
        if not v:
            raise ValueError(f"variations[{k!r}]: expected at least one value")
        values.append(v)
    return [dict(zip(keys, combo)) for combo in itertools.product(*values)]


def _set(node, parts, value, path):
    """Sets node[parts...] = value: a dict value merges into the dict there;
    '*' stands for every element of a list; missing object keys are created."""
    head, rest = parts[0], parts[1:]
    if isinstance(node, list):
        if head == "*":
            indices = range(len(node))
        else:
            try:
                indices = [int(head)]
            except ValueError:
                raise ValueError(f"{path}: '{head}' indexes a list: expected a number or *") from None
            if not 0 <= indices[0] < len(node):
                raise ValueError(f"{path}: index {indices[0]} is outside the list of {len(node)}")
        for i in indices:
            if rest:
                _set(node[i], rest, value, path)
            else:
                node[i] = _merge(node[i], value)
        return
    if not isinstance(node, dict):
        raise ValueError(f"{path}: '{head}' is inside a {type(node).__name__}, not an object")
    if rest:
        _set(node.setdefault(head, {}), rest, value, path)
    else:
        node[head] = _merge(node.get(head), value)


def _merge(old, new):
    if isinstance(old, dict) and isinstance(new, dict):
        out = dict(old)
        for k, v in new.items():
            out[k] = _merge(out.get(k), v)
        return out
    return json.loads(json.dumps(new))  # a copy


def apply_variation(scene, variation):
    """A copy of the scene dict with the variation applied: each dotted key path
    (e.g. "ball.vx", "robots.0.params.mass", "robots.*.params.mass") set to its
    value; a dict value merges into the object there. Raises ValueError."""
    out = json.loads(json.dumps(scene))
    for path, value in variation.items():
        if not isinstance(path, str) or not path or any(not p for p in path.split(".")):
            raise ValueError(f"{path!r}: expected a dotted key path such as 'ball.vx'")
        _set(out, path.split("."), value, path)
    return out


def _flat(variation):
    """The variation's values by dotted key path, nested dicts spread out: the table's columns."""
    out = {}
    for k, v in variation.items():
        if isinstance(v, dict) and v:
            for k2, v2 in _flat(v).items():
                out[f"{k}.{k2}"] = v2
        else:
            out[k] = v
    return out
