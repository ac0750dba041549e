#!/usr/bin/python3
"""FIRASim's interface from a Python client (python3-protobuf), with modules
compiled from vssim's own .proto files (build/python_proto): `vssim serve
--firasim` as a subprocess, spoken to over UDP as team software and
VSSReferee would (docs/firasim.md).

- vision against the state: bodies replaced at known poses, at rest, seen
  where they were put (orientation sent in degrees, seen in radians);
- a robot tracks commanded wheel speeds through the on-board speed loop: the
  straight and turning speeds it settles at, and its step response against
  an independent model of the discrete PI loop driving the linear motor
  model, integrated exactly over each hold;
- replacement of robots (degrees) and of the ball (with its velocity),
  replacement-only packets in lockstep, turnon false and true;
- goals in the Environment after a goal: counted by the server with
  --referee external, and by the built-in referee with --referee on;
- --firasim-sync determinism: the same packets twice, the same bytes;
- bad input: garbage, oversized datagrams, unknown robots, NaN and huge
  wheel speeds, replacements outside the field or onto another body; the
  server keeps answering and the other team's robot is unaffected.

The vision goes by unicast to 127.0.0.1 (multicast may be unavailable in a
container; tests/test_firasim.cpp tests multicast on loopback where the
kernel allows it). Everything runs in the lockstep mode (--firasim-sync), so
nothing depends on the machine's speed.

    /usr/bin/python3 tests/firasim_python_test.py --vssim build/app/vssim \
        --proto-dir build/python_proto [unittest options]

(or the environment variables VSSIM_BINARY and VSSIM_PYTHON_PROTO).
Standard library and python3-protobuf only.
"""

import json
import math
import os
import re
import select
import socket
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))


def take_option(argv, name, default):
    """Removes `name VALUE` (or name=VALUE) from argv; returns VALUE or default."""
    for i, arg in enumerate(argv):
        if arg == name and i + 1 < len(argv):
            value = argv[i + 1]
            del argv[i:i + 2]
            return value
        if arg.startswith(name + "="):
            del argv[i]
            return arg[len(name) + 1:]
    return default


VSSIM = take_option(sys.argv, "--vssim", os.environ.get("VSSIM_BINARY",
                                                        os.path.join(HERE, "..", "build", "app", "vssim")))
PROTO_DIR = take_option(sys.argv, "--proto-dir", os.environ.get("VSSIM_PYTHON_PROTO",
                                                                os.path.join(HERE, "..", "build", "python_proto")))
sys.path.insert(0, PROTO_DIR)
import fira_packet_pb2 as fira  # noqa: E402  (generated from runtime/proto/fira_packet.proto)

# --------------------------------------------------------------------------
# The default robot (docs/scenes.md) and its speed loop (speed_controller.h)
# --------------------------------------------------------------------------

MASS = 0.18             # kg
SIDE = 0.075            # m
INERTIA = MASS * SIDE ** 2 / 6  # kg m^2, a uniform cube
WHEEL_BASE = 0.065      # m
FRICTION_LINEAR = 0.05  # N s/m
FRICTION_ANGULAR = 0.0002  # N m s/rad
WHEEL_RADIUS = 0.025    # m
RESISTANCE = 12.0       # ohm
MOTOR_K = 0.09          # V s/rad
ROTOR_INERTIA = 1e-5    # kg m^2
MOTOR_FRICTION = 1e-4   # N m s/rad
MAX_VOLTAGE = 7.4       # V
LOOP_RATE = 200.0       # Hz
LOOP_KP = 0.6           # V per rad/s
LOOP_KI = 10.0          # V per rad
DT = 0.001              # s, the engine's step
BALL_DECAY = 0.02 / 0.046  # 1/s, the ball's friction over its mass
FIELD_3V3 = {"width": 1.30, "length": 1.50, "goal_width": 0.40, "goal_depth": 0.10, "center_radius": 0.20,
             "penalty_width": 0.70, "penalty_depth": 0.15, "penalty_point": 0.375}


# Small dense matrices as lists of rows: enough linear algebra for a 2x2
# system (numpy and scipy are not required).
def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(len(b))) for j in range(len(b[0]))] for i in range(len(a))]


def mat_add(a, b, scale=1.0):
    return [[a[i][j] + scale * b[i][j] for j in range(len(a[0]))] for i in range(len(a))]


