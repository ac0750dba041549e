#!/usr/bin/python3
"""The step response of the robots' on-board speed loop, for docs/model.md.

    speed_loop_step.py VSSIM [--plot PNG]

VSSIM is the vssim binary. The script runs the built-in scene speed_step
(four default robots given wheel-speed steps at t = 0: 10 rad/s on both
wheels, 40 rad/s on both (beyond what 7.4 V holds at first: the loop
saturates), a turning step of 15 / 5 rad/s, and 10 rad/s through a
512-count encoder) for 0.6 s with `vssim run`, sampled every step (1 ms),
and prints a Markdown table of each wheel's response: the 10-90 % rise
time, the overshoot, the 2 % settling time and the steady-state error at
0.6 s. With --plot it also draws the wheel speeds and the voltages
(matplotlib) into PNG.
"""
import argparse
import csv
import io
import subprocess
import sys

TARGETS = {  # robot -> (right, left) targets, rad/s, as in resources/scenes/speed_step.json
    "small_step": (10.0, 10.0),
    "large_step": (40.0, 40.0),
    "turning_step": (15.0, 5.0),
    "encoder_512": (10.0, 10.0),
}
DURATION = 0.6  # s


def run(vssim):
    out = subprocess.run([vssim, "run", "speed_step", "--duration", str(DURATION), "--sample", "0.001"],
                         check=True, capture_output=True, text=True).stdout
    rows = {}
    for r in csv.DictReader(io.StringIO(out)):
        if r["body"] == "ball":
            continue
        rows.setdefault(r["body"], []).append(
            (float(r["t"]), float(r["omega_right"]), float(r["omega_left"]), float(r["e_right"]),
             float(r["e_left"])))
    return rows


def response(t, w, target):
    """Rise time 10-90 % (s), overshoot (%), 2 % settling time (s), final error (rad/s)."""
    t10 = next(ti for ti, wi in zip(t, w) if wi >= 0.1 * target)
    t90 = next(ti for ti, wi in zip(t, w) if wi >= 0.9 * target)
    overshoot = max(0.0, 100.0 * (max(w) - target) / target)
    settle = 0.0
    for ti, wi in zip(t, w):
        if abs(wi - target) > 0.02 * target:
            settle = ti
    return t90 - t10, overshoot, settle, w[-1] - target


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("vssim")
    parser.add_argument("--plot", metavar="PNG")
    args = parser.parse_args()
    rows = run(args.vssim)
    print("| robot, wheel | target | rise 10-90 % | overshoot | settles within 2 % | error at 0.6 s |")
    print("|---|---|---|---|---|---|")
    for robot, (right, left) in TARGETS.items():
        samples = rows[robot]
        t = [s[0] for s in samples]
        for wheel, column, target in (("right", 1, right), ("left", 2, left)):
            if wheel == "left" and left == right:
                continue  # the same response
            rise, overshoot, settle, error = response(t, [s[column] for s in samples], target)
            print(f"| {robot}, {wheel} | {target:g} rad/s | {1e3 * rise:.0f} ms | {overshoot:.1f} % "
                  f"| {1e3 * settle:.0f} ms | {error:+.2g} rad/s |")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (speed, volts) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
        for robot, (right, left) in TARGETS.items():
            samples = rows[robot]
            t = [1e3 * s[0] for s in samples]
            line, = speed.plot(t, [s[1] for s in samples], label=f"{robot} (right, target {right:g})")
            volts.plot(t, [s[3] for s in samples], color=line.get_color(), label=robot)
            if left != right:
                speed.plot(t, [s[2] for s in samples], color=line.get_color(), linestyle="--",
                           label=f"{robot} (left, target {left:g})")
                volts.plot(t, [s[4] for s in samples], color=line.get_color(), linestyle="--")
        speed.set_ylabel("wheel speed (rad/s)")
        speed.grid(True, alpha=0.3)
        speed.legend(fontsize=8)
        volts.set_ylabel("armature voltage (V)")
        volts.set_xlabel("time (ms)")
        volts.grid(True, alpha=0.3)
        fig.suptitle("On-board speed loop, default robot: PI 200 Hz, kp 0.6 V s/rad, ki 10 V/rad, 7.4 V")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=100)
        print(f"plot written to {args.plot}", file=sys.stderr)


if __name__ == "__main__":
    main()
