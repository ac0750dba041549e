#!/usr/bin/python3
"""Plots the CSV files of vssim_bench for docs/performance.md.

Usage: bench/plot.py RESULTS_DIR OUTPUT_DIR
Reads work_precision.csv and scale.csv from RESULTS_DIR and writes
work_precision.png and scale.png into OUTPUT_DIR, created if needed
(Debian's python3-matplotlib).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


# What a scene gets without "integrator" or "dt" (engine/include/vssim/scene.h):
# the exact integrator with long steps at 1 ms.
DEFAULT = ("exact", 0.001)


def work_precision(rows, out):
    fig, ax = plt.subplots(figsize=(7, 5))
    styles = {"euler": "o-", "rk4": "s-", "exact-fixed": "^-", "exact": "D-"}
    labels = {"euler": "Euler", "rk4": "RK4", "exact-fixed": "exact, fixed steps", "exact": "exact, long steps"}
    labels[DEFAULT[0]] += " (default)"
    floor = 1e-15  # m: errors at rounding level are drawn here
    for name, style in styles.items():
        mine = [r for r in rows if r["integrator"] == name]
        if not mine:
            continue
        seconds = [float(r["run_time_s"]) / 10.0 for r in mine]  # per simulated second
        errors = [max(floor, float(r["max_position_error_m"])) for r in mine]
        ax.loglog(seconds, errors, style, label=labels[name])
        for r, x, y in zip(mine, seconds, errors):
            if name == DEFAULT[0] and float(r["dt_s"]) == DEFAULT[1]:
                ax.plot(x, y, "o", ms=14, mfc="none", mec="red", mew=1.5)
                ax.annotate("default (1 ms)", (x, y), fontsize=8, color="red", xytext=(9, 7), textcoords="offset points")
        if name == "exact":  # every step gives the same run: one label
            ax.annotate("any step", (seconds[0], errors[0]), fontsize=6, xytext=(3, -9), textcoords="offset points")
            continue
        for r, x, y in zip(mine, seconds, errors):
            ax.annotate(f"{float(r['dt_s']) * 1e3:g}", (x, y), fontsize=6, xytext=(3, 3), textcoords="offset points")
    ax.axhline(1e-6, color="grey", lw=0.8, ls="--")
    ax.text(ax.get_xlim()[0], 1.3e-6, " 1 um", fontsize=8, color="grey")
    ax.set_xlabel("run time per simulated second [s] (6 robots)")
    ax.set_ylabel("largest position error over 10 s [m]")
    ax.set_title("Work against precision (labels: step in ms)")
    ax.grid(True, which="both", lw=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def scale(rows, out):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    series = (("rk4", "on", "o-", "RK4 1 ms, broad phase on"),
              ("rk4", "off", "s--", "RK4 1 ms, broad phase off (all pairs)"),
              ("exact, long steps (default)", "on", "^-", "exact, long steps, contacts at their instant (default)"))
    for setting, flag, style, label in series:
        # (CSV files from before the setting column hold RK4 rows only.)
        mine = [r for r in rows if r["broad_phase"] == flag and r.get("setting", "rk4") == setting]
        if mine:
            ax.loglog([int(r["robots"]) for r in mine], [float(r["us_per_robot_per_simulated_s"]) for r in mine],
                      style, label=label)
    ax.set_xlabel("robots")
    ax.set_ylabel("run time per robot per simulated second [us]")
    ax.set_title("Scale (random voltages every 30 ms, the 3-vs-3 density; mean of the crowds)")
    ax.grid(True, which="both", lw=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def main():
    if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    results, output = sys.argv[1], sys.argv[2]
    os.makedirs(output, exist_ok=True)
    try:
        work_precision(read(os.path.join(results, "work_precision.csv")), os.path.join(output, "work_precision.png"))
        scale(read(os.path.join(results, "scale.csv")), os.path.join(output, "scale.png"))
    except OSError as error:
        sys.exit(f"plot.py: {error.filename}: {error.strerror} (run build/bench/vssim_bench --out {results} first)")
    except (KeyError, ValueError) as error:
        sys.exit(f"plot.py: a CSV file in {results} is not what vssim_bench writes ({error})")


if __name__ == "__main__":
    main()