def transpose(a):
    return [list(row) for row in zip(*a)]


def identity(n):
    return [[1.0 if i == j else 0.0 for j in range(n)] for i in range(n)]


def inverse2(a):
    det = a[0][0] * a[1][1] - a[0][1] * a[1][0]
    return [[a[1][1] / det, -a[0][1] / det], [-a[1][0] / det, a[0][0] / det]]


def diag(*values):
    return [[values[i] if i == j else 0.0 for j in range(len(values))] for i in range(len(values))]


def expm(a):
    """exp(a) by scaling and squaring with a Taylor series (to double precision
    for the small, well-conditioned matrices used here)."""
    norm = max(sum(abs(x) for x in row) for row in a)
    squarings = max(0, int(math.ceil(math.log2(norm / 0.1))) if norm > 0.1 else 0)
    scaled = [[x / 2 ** squarings for x in row] for row in a]
    n = len(a)
    result, term = identity(n), identity(n)
    for k in range(1, 30):
        term = [[x / k for x in row] for row in mat_mul(term, scaled)]
        result = mat_add(result, term)
    for _ in range(squarings):
        result = mat_mul(result, result)
    return result


class RobotModel:
    """The default robot's body velocity u = (v, omega) under armature voltages
    e = (e_right, e_left): M u' + B u = K e (docs/model.md), with
    M = diag(m, J) + Tw^-T diag(Jr, Jr) Tw^-1,
    B = diag(beta_l, beta_theta) + Tw^-T diag(K^2/R + beta, K^2/R + beta) Tw^-1,
    K = Tw^-T diag(K/R, K/R), wheel speeds (right, left) = Tw^-1 u."""

    def __init__(self):
        r, b = WHEEL_RADIUS, WHEEL_BASE
        self.tw_inv = [[1 / r, b / (2 * r)], [1 / r, -b / (2 * r)]]
        tw_inv_t = transpose(self.tw_inv)
        m = mat_add(diag(MASS, INERTIA), mat_mul(mat_mul(tw_inv_t, diag(ROTOR_INERTIA, ROTOR_INERTIA)), self.tw_inv))
        damping = MOTOR_K ** 2 / RESISTANCE + MOTOR_FRICTION
        bm = mat_add(diag(FRICTION_LINEAR, FRICTION_ANGULAR),
                     mat_mul(mat_mul(tw_inv_t, diag(damping, damping)), self.tw_inv))
        km = mat_mul(tw_inv_t, diag(MOTOR_K / RESISTANCE, MOTOR_K / RESISTANCE))
        m_inv = inverse2(m)
        a = [[-x for x in row] for row in mat_mul(m_inv, bm)]
        g = mat_mul(m_inv, km)
        # u(t + h) = Phi u(t) + Gamma e for e held over h: the top blocks of
        # exp([[A, G], [0, 0]] h).
        z = [a[0] + g[0], a[1] + g[1], [0.0] * 4, [0.0] * 4]
        e = expm([[x * DT for x in row] for row in z])
        self.phi = [row[:2] for row in e[:2]]
        self.gamma = [row[2:] for row in e[:2]]

    def wheels(self, u):
        return [self.tw_inv[i][0] * u[0] + self.tw_inv[i][1] * u[1] for i in range(2)]

    def step(self, u, volts):
        return [sum(self.phi[i][j] * u[j] for j in range(2)) + sum(self.gamma[i][j] * volts[j] for j in range(2))
                for i in range(2)]


def pi_update(integral, target, measured):
    """One PI update of one wheel: (voltage, new integral). Conditional
    integration: the integrator takes the error only when the output it
    would give is not saturated or when the error pulls the output back."""
    period = 1.0 / LOOP_RATE
    error = target - measured
    integrated = min(max(integral + LOOP_KI * error * period, -MAX_VOLTAGE), MAX_VOLTAGE)
    unclamped = LOOP_KP * error + integrated
    if abs(unclamped) <= MAX_VOLTAGE or (unclamped > 0) != (error > 0):
        integral = integrated
    return min(max(LOOP_KP * error + integral, -MAX_VOLTAGE), MAX_VOLTAGE), integral


