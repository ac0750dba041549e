#!/usr/bin/env python3
"""What the desktop app costs paused and running at x1, driven as a person
drives it (docs/performance.md, "Paused by hand").

Starts `vssim gui` with no scene (the default match: the referee and the
built-in team on both sides) on an X server of 1400 x 1000 (Xvfb, started
here with xvfb-run when DISPLAY is not set), resizes its window to
1400 x 1000 and moves it to the screen's corner with xdotool, clicks the
field at (400, 400) and presses Space, all as real X events. It checks
through the app's TCP server (a WELCOME's "paused") that the app is paused,
then reads the process's CPU time from /proc/PID/stat over --seconds (and
each thread's from /proc/PID/task); then Space again, checks that it runs,
and measures again. Prints one line per phase and, with --out, appends them
to a CSV file.

    python3 bench/gui_idle.py [--vssim build/app/vssim] [--seconds 10]
        [--out FILE.csv] [--label NAME] [--screenshots PREFIX]

--screenshots PREFIX saves the screen (ImageMagick's import) in each phase
as PREFIX-paused.png and PREFIX-running.png.
"""

import argparse
import csv
import json
import os
import socket
import struct
import subprocess
import sys
import time

SCREEN = "1400x1000x24"


def run(*args):
    return subprocess.run(args, check=True, capture_output=True, text=True, timeout=30).stdout


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def welcome(port):
    """The app's WELCOME to an observer (docs/protocol.md), as a dict."""
    with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
        s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        hello = json.dumps({"protocol": 1, "role": "observer", "name": "gui_idle"}).encode()
        s.sendall(struct.pack(">IB", len(hello) + 1, 0x01) + hello)

        def read(n):
            data = b""
            while len(data) < n:
                chunk = s.recv(n - len(data))
                if not chunk:
                    raise RuntimeError("the app closed the connection")
                data += chunk
            return data

        length, kind = struct.unpack(">IB", read(5))
        payload = read(length - 1)
        if kind != 0x81:
            raise RuntimeError(f"expected WELCOME (0x81), got 0x{kind:02x}: {payload[:200]!r}")
        return json.loads(payload)


def ticks(path):
    """utime + stime of a /proc stat file, in clock ticks (the fields after the command's ')')."""
    with open(path) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return int(fields[11]) + int(fields[12])


def thread_ticks(pid):
    out = {}
    for tid in os.listdir(f"/proc/{pid}/task"):
        try:
            with open(f"/proc/{pid}/task/{tid}/comm") as f:
                name = f.read().strip()
            out[int(tid)] = (name, ticks(f"/proc/{pid}/task/{tid}/stat"))
        except OSError:  # a thread that ended meanwhile
            pass
    return out


def measure(pid, seconds):
    """Percent of one core: the process, its main thread, and its busiest other threads."""
    hz = os.sysconf("SC_CLK_TCK")
    p0, t0, w0 = ticks(f"/proc/{pid}/stat"), thread_ticks(pid), time.monotonic()
    time.sleep(seconds)
    p1, t1, w1 = ticks(f"/proc/{pid}/stat"), thread_ticks(pid), time.monotonic()
    wall = w1 - w0

    def percent(dt):
        return 100.0 * dt / hz / wall

    threads = []
    for tid, (name, after) in t1.items():
        before = t0.get(tid, (name, 0))[1]
        threads.append((percent(after - before), tid, name))
    threads.sort(reverse=True)
    main = next((pc for pc, tid, _ in threads if tid == pid), 0.0)
    others = [(name, pc) for pc, tid, name in threads if tid != pid and pc >= 0.05][:4]
    return percent(p1 - p0), main, others


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--vssim", default="build/app/vssim")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--settle", type=float, default=3.0, help="s to wait after each change before measuring")
    ap.add_argument("--out", help="CSV file to append the phases to")
    ap.add_argument("--label", default="", help="a name for this build in the CSV")
    ap.add_argument("--screenshots", help="save screenshots as PREFIX-paused.png, PREFIX-running.png")
    args = ap.parse_args()

    if not os.environ.get("DISPLAY"):
        os.execvp("xvfb-run", ["xvfb-run", "-a", "-s", f"-screen 0 {SCREEN}", sys.executable] + sys.argv)

    port = free_port()
    env = dict(os.environ, QT_QPA_PLATFORM="xcb")
    # `vssim gui` with no scene is what `vssim` alone opens; --port keeps it
    # off the default port, which another vssim may hold.
    app = subprocess.Popen([args.vssim, "gui", "--port", str(port)], env=env,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    rows = []
    try:
        run("xdotool", "search", "--sync", "--onlyvisible", "--name", "vssim",
            "windowsize", "%@", "1400", "1000", "windowmove", "%@", "0", "0")
        time.sleep(args.settle)
        run("xdotool", "mousemove", "400", "400", "click", "1")
        run("xdotool", "key", "space")
        for phase, paused in (("paused", True), ("running x1", False)):
            time.sleep(args.settle)
            state = welcome(port)
            if state.get("paused") != paused:
                sys.exit(f"gui_idle: expected paused={paused} in the {phase} phase, the app says {state.get('paused')}")
            time.sleep(1.0)  # the observer's departure shown in the connections dock
            if args.screenshots:
                run("import", "-window", "root", f"{args.screenshots}-{phase.split()[0]}.png")
            process, main_thread, others = measure(app.pid, args.seconds)
            print(f"{phase:>11}: process {process:5.1f} % of a core, main thread {main_thread:5.1f} %; "
                  + ", ".join(f"{name} {pc:.1f} %" for name, pc in others))
            rows.append([args.label, phase, f"{args.seconds:g}", f"{process:.1f}", f"{main_thread:.1f}",
                         "; ".join(f"{name} {pc:.1f}" for name, pc in others)])
            if paused:
                run("xdotool", "key", "space")
    finally:
        app.terminate()
        try:
            app.wait(10)
        except subprocess.TimeoutExpired:
            app.kill()
    if args.out:
        new = not os.path.exists(args.out)
        with open(args.out, "a", newline="") as f:
            w = csv.writer(f)
            if new:
                w.writerow(["build", "phase", "seconds", "process_percent", "main_thread_percent", "other_threads_percent"])
            w.writerows(rows)


if __name__ == "__main__":
    main()
