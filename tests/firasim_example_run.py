#!/usr/bin/python3
"""The FIRASim example client end to end (examples/firasim/go_to_ball.py):
`vssim serve --firasim` in real time at --speed 4 with one blue robot and
the ball, the example driving that robot with --ignore-referee, and this
script watching the same vision. The robot must reach the ball and push it
towards the goal it attacks: x > 0, as blue does in FIRASim's layout, which
both the example and --firasim follow by default.

The vision goes by unicast to 127.0.0.1 (multicast may be unavailable in a
container; tests/test_firasim.cpp tests multicast on loopback where the
kernel allows it). A unicast port has one reader, so this script receives
the vision and relays every datagram, unchanged, to the example's port.

    /usr/bin/python3 tests/firasim_example_run.py --vssim build/app/vssim \
        --proto-dir build/python_proto [unittest options]

(or the environment variables VSSIM_BINARY and VSSIM_PYTHON_PROTO).
"""

import math
import os
import re
import select
import signal
import socket
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import firasim_python_test as common  # noqa: E402  (takes --vssim and --proto-dir from sys.argv)

fira = common.fira
EXAMPLE = os.path.join(HERE, "..", "examples", "firasim", "go_to_ball.py")

# One blue robot beside the ball, facing away from the goal it attacks:
# it must drive round the ball, line up behind it and push it towards x > 0.
SCENE = {
    "version": 1,
    "field": {"type": "vsss_3v3"},
    "robots": [{"team": "blue", "x": -0.45, "y": -0.2, "theta": math.pi / 2}],
    "ball": {"x": -0.25, "y": 0.05},
}
SPEED = 4.0         # simulated seconds per wall second
WALL_SECONDS = 8.0  # the example's --duration (32 s of simulated time): stopped once done
MATCH_WALL_SECONDS = 60.0  # at most, for the match against the built-in team (in lockstep: far more simulated)
MATCH_SIMULATED_MS = 300_000  # the match stops after 300 s of simulated time at most
# The match: the example's three blue robots on the left, as FIRASim places
# blue, against vssim's built-in team with one robot, which keeps the goal at
# x > 0 (a striker alone does not beat the built-in team's three robots).
KEEPER_SCENE = {
    "version": 1,
    "field": {"type": "vsss_3v3"},
    "robots": [{"name": "blue0", "team": "blue", "x": -0.68, "y": 0.0, "theta": 0.0},
               {"name": "blue1", "team": "blue", "x": -0.35, "y": 0.25, "theta": 0.0},
               {"name": "blue2", "team": "blue", "x": -0.2, "y": -0.1, "theta": 0.0},
               {"name": "yellow0", "team": "yellow", "x": 0.68, "y": 0.0, "theta": math.pi}],
    "game": {"referee": True},
}


def relayed_vision(server, relay_port, example, deadline):
    """Each Environment the server sends while the example runs (until
    `deadline`, monotonic s), after relaying its datagram, unchanged, to the
    example's vision port."""
    relay = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        while example.poll() is None and time.monotonic() < deadline:
            ready, _, _ = select.select([server.vision], [], [], 0.1)
            if not ready:
                continue
            data = server.vision.recv(65536)
            relay.sendto(data, ("127.0.0.1", relay_port))
            e = fira.Environment()
            e.ParseFromString(data)
            yield e
    finally:
        relay.close()


