#!/usr/bin/python3
"""Teaches a robot to drive to the ball, from nothing, in about ten seconds on
one machine: the cross-entropy method (a simple evolutionary search) over a
linear policy, on vssim's GoToBall task, every candidate's episodes run
together in one vssim.env.VssimVectorEnv (a BatchWorld in C++).

    PYTHONPATH=build/python examples/python/train_go_to_ball.py --plot curve.png

The policy: action = tanh(W x + b), x the 12 observations scaled to about
[-1, 1] (metres, m/s and rad/s divided by their typical sizes) and the cosine
and sine of the ball's bearing, 2 x 14 weights and 2 biases, actions as
fractions of the battery's voltage. Each generation draws
`population` policies around the current mean, plays each on `episodes`
starts (the same starts for all, new each generation), keeps the best fifth
and moves the mean and spread to them. After each generation the mean policy
is scored on 64 fixed starts it never trains on: its mean return and how
often it touches the ball within the episode's 10 s. Needs numpy (Debian's
python3-numpy); --plot needs python3-matplotlib. docs/python.md,
"Training example", shows a run."""

import argparse
import csv
import math
import sys
import time

import numpy as np

from vssim.env import VssimVectorEnv

# Typical sizes of the 12 observations (go_to_ball.py): m, m/s, rad/s, m, -, m.
OBS_SCALE = np.array([1.5, 1.3, 1.75, 50, 70, 70, 0.75, 0.65, 1, 1, 0.75, 0.65])
N_FEATURES = 14
N_PARAMS = 2 * N_FEATURES + 2
EVAL_SEEDS = 1_000_000  # the held-out starts: seeds 1,000,000 to 1,000,063


def features(obs):
    """(n, 14): the observations scaled, and the cosine and sine of the
    bearing of the ball from the robot's heading."""
    bearing = np.arctan2(obs[:, 1], obs[:, 0])
    return np.concatenate([obs / OBS_SCALE, np.cos(bearing)[:, None], np.sin(bearing)[:, None]], axis=1)


def actions_of(params, obs):
    """(n, 2) actions of n policies (params (n, N_PARAMS)) on their observations (n, 12)."""
    w = params[:, :2 * N_FEATURES].reshape(-1, 2, N_FEATURES)
    b = params[:, 2 * N_FEATURES:]
    return np.tanh(np.einsum("nij,nj->ni", w, features(obs)) + b)


def hand_written(obs):
    """A hand-written controller to compare with: turn towards the ball,
    drive when it is ahead (or behind: backwards)."""
    angle = np.arctan2(obs[:, 1], obs[:, 0])
    angle = np.where(np.abs(angle) > math.pi / 2, angle - np.sign(angle) * math.pi, angle)  # nearer end first
    forward = 0.8 * np.sign(obs[:, 0]) * np.cos(angle) ** 2
    turn = np.clip(1.5 * angle, -1, 1) * 0.4
    return np.stack([forward + turn, forward - turn], axis=1)