def predict_speeds(schedule, last_step):
    """The robot's (v, omega) at every step boundary 0..last_step, starting at
    rest with 0 V, its loop switched on by the first command: `schedule` maps
    a step to the (right, left) wheel-speed targets that apply from it. The
    loop samples at k / LOOP_RATE (every 5 steps of 1 ms) and holds its
    voltages in between; the motors are integrated exactly over each step."""
    model = RobotModel()
    steps_per_sample = round(1.0 / (LOOP_RATE * DT))
    u, volts, integrals, target, active = [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], None, False
    out = [tuple(u)]
    for n in range(last_step):
        if n in schedule:
            target = schedule[n]
            if not active:  # the first sample is the first loop instant at or after now
                active = True
                first = -(-n // steps_per_sample) * steps_per_sample
        if active and n >= first and n % steps_per_sample == 0:
            measured = model.wheels(u)
            for w in range(2):
                volts[w], integrals[w] = pi_update(integrals[w], target[w], measured[w])
        u = model.step(u, volts)
        out.append(tuple(u))
    return out


# --------------------------------------------------------------------------
# Packets
# --------------------------------------------------------------------------

def command(packet, yellow, robot_id, right, left):
    c = packet.cmd.robot_commands.add()
    c.id, c.yellowteam, c.wheel_right, c.wheel_left = robot_id, yellow, right, left
    return packet


def replace_robot(packet, yellow, robot_id, x, y, degrees, turnon=True, vx=0.0, vy=0.0, vorientation=0.0):
    r = packet.replace.robots.add()
    r.yellowteam, r.turnon = yellow, turnon
    p = r.position
    p.robot_id, p.x, p.y, p.orientation, p.vx, p.vy, p.vorientation = robot_id, x, y, degrees, vx, vy, vorientation
    return packet


def replace_ball(packet, x, y, vx=0.0, vy=0.0):
    b = packet.replace.ball
    b.x, b.y, b.vx, b.vy = x, y, vx, vy
    return packet


def tick(packet=None):
    """A packet with the `cmd` field present (an empty Commands is a pure tick)."""
    packet = packet if packet is not None else fira.Packet()
    packet.cmd.SetInParent()
    return packet


def find_robot(env, yellow, robot_id):
    for r in (env.frame.robots_yellow if yellow else env.frame.robots_blue):
        if r.robot_id == robot_id:
            return r
    return None


def wrap(angle):
    return math.atan2(math.sin(angle), math.cos(angle))


# --------------------------------------------------------------------------
# The server
# --------------------------------------------------------------------------

# One yellow and one blue robot far apart, the ball elsewhere; no game
# section: no referee, both teams remote.
TWO_ROBOTS = {
    "version": 1,
    "field": {"type": "vsss_3v3"},
    "robots": [{"team": "yellow", "x": -0.6, "y": 0.35, "theta": 0.0},
               {"team": "blue", "x": 0.55, "y": -0.45, "theta": math.pi}],
    "ball": {"x": -0.3, "y": -0.2},
}


def free_ports(n):
    """n distinct UDP ports free on 127.0.0.1 now (all held while chosen)."""
    sockets = [socket.socket(socket.AF_INET, socket.SOCK_DGRAM) for _ in range(n)]
    for s in sockets:
        s.bind(("127.0.0.1", 0))
    ports = [s.getsockname()[1] for s in sockets]
    for s in sockets:
        s.close()
    return ports


def free_port():
    return free_ports(1)[0]


class Server:
    """`vssim serve SCENE --firasim-sync` (or --firasim) with its vision sent
    by unicast to a socket of ours on 127.0.0.1."""

    def __init__(self, scene, *extra, sync=True, tmpdir=None):
        if isinstance(scene, dict):
            path = os.path.join(tmpdir, "scene.json")
            with open(path, "w") as f:
                json.dump(scene, f)
            scene = path
        self.vision = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.vision.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 20)
        self.vision.bind(("127.0.0.1", 0))
        self.vision_port = self.vision.getsockname()[1]
        self.out = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.log_file = tempfile.TemporaryFile()
        env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM")}
        for attempt in range(3):  # a free port may be taken between our test and the server's bind
            self.port = free_port()
            args = [VSSIM, "serve", scene, "--port", "0", "--firasim-port", str(self.port),
                    "--vision-address", "127.0.0.1", "--vision-port", str(self.vision_port),
                    "--quit-after", "120"] + (["--firasim-sync"] if sync else ["--firasim"]) + list(extra)
            self.proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=self.log_file, env=env)
            line = self._read_banner()
            if line:
                break
            self.proc.wait(5)
        else:
            raise AssertionError("vssim serve did not start: %s" % self.log())
        address, port, vision = line
        assert (address, port) == ("127.0.0.1", self.port), line
        assert vision == self.vision_port, line
        print("unicast vision 127.0.0.1:%d (multicast is tested by test_firasim)" % self.vision_port, flush=True)
        self.last = -1
        self.raw = None

    def _read_banner(self, timeout=20.0):
        pattern = re.compile(rb"firasim: commands on ([0-9.]+):([0-9]+), vision to 127\.0\.0\.1:([0-9]+)")
        out, end = b"", time.monotonic() + timeout
        fd = self.proc.stdout.fileno()
        while time.monotonic() < end:
            m = pattern.search(out)
            if m:
                return m.group(1).decode(), int(m.group(2)), int(m.group(3))
            ready, _, _ = select.select([fd], [], [], 0.2)
            if ready:
                chunk = os.read(fd, 4096)
                if not chunk:
                    return None  # exited
                out += chunk
        return None

    def send(self, data):
        if not isinstance(data, (bytes, bytearray)):
            data = data.SerializeToString()
        self.out.sendto(data, ("127.0.0.1", self.port))

    def receive(self, timeout=5.0):
        """The next Environment (its bytes in self.raw), or None after timeout s."""
        ready, _, _ = select.select([self.vision], [], [], timeout)
        if not ready:
            return None
        self.raw = self.vision.recv(65536)
        env = fira.Environment()
        env.ParseFromString(self.raw)
        return env

    def next(self, timeout=5.0):
        """The next Environment newer than the last one seen."""
        end = time.monotonic() + timeout
        while True:
            env = self.receive(max(0.0, end - time.monotonic()))
            if env is None:
                raise AssertionError("no Environment after step %d within %g s; log: %s"
                                     % (self.last, timeout, self.log()))
            if env.step > self.last:
                self.last = env.step
                return env

    def step(self, packet=None):
        """Sync mode: sends a packet with `cmd` (one vision period) and returns
        the Environment at its end."""
        self.send(tick(packet))
        return self.next()

    def quiet(self, seconds=0.3):
        """True when no Environment arrives within `seconds`."""
        return self.receive(seconds) is None

    def log(self):
        if self.log_file.closed:
            return self.final_log
        self.log_file.flush()
        self.log_file.seek(0)
        return self.log_file.read().decode(errors="replace")

    def close(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.proc.stdout.close()
        self.final_log = self.log()
        self.vision.close()
        self.out.close()
        self.log_file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


class FirasimTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def server(self, scene, *extra, **kw):
        s = Server(scene, *extra, tmpdir=self.tmp.name, **kw)
        self.addCleanup(s.close)
        first = s.next()  # the vision of the start, step 0
        self.assertEqual(first.step, 0)
        return s, first


class VisionAgainstTheState(FirasimTest):
    def test_bodies_at_rest_are_seen_where_they_were_put(self):
        s, first = self.server(TWO_ROBOTS)
        # The scene's own poses at step 0.
        y0, b0 = find_robot(first, True, 0), find_robot(first, False, 0)
        self.assertEqual((y0.x, y0.y, y0.orientation), (-0.6, 0.35, 0.0))
        self.assertEqual((b0.x, b0.y), (0.55, -0.45))
        self.assertAlmostEqual(b0.orientation, math.pi, delta=1e-12)
        self.assertEqual((first.frame.ball.x, first.frame.ball.y), (-0.3, -0.2))
        for key, value in FIELD_3V3.items():
            self.assertAlmostEqual(getattr(first.field, key), value, delta=1e-12, msg=key)
        # Replaced, at rest, and one vision period with zero commands.
        p = fira.Packet()
        replace_robot(p, True, 0, -0.2, 0.3, 30.0)
        replace_robot(p, False, 0, 0.4, -0.25, -135.0)
        replace_ball(p, 0.1, -0.1)
        command(p, True, 0, 0.0, 0.0)
        command(p, False, 0, 0.0, 0.0)
        env = s.step(p)
        self.assertGreater(env.step, 0)
        self.assertEqual(len(env.frame.robots_yellow), 1)
        self.assertEqual(len(env.frame.robots_blue), 1)
        y0, b0, ball = find_robot(env, True, 0), find_robot(env, False, 0), env.frame.ball
        for got, want in ((ball.x, 0.1), (ball.y, -0.1), (ball.z, 0.02135), (ball.vx, 0.0), (ball.vy, 0.0),
                          (y0.x, -0.2), (y0.y, 0.3), (y0.orientation, math.radians(30.0)),
                          (y0.vx, 0.0), (y0.vy, 0.0), (y0.vorientation, 0.0),
                          (b0.x, 0.4), (b0.y, -0.25), (wrap(b0.orientation), math.radians(-135.0)),
                          (b0.vx, 0.0), (b0.vy, 0.0), (b0.vorientation, 0.0)):
            self.assertAlmostEqual(got, want, delta=1e-9)
        for key, value in FIELD_3V3.items():
            self.assertAlmostEqual(getattr(env.field, key), value, delta=1e-12, msg=key)
        self.assertEqual((env.goals_yellow, env.goals_blue), (0, 0))
        # Still there a period later (nothing drives them).
        again = s.step()
        self.assertGreater(again.step, env.step)
        self.assertEqual(find_robot(again, True, 0).x, y0.x)
        self.assertEqual(again.frame.ball.x, ball.x)

    def test_moving_robot_velocity_is_along_its_heading(self):
        s, _ = self.server(TWO_ROBOTS)
        p = replace_robot(fira.Packet(), True, 0, -0.3, 0.2, 60.0)
        env = s.step(command(p, True, 0, 25.0, 15.0))
        for _ in range(20):
            env = s.step(command(fira.Packet(), True, 0, 25.0, 15.0))
        r = find_robot(env, True, 0)
        speed = math.hypot(r.vx, r.vy)
        self.assertGreater(speed, 0.1)
        # vx, vy = v (cos theta, sin theta): the velocity is along the heading.
        self.assertAlmostEqual(r.vx, speed * math.cos(r.orientation), delta=1e-12)
        self.assertAlmostEqual(r.vy, speed * math.sin(r.orientation), delta=1e-12)
        self.assertGreater(r.vorientation, 0.5)  # right wheel faster: counter-clockwise


class SpeedLoop(FirasimTest):
    def test_tracks_wheel_speeds_and_matches_the_loop_model(self):
        s, _ = self.server(TWO_ROBOTS)
        seen = {}       # step -> (v, omega) of yellow 0
        schedule = {}   # step -> (right, left) targets from it
        blue = []

        def run(right, left, until):
            env = None
            while s.last < until:
                schedule.setdefault(s.last, (right, left))
                env = s.step(command(fira.Packet(), True, 0, right, left))
                r = find_robot(env, True, 0)
                v = math.hypot(r.vx, r.vy)
                seen[env.step] = (v if r.vx * math.cos(r.orientation) + r.vy * math.sin(r.orientation) >= 0 else -v,
                                  r.vorientation)
                blue.append(find_robot(env, False, 0))
            return env

        # Straight: both wheels at 20 rad/s for 1.5 s.
        env = run(20.0, 20.0, 1500)
        r = find_robot(env, True, 0)
        self.assertAlmostEqual(math.hypot(r.vx, r.vy), WHEEL_RADIUS * 20.0, delta=1e-3)
        self.assertAlmostEqual(r.vorientation, 0.0, delta=1e-6)
        self.assertAlmostEqual(r.orientation, 0.0, delta=1e-6)
        self.assertAlmostEqual(r.y, 0.35, delta=1e-6)
        # Turning: right 30, left 10 rad/s for 1.5 s more.
        env = run(30.0, 10.0, 3000)
        r = find_robot(env, True, 0)
        self.assertAlmostEqual(r.vorientation, WHEEL_RADIUS * (30.0 - 10.0) / WHEEL_BASE, delta=1e-2)
        self.assertAlmostEqual(math.hypot(r.vx, r.vy), WHEEL_RADIUS * (30.0 + 10.0) / 2, delta=1e-3)

        # The loop's own model, step by step: the first 100 ms (the step
        # response, saturated at first) to 1e-6 m/s, and the whole run.
        predicted = predict_speeds(schedule, max(seen))
        first = sorted(k for k in seen if k <= 100)
        self.assertGreaterEqual(len(first), 5)
        worst = 0.0
        for k in sorted(seen):
            v, omega = seen[k]
            pv, pomega = predicted[k]
            if k <= 100:
                self.assertAlmostEqual(v, pv, delta=1e-6, msg="v at step %d" % k)
                self.assertAlmostEqual(omega, pomega, delta=1e-6, msg="omega at step %d" % k)
            worst = max(worst, abs(v - pv), abs(omega - pomega) * WHEEL_BASE / 2)
        print("speed loop: %d vision packets over %d steps; largest difference from the model %.2g m/s"
              % (len(seen), max(seen), worst), flush=True)
        self.assertLess(worst, 1e-6)
        # The first period saturates (12 V asked): a model without the clamp
        # would be far off, so the comparison does check the clamp.
        self.assertGreater(seen[first[0]][0], 0.1)
        # Blue was never commanded: at rest where the scene put it.
        for b in blue:
            self.assertEqual((b.x, b.y, b.vx, b.vy), (0.55, -0.45, 0.0, 0.0))


class Replacement(FirasimTest):
    def test_robots_in_degrees_and_the_ball_with_its_velocity(self):
        s, first = self.server(TWO_ROBOTS)
        p = fira.Packet()
        # The replacement's speeds are ignored: robots are placed at rest.
        replace_robot(p, True, 0, 0.2, 0.3, 90.0, vx=1.0, vy=0.5, vorientation=3.0)
        replace_robot(p, False, 0, -0.4, -0.3, 225.0)
        replace_ball(p, 0.0, -0.1, 0.5, -0.2)
        start = s.last
        env = s.step(p)
        t = (env.step - start) * DT
        y0, b0, ball = find_robot(env, True, 0), find_robot(env, False, 0), env.frame.ball
        self.assertAlmostEqual(y0.x, 0.2, delta=1e-9)
        self.assertAlmostEqual(y0.y, 0.3, delta=1e-9)
        self.assertAlmostEqual(y0.orientation, math.pi / 2, delta=1e-9)
        self.assertEqual((y0.vx, y0.vy, y0.vorientation), (0.0, 0.0, 0.0))
        self.assertAlmostEqual(b0.x, -0.4, delta=1e-9)
        self.assertAlmostEqual(wrap(b0.orientation), wrap(math.radians(225.0)), delta=1e-9)
        # The ball rolls from where it was put with its speed decaying as
        # exp(-beta t / m) (docs/model.md).
        travelled = (1 - math.exp(-BALL_DECAY * t)) / BALL_DECAY
        self.assertAlmostEqual(ball.x, 0.0 + 0.5 * travelled, delta=1e-9)
        self.assertAlmostEqual(ball.y, -0.1 - 0.2 * travelled, delta=1e-9)
        self.assertAlmostEqual(ball.vx, 0.5 * math.exp(-BALL_DECAY * t), delta=1e-9)
        self.assertAlmostEqual(ball.vy, -0.2 * math.exp(-BALL_DECAY * t), delta=1e-9)

        # Replacement only (no `cmd`): applied without a step; the next tick shows it.
        q = replace_robot(fira.Packet(), True, 0, -0.5, 0.45, -45.0)
        s.send(q)
        self.assertTrue(s.quiet(0.3), "a replacement-only packet must not step")
        before = s.last
        env = s.step()
        self.assertGreater(env.step, before)
        y0 = find_robot(env, True, 0)
        self.assertAlmostEqual(y0.x, -0.5, delta=1e-9)
        self.assertAlmostEqual(y0.y, 0.45, delta=1e-9)
        self.assertAlmostEqual(y0.orientation, -math.pi / 4, delta=1e-9)

    def test_turnon_false_takes_a_robot_off_and_true_brings_it_back(self):
        s, first = self.server(TWO_ROBOTS)
        # Blue 0 driving; then off the field.
        was = find_robot(s.step(command(fira.Packet(), False, 0, 15.0, 15.0)), False, 0)
        off = fira.Packet()
        replace_robot(off, False, 0, 0.0, 0.0, 0.0, turnon=False)
        env = s.step(off)
        self.assertIsNone(find_robot(env, False, 0))
        self.assertEqual(len(env.frame.robots_blue), 0)
        self.assertIsNotNone(find_robot(env, True, 0))
        # Commands to a robot off the field do nothing; it stays off.
        for _ in range(5):
            env = s.step(command(fira.Packet(), False, 0, 15.0, 15.0))
            self.assertEqual(len(env.frame.robots_blue), 0)
        # A robot off the field does not block a replacement where it was.
        env = s.step(replace_robot(fira.Packet(), True, 0, was.x, was.y, 0.0))
        y0 = find_robot(env, True, 0)
        self.assertAlmostEqual(y0.x, was.x, delta=1e-9)
        self.assertAlmostEqual(y0.y, was.y, delta=1e-9)
        # Back on, at the given pose, at rest.
        on = replace_robot(fira.Packet(), False, 0, 0.3, -0.45, 90.0, turnon=True)
        env = s.step(command(on, False, 0, 0.0, 0.0))
        b0 = find_robot(env, False, 0)
        self.assertIsNotNone(b0)
        self.assertAlmostEqual(b0.x, 0.3, delta=1e-9)
        self.assertAlmostEqual(b0.y, -0.45, delta=1e-9)
        self.assertAlmostEqual(b0.orientation, math.pi / 2, delta=1e-9)
        self.assertEqual((b0.vx, b0.vy, b0.vorientation), (0.0, 0.0, 0.0))
        # And it drives again.
        for _ in range(20):
            env = s.step(command(fira.Packet(), False, 0, 15.0, 15.0))
        self.assertGreater(find_robot(env, False, 0).y, -0.45 + 0.05)


class Goals(FirasimTest):
    def shoot(self, s, x, y, vx, counter, want, ticks=120):
        env = s.step(replace_ball(fira.Packet(), x, y, vx, 0.0))
        for _ in range(ticks):
            if getattr(env, counter) == want:
                break
            env = s.step()
        return env

    def test_external_referee_the_goals_stay_as_firasim_sends_them(self):
        # FIRASim never counts goals (its arbiter is switched off in its
        # source): with an external referee, which keeps the score itself,
        # the vision's goal fields stay 0:0 through goals at both ends.
        s, first = self.server(TWO_ROBOTS, "--referee", "external")
        self.assertEqual((first.goals_yellow, first.goals_blue), (0, 0))
        for x, vx, past in ((0.6, 1.5, lambda b: b > 0.75), (-0.6, -1.5, lambda b: b < -0.75)):
            env = s.step(replace_ball(fira.Packet(), x, 0.1, vx, 0.0))
            went_in = False
            for _ in range(120):
                self.assertEqual((env.goals_yellow, env.goals_blue), (0, 0))
                went_in = went_in or past(env.frame.ball.x)
                env = s.step()
            self.assertTrue(went_in, "the shot at x %.1f went in" % x)
        self.assertIn("0:0, as FIRASim sends them (--referee external", s.log())

    def test_builtin_referee_goal_in_the_environment(self):
        s, first = self.server("kickoff_3v3", "--yellow", "tcp", "--blue", "tcp", "--referee", "on")
        # The match starts stopped for the kick-off (4 s by default): tick
        # through it, then shoot.
        env = first
        while env.step < 4500:
            env = s.step()
        self.assertEqual((env.goals_yellow, env.goals_blue), (0, 0))
        # --firasim plays FIRASim's layout: the goal at x > 0 is yellow's, so blue scores.
        env = self.shoot(s, 0.6, 0.1, 1.5, "goals_blue", 1)
        self.assertEqual((env.goals_yellow, env.goals_blue), (0, 1))
        for _ in range(30):
            env = s.step()
        self.assertEqual((env.goals_yellow, env.goals_blue), (0, 1))
        self.assertIn("the built-in referee's", s.log())
        self.assertIn("blue defends x < 0", s.log())


class SyncDeterminism(FirasimTest):
    def run_once(self):
        s, first = self.server("kickoff_3v3", "--yellow", "tcp", "--blue", "tcp", "--referee", "off")
        out = [s.raw]
        setup = fira.Packet()
        replace_ball(setup, 0.1, 0.05, -0.8, 0.3)
        replace_robot(setup, True, 2, -0.1, -0.3, 30.0)
        s.send(setup)
        for k in range(90):
            p = fira.Packet()
            command(p, True, 0, 10.0 + 0.1 * k, 12.0)
            command(p, True, 1, 30.0, -5.0)
            command(p, False, 1, -8.0, 5.0 * math.sin(0.1 * k))
            command(p, False, 2, 40.0, 38.0)
            if k == 40:
                replace_ball(p, 0.0, 0.0, 1.0, 1.0)
            s.step(p)
            out.append(s.raw)
        s.close()
        return out

    def test_same_packets_same_bytes(self):
        a = self.run_once()
        b = self.run_once()
        self.assertEqual(len(a), 91)
        self.assertEqual(len(set(a)), 91, "the world moves: every Environment differs")
        self.assertEqual(a, b)


class BadInput(FirasimTest):
    def drive_blue(self, bad):
        """Blue 0 driven at 20 rad/s for 1 s while yellow (bad) sends
        garbage, bad speeds and bad replacements; blue 0's vision per step."""
        s, first = self.server(TWO_ROBOTS)
        track = []
        while s.last < 1000:
            p = command(fira.Packet(), False, 0, 20.0, 20.0)
            if bad:
                s.send(b"\xff\xff\xff\xff garbage \x01\x02")          # not a Packet
                s.send(b"\x0a" * 9000)                                 # oversized
                s.send(b"")                                            # empty: a Packet with nothing in it
                command(p, True, 0, float("nan"), 1e30)                # NaN -> 0, huge -> 1000 rad/s
                command(p, True, 7, 1.0, 1.0)                          # unknown yellow robot
                command(p, False, 9, 1.0, 1.0)                         # unknown blue robot
                replace_robot(p, True, 5, 0.0, 0.0, 0.0)               # unknown robot
                replace_robot(p, True, 0, 1.0, 0.0, 0.0)               # beyond the goal line
                replace_robot(p, True, 0, 0.74, 0.6, 0.0)              # into a corner
                replace_robot(p, True, 0, float("inf"), 0.0, 0.0)      # not finite
                replace_ball(p, 0.0, 0.9, 0.0, 0.0)                    # outside the field
                bx, by = (track[-1][1], track[-1][2]) if track else (0.55, -0.45)
                replace_robot(p, True, 0, bx + 0.03, by, 0.0)          # onto blue 0 (as last seen)
                if len(track) % 3 == 0:
                    replace_ball(p, 0.0, 0.0, 50.0, 0.0)               # faster than 20 m/s
            env = s.step(p)
            if bad:
                ball = env.frame.ball
                self.assertLess(abs(ball.y), 0.65)
                self.assertLess(math.hypot(ball.vx, ball.vy), 1e-9)
                y0 = find_robot(env, True, 0)
                self.assertLess(abs(y0.x), 0.75)
                self.assertTrue(all(math.isfinite(v) for v in (y0.x, y0.y, y0.orientation, y0.vx, y0.vy)))
            b = find_robot(env, False, 0)
            track.append((env.step, b.x, b.y, b.orientation, b.vx, b.vy, b.vorientation))
        # Still answering, and still accepting good replacements.
        env = s.step(replace_robot(fira.Packet(), True, 0, -0.5, 0.4, 45.0))
        self.assertLess(math.hypot(find_robot(env, True, 0).x + 0.5, find_robot(env, True, 0).y - 0.4), 0.01)
        s.close()
        return track, s.log()

    def test_bad_input_leaves_the_other_team_alone(self):
        good, _ = self.drive_blue(False)
        bad, log = self.drive_blue(True)
        self.assertEqual(len(good), len(bad))
        self.assertEqual(good, bad, "blue's robot must not feel yellow's bad input")
        # Blue tracked its command: 0.5 m/s along its heading (towards -x).
        step, x, y, theta, vx, vy, omega = bad[-1]
        self.assertAlmostEqual(math.hypot(vx, vy), WHEEL_RADIUS * 20.0, delta=2e-3)
        self.assertLess(x, 0.55 - 0.3)
        for words in ("not a fira_message.sim_to_ref.Packet", "refused"):
            self.assertIn(words, log)


if __name__ == "__main__":
    unittest.main()