class ExampleRun(unittest.TestCase):
    def test_go_to_ball_pushes_the_ball_towards_the_goal(self):
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        server = common.Server(SCENE, "--speed", str(SPEED), sync=False, tmpdir=tmp.name)
        self.addCleanup(server.close)
        first = server.next()
        robot0, ball0 = common.find_robot(first, False, 0), first.frame.ball
        self.assertIsNotNone(robot0)

        # The example's own ports: vision (relayed by us) and the referee
        # (silent: --ignore-referee; unicast so that no multicast is needed).
        relay_port, referee_port = common.free_ports(2)
        env = {k: v for k, v in os.environ.items()}
        example = subprocess.Popen(
            ["/usr/bin/python3", EXAMPLE, "--team", "blue", "--robot", "0", "--ignore-referee",
             "--duration", str(WALL_SECONDS),
             "--vision-address", "127.0.0.1", "--vision-port", str(relay_port),
             "--command-address", "127.0.0.1", "--command-port", str(server.port),
             "--referee-address", "127.0.0.1", "--referee-port", str(referee_port),
             "--proto-dir", common.PROTO_DIR],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env)
        self.addCleanup(lambda: example.poll() is None and example.kill())
        closest = math.inf   # robot centre to ball centre, m
        touched_at = None
        ball_x_max = ball0.x
        last = first
        packets = 0
        stopped = None       # the step at which the example was stopped
        started = time.monotonic() - first.step * 0.001 / SPEED
        for e in relayed_vision(server, relay_port, example, time.monotonic() + WALL_SECONDS + 10.0):
            packets += 1
            last = e
            r = common.find_robot(e, False, 0)
            d = math.hypot(r.x - e.frame.ball.x, r.y - e.frame.ball.y)
            if d < closest:
                closest = d
            if touched_at is None and d < 0.08:
                touched_at = e.step
            ball_x_max = max(ball_x_max, e.frame.ball.x)
            if not stopped and touched_at is not None and (ball_x_max > ball0.x + 0.2 or e.goals_blue > 0):
                # Done: Ctrl-C, as a person would; the example stops its
                # robots and exits (0). Its --duration is the upper bound.
                example.send_signal(signal.SIGINT)
                stopped = e.step
        output = example.communicate(timeout=10)[0].decode(errors="replace")
        self.assertEqual(example.returncode, 0, output)
        print("example: %s" % output.strip().splitlines()[-1], flush=True)
        print("vision packets %d; the robot came within %.3f m of the ball (first at step %s); ball x %.3f -> %.3f "
              "(at most %.3f); goals yellow %d, blue %d; example stopped at step %s"
              % (packets, closest, touched_at, ball0.x, last.frame.ball.x, ball_x_max, last.goals_yellow,
                 last.goals_blue, stopped), flush=True)
        self.assertGreater(packets, 30)
        # --speed 4: the example ran at most WALL_SECONDS of wall time, and the
        # simulation went about 4 times as fast as the wall clock meanwhile.
        self.assertGreater(last.step * 0.001 / (time.monotonic() - started), 0.5 * SPEED)
        # Reached the ball: centres closer than a robot's half diagonal plus
        # the ball's radius (0.074 m: touching at a corner; 0.059 m face on).
        self.assertIsNotNone(touched_at, "the robot never reached the ball (closest %.3f m)" % closest)
        # Pushed towards x > 0: the ball went at least 10 cm that way (or into the goal).
        self.assertTrue(ball_x_max > ball0.x + 0.1 or last.goals_blue > 0,
                        "ball x from %.3f to at most %.3f" % (ball0.x, ball_x_max))

    def test_a_firasim_layout_team_scores_into_the_right_goal(self):
        """A match as FIRASim-based software plays it: `vssim serve --firasim-sync
        --vssref` with its defaults (blue on the left, FIRASim's layout), the
        built-in referee and the built-in yellow team (a goalkeeper); the
        example plays blue with FIRASim's conventions (it attacks x > 0,
        reads the ball's z as given, answers every stoppage with its own
        placements). It must score into the goal at x > 0, and every one of
        its placements must be accepted."""
        tmp = tempfile.TemporaryDirectory()
        self.addCleanup(tmp.cleanup)
        referee_port, placement_port, relay_port = common.free_ports(3)
        # Lockstep on the example's commands (--firasim-sync): each of its
        # answers advances one vision period, so the match does not depend on
        # how fast this machine answers.
        server = common.Server(KEEPER_SCENE, "--blue", "tcp", "--yellow", "builtin",
                               "--vssref", "--vssref-address", "127.0.0.1",
                               "--vssref-command-port", str(referee_port),
                               "--vssref-placement-port", str(placement_port), sync=True, tmpdir=tmp.name)
        self.addCleanup(server.close)
        example = subprocess.Popen(
            ["/usr/bin/python3", EXAMPLE, "--team", "blue", "--robot", "1", "--duration", str(MATCH_WALL_SECONDS),
             "--vision-address", "127.0.0.1", "--vision-port", str(relay_port),
             "--command-address", "127.0.0.1", "--command-port", str(server.port),
             "--referee-address", "127.0.0.1", "--referee-port", str(referee_port),
             "--placement-address", "127.0.0.1", "--placement-port", str(placement_port),
             "--proto-dir", common.PROTO_DIR],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        self.addCleanup(lambda: example.poll() is None and example.kill())
        goals = []        # (scorer, ball x in the last vision before the score changed)
        scored_at = None  # the vision's step (ms) when blue first scored
        interrupted = False
        score = (0, 0)    # blue, yellow
        ball_x = 0.0
        ball_z = None
        for e in relayed_vision(server, relay_port, example, time.monotonic() + MATCH_WALL_SECONDS + 10.0):
            if e.frame.HasField("ball"):
                ball_z = e.frame.ball.z
            now = (e.goals_blue, e.goals_yellow)
            if now != score:
                goals.append(("blue" if now[0] > score[0] else "yellow", ball_x))
                score = now
                if now[0] >= 1 and scored_at is None:
                    scored_at = e.step
            if e.frame.HasField("ball"):
                ball_x = e.frame.ball.x
            # Two simulated seconds after blue's goal, into the stop for the
            # kick-off that follows it (which the example answers with a
            # placement; it may have missed the first one, sent before it
            # listened), or after the longest match: stop the example.
            done = scored_at is not None and e.step > scored_at + 2000
            if (done or e.step > MATCH_SIMULATED_MS) and not interrupted:
                example.send_signal(signal.SIGINT)  # once: the assertions below say what happened
                interrupted = True
        output = example.communicate(timeout=10)[0].decode(errors="replace")
        log = server.log()
        print("goals (scorer, ball x just before): %s; example: %s" % (goals, output.strip().splitlines()[-1]),
              flush=True)
        self.assertEqual(example.returncode, 0, output)
        self.assertIn("blue defends x < 0", log)
        self.assertAlmostEqual(ball_z, 0.02135, places=6)  # the ball's centre height, as FIRASim sends it
        self.assertGreaterEqual(score[0], 1, "blue did not score in %d s of simulated time: %s"
                                % (MATCH_SIMULATED_MS // 1000, log))
        for scorer, x in goals:
            if scorer == "blue":
                self.assertGreater(x, 0.7, "blue's goal was scored at x %.3f: not in the goal at x > 0" % x)
        sent = re.search(r"placements (\d+)", output)
        self.assertIsNotNone(sent, output)
        self.assertGreaterEqual(int(sent.group(1)), 1, "the example answered no stoppage")
        self.assertNotIn("refused", log, log)


if __name__ == "__main__":
    unittest.main()