def play(env, params, seed, policy=None):
    """Each env's first episode under its own policy (params (num_envs, N_PARAMS),
    or `policy(obs)`), starts from seed: (returns, touched, simulated
    seconds)."""
    obs, _ = env.reset(seed=seed)
    returns = np.zeros(env.num_envs)
    touched = np.zeros(env.num_envs, dtype=bool)
    running = np.ones(env.num_envs, dtype=bool)
    simulated = 0.0
    for _ in range(env.max_episode_steps):
        simulated += running.sum() * env.control_period
        obs, rewards, terminated, truncated, _ = env.step(policy(obs) if policy else actions_of(params, obs))
        returns += np.where(running, rewards, 0.0)
        touched |= running & terminated
        running &= ~(terminated | truncated)
        if not running.any():
            break
    return returns, touched, simulated


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--generations", type=int, default=30, help="generations (default 30)")
    parser.add_argument("--population", type=int, default=48, help="policies per generation (default 48)")
    parser.add_argument("--episodes", type=int, default=4, help="episodes per policy per generation (default 4)")
    parser.add_argument("--seed", type=int, default=1, help="the run's seed (default 1)")
    parser.add_argument("--threads", type=int, default=0, help="BatchWorld threads (default 0: every core)")
    parser.add_argument("--csv", help="write the learning curve here (CSV)")
    parser.add_argument("--plot", help="plot the learning curve here (PNG; needs matplotlib)")
    args = parser.parse_args()
    for name in ("generations", "population", "episodes"):
        if getattr(args, name) < 1:
            parser.error(f"--{name} must be at least 1")
    if args.population < 5:
        parser.error("--population must be at least 5 (the best fifth is kept)")

    rng = np.random.default_rng(args.seed)
    train = VssimVectorEnv("GoToBall", num_envs=args.population * args.episodes, threads=args.threads)
    evaluate = VssimVectorEnv("GoToBall", num_envs=64, threads=args.threads)
    mean, spread = np.zeros(N_PARAMS), np.full(N_PARAMS, 1.0)
    elite = max(2, args.population // 5)
    rows = []
    start = time.perf_counter()

    simulated = 0.0
    returns, touched, _ = play(evaluate, None, EVAL_SEEDS, hand_written)
    reference = {"eval_return": float(returns.mean()), "eval_success": float(touched.mean())}
    print(f"hand-written controller: held-out return {returns.mean():7.3f}, touches the ball in "
          f"{100 * touched.mean():5.1f} % of episodes")

    def score(generation, params):
        nonlocal simulated
        returns, touched, seconds = play(evaluate, np.repeat(params[None], 64, axis=0), EVAL_SEEDS)
        simulated += seconds
        rows.append({"generation": generation, "eval_return": float(returns.mean()),
                     "eval_success": float(touched.mean()), "seconds": time.perf_counter() - start,
                     "simulated_seconds": simulated})
        print(f"generation {generation:3d}: held-out return {returns.mean():7.3f}, touches the ball in "
              f"{100 * touched.mean():5.1f} % of episodes ({time.perf_counter() - start:5.1f} s)", flush=True)

    score(0, mean)
    for generation in range(1, args.generations + 1):
        candidates = mean + spread * rng.standard_normal((args.population, N_PARAMS))
        # Every candidate on the same `episodes` starts: env c * episodes + k plays candidate c on start k.
        params = np.repeat(candidates, args.episodes, axis=0)
        seeds = [int(s) for s in np.tile(rng.integers(0, 2**31, args.episodes), args.population)]
        returns, _, seconds = play(train, params, seeds)
        simulated += seconds
        fitness = returns.reshape(args.population, args.episodes).mean(axis=1)
        best = candidates[np.argsort(fitness)[-elite:]]
        mean = best.mean(axis=0)
        spread = best.std(axis=0) + 0.02  # a floor keeps the search alive
        score(generation, mean)

    wall = time.perf_counter() - start
    print(f"done in {wall:.1f} s: {simulated / 3600:.1f} h of simulated play, {simulated / wall:,.0f}x real time")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    if args.plot:
        plot(rows, reference, args.plot)


def plot(rows, reference, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    g = [r["generation"] for r in rows]
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(g, [100 * r["eval_success"] for r in rows], "o-", color="tab:orange", label="touches the ball (%)")
    ax.set_xlabel("generation")
    ax.set_ylabel("held-out episodes reaching the ball, %")
    ax.set_ylim(-2, 102)
    ax.axhline(100 * reference["eval_success"], color="tab:gray", linestyle=":",
               label="hand-written controller (%)")
    ax2 = ax.twinx()
    ax2.plot(g, [r["eval_return"] for r in rows], "s--", color="tab:blue", label="mean return")
    ax2.set_ylabel("mean return")
    lines = ax.get_lines() + ax2.get_lines()
    ax.legend(lines, [l.get_label() for l in lines], loc="lower right")
    ax.set_title(f"GoToBall: cross-entropy method, linear policy ({rows[-1]['seconds']:.0f} s wall time)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    sys.exit(main())
