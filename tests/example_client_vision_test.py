#!/usr/bin/python3
"""The example clients' vision (examples/README.md, "Vision") without vssim.

- The pixel -> field mapping of examples/python/vssim_client.py: points
  projected by OpenCV itself (cv2.projectPoints, the camera 2 m above the
  field centre looking down: rvec (pi, 0, 0), tvec (0, 0, height)) through the
  realistic preset's lens come back to within a micrometre at the height they
  were projected from; the orthographic map of the ideal camera, with its
  pixel centres at +0.5; the parallax of the top face; bad WELCOME cameras.
- The colour classes under the realistic camera's light: vignetting, a
  gradient, the colour cast, sensor noise and motion blur, on every identity
  colour and both teams, anywhere on the field.
- Both clients (Python, and C++ when VSSIM_EXAMPLE_CLIENT names it) against
  a mock server in this file, which answers WELCOME with a pinhole camera
  and sends images drawn here (the same camera model, the same light and
  noise, delivered 60 ms late in lockstep, one frame in 20 dropped): their
  estimates of a still robot and ball are within 3 mm and 4 degrees of the
  truth, and a robot moved by the client's voltages (a simple unicycle
  model) reaches the ball.

Run with Debian's python3 (numpy, OpenCV):
    /usr/bin/python3 tests/example_client_vision_test.py -v
"""

import json
import math
import os
import re
import socket
import struct
import subprocess
import sys
import threading
import unittest

import cv2
import numpy as np

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PYTHON_CLIENT = os.path.join(SOURCE_DIR, "examples", "python", "vssim_client.py")
sys.path.insert(0, os.path.dirname(PYTHON_CLIENT))
import vssim_client as client  # noqa: E402

CPP_CLIENT = os.environ.get("VSSIM_EXAMPLE_CLIENT")

# The 1.5 x 1.3 m field's ideal camera and the realistic preset's lens and light
# (engine/include/vssim/camera_settings.h): focal length = scale * height.
WIDTH, HEIGHT = 640, 480
SCALE = min(600 / (1.5 + 2 * 0.1), 440 / 1.3)
CAMERA_HEIGHT = 2.0
FOCAL = SCALE * CAMERA_HEIGHT
MATRIX = np.array([[FOCAL, 0, 319.5], [0, FOCAL, 239.5], [0, 0, 1]])
DISTORTION = np.array([-0.15, 0.03, 0.0005, -0.0005, 0.0])
LIGHT = {"vignetting": 0.30, "gradient_x": 0.10, "gradient_y": -0.05,
         "gain_b": 0.92, "gain_g": 1.00, "gain_r": 1.08, "noise": 3.0, "exposure": 0.010}
SIDE, BALL_RADIUS = 0.075, 0.02135
RVEC, TVEC = np.array([math.pi, 0.0, 0.0]), np.array([0.0, 0.0, CAMERA_HEIGHT])
# What vision from these images achieves: a patch's centroid (of a binary
# mask of about 10 x 20 px) is within 0.4 px, about 1.2 mm; the robot's
# heading comes from two centroids 9 px apart, so within about 2.5 degrees.
POSITION_TOLERANCE, HEADING_TOLERANCE = 0.003, math.radians(4)

# WELCOME's camera: "height" is the image's (px), "mount_height" the camera's above the field (m).
PINHOLE_CAMERA = {"width": WIDTH, "height": HEIGHT, "scale": SCALE, "centre_u": 320, "centre_v": 240,
                  "projection": "pinhole", "mount_height": CAMERA_HEIGHT,
                  "matrix": MATRIX.tolist(), "distortion": DISTORTION.tolist(),
                  "settings": dict(LIGHT, projection="pinhole", height=CAMERA_HEIGHT, latency=0.05,
                                   jitter=0.01, drop=0.01)}
ORTHOGRAPHIC_CAMERA = {"width": WIDTH, "height": HEIGHT, "scale": SCALE, "centre_u": 320, "centre_v": 240}


# --------------------------------------------------------------------------
# Drawing what the camera sees
# --------------------------------------------------------------------------

def project(points):
    """World points (N x 3, m) -> OpenCV pixel coordinates (N x 2) through the lens."""
    image, _ = cv2.projectPoints(np.asarray(points, np.float64).reshape(-1, 1, 3), RVEC, TVEC, MATRIX, DISTORTION)
    return image.reshape(-1, 2)


def rectangle(x0, x1, y0, y1, pose, z, per_edge=6):
    """The outline of a rectangle of the robot's frame ([x0, x1] x [y0, y1]) at
    height z, in world coordinates, with points along its edges (the lens bends them)."""
    x, y, theta = pose
    c, s = math.cos(theta), math.sin(theta)
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    outline = []
    for (ax, ay), (bx, by) in zip(corners, corners[1:] + corners[:1]):
        for k in range(per_edge):
            f = k / per_edge
            px, py = ax + f * (bx - ax), ay + f * (by - ay)
            outline.append((x + c * px - s * py, y + s * px + c * py, z))
    return outline


# Drawn SUPERSAMPLE times finer, without anti-aliasing, then averaged down:
# each pixel gets its coverage to 1/16 (OpenCV's anti-aliased polygons are up
# to 0.4 px off, which would be the test's error, not the clients').
SUPERSAMPLE = 4


def fine(pixels):
    """OpenCV pixel coordinates -> the fine image's, with 8 fractional bits."""
    return np.round((np.asarray(pixels) * SUPERSAMPLE + (SUPERSAMPLE - 1) / 2) * 256).astype(np.int32)


def fill(image, world_outline, bgr):
    cv2.fillPoly(image, [fine(project(world_outline))], bgr, cv2.LINE_8, shift=8)


def draw_scene(robots, ball):
    """The bodies on the empty field, flat colours (float BGR): robots as
    (pose, team colour, identity colour), seen from above: the top face at
    z = side, black with the two patches; the ball a disc around its centre."""
    image = np.full((HEIGHT * SUPERSAMPLE, WIDTH * SUPERSAMPLE, 3), 20, np.uint8)
    centre = fine(project([(0, 0, 0)]))[0]
    cv2.circle(image, tuple(centre), int(0.2 * FOCAL / CAMERA_HEIGHT * SUPERSAMPLE * 256),
               (255, 255, 255), SUPERSAMPLE, cv2.LINE_8, shift=8)   # a field marking (white, 1 px)
    for pose, team_bgr, identity_bgr in robots:
        h = 0.5 * SIDE
        fill(image, rectangle(-h, h, -h, h, pose, SIDE), (0, 0, 0))
        fill(image, rectangle(-0.45 * SIDE, -0.05 * SIDE, -0.4 * SIDE, 0.4 * SIDE, pose, SIDE), team_bgr)
        fill(image, rectangle(0.05 * SIDE, 0.45 * SIDE, -0.4 * SIDE, 0.4 * SIDE, pose, SIDE), identity_bgr)
    if ball is not None:
        centre = fine(project([(ball[0], ball[1], BALL_RADIUS)]))[0]
        radius = FOCAL * BALL_RADIUS / (CAMERA_HEIGHT - BALL_RADIUS) * SUPERSAMPLE
        cv2.circle(image, tuple(centre), int(round(radius * 256)), client.BALL_COLOUR, -1, cv2.LINE_8, shift=8)
    return cv2.resize(image, (WIDTH, HEIGHT), interpolation=cv2.INTER_AREA).astype(np.float64)


def light_field():
    """Per pixel and channel: vignetting (r^2 to the corners), a gradient, the colour cast."""
    v, u = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float64)
    du, dv = (u - 319.5) / 319.5, (v - 239.5) / 239.5
    light = (1 - LIGHT["vignetting"] * (du ** 2 + dv ** 2) / 2) \
        * (1 + LIGHT["gradient_x"] * du) * (1 + LIGHT["gradient_y"] * dv)
    gains = np.array([LIGHT["gain_b"], LIGHT["gain_g"], LIGHT["gain_r"]])
    return light[..., None] * gains


LIGHT_FIELD = light_field()


def photograph(flat_images, rng):
    """The flat images over the exposure (averaged: motion blur) -> what the camera delivers."""
    image = np.mean(flat_images, axis=0) * LIGHT_FIELD + rng.normal(0.0, LIGHT["noise"], (HEIGHT, WIDTH, 3))
    return np.clip(np.round(image), 0, 255).astype(np.uint8)


def team_colour(team):
    return client.TEAM_COLOURS[team]


def identity_colour(robot_id):
    return client.IDENTITY_COLOURS[robot_id % len(client.IDENTITY_COLOURS)]


# --------------------------------------------------------------------------
# The mapping
# --------------------------------------------------------------------------

class MappingTest(unittest.TestCase):
    def test_pinhole_recovers_projected_points(self):
        camera = client.Camera(PINHOLE_CAMERA)
        rng = np.random.default_rng(17)
        for z in (SIDE, BALL_RADIUS, 0.0):
            points = np.column_stack((rng.uniform(-0.85, 0.85, 500), rng.uniform(-0.75, 0.75, 500), np.full(500, z)))
            points[:4, :2] = [(-0.85, -0.75), (0.85, -0.75), (0.85, 0.75), (-0.85, 0.75)]  # the corners
            recovered = camera.to_field(project(points), z)
            self.assertLess(np.abs(recovered - points[:, :2]).max(), 1e-6, f"z = {z}")

    def test_pinhole_without_distortion_is_the_plain_ray(self):
        camera = client.Camera(dict(PINHOLE_CAMERA, distortion=[0, 0, 0, 0, 0]))
        # u = fx x / (h - z) + cx, v = -fy y / (h - z) + cy.
        x, y, z = 0.5, -0.3, SIDE
        u, v = FOCAL * x / (CAMERA_HEIGHT - z) + 319.5, -FOCAL * y / (CAMERA_HEIGHT - z) + 239.5
        np.testing.assert_allclose(camera.to_field((u, v), z)[0], (x, y), atol=1e-12)
        # The principal point is the field centre at every height.
        np.testing.assert_allclose(camera.to_field((319.5, 239.5), 0.5)[0], (0, 0), atol=1e-12)

    def test_parallax_of_the_top_face(self):
        # Mapped at the floor's height, a top-face point lands side / (h - side)
        # times farther out: 2.7 cm at 0.7 m. The client maps at z = side.
        camera = client.Camera(PINHOLE_CAMERA)
        pixel = project([(0.7, 0.0, SIDE)])
        floor = camera.to_field(pixel, 0.0)[0]
        self.assertAlmostEqual(floor[0] - 0.7, 0.7 * SIDE / (CAMERA_HEIGHT - SIDE), delta=1e-6)
        self.assertAlmostEqual(camera.to_field(pixel, SIDE)[0][0], 0.7, delta=1e-9)

    def test_orthographic_pixel_centres(self):
        # Pixel column i covers u in [i, i+1): a centroid of pixel indices c is at u = c + 0.5.
        for projection in ({}, {"projection": "orthographic"}):   # no key: an older server
            camera = client.Camera(dict(ORTHOGRAPHIC_CAMERA, **projection))
            x, y = 0.41, -0.27
            u, v = 320 + SCALE * x, 240 - SCALE * y
            for z in (0.0, SIDE):     # the ideal top view sees every height alike
                np.testing.assert_allclose(camera.to_field((u - 0.5, v - 0.5), z)[0], (x, y), atol=1e-12)
            self.assertEqual(camera.delay, 0.0)

    def test_mount_height_or_the_settings_height(self):
        # Without "mount_height", the settings' "height" (m); never the image's "height" (px).
        settings_only = {k: v for k, v in PINHOLE_CAMERA.items() if k != "mount_height"}
        self.assertEqual(client.Camera(settings_only).height, CAMERA_HEIGHT)
        self.assertEqual(client.Camera(dict(PINHOLE_CAMERA, mount_height=1.5)).height, 1.5)

    def test_delay_from_the_settings(self):
        self.assertAlmostEqual(client.Camera(PINHOLE_CAMERA).delay, 0.05 + 0.01 / 2 + 0.010 / 2)
        self.assertEqual(client.Camera(dict(PINHOLE_CAMERA, settings={})).delay, 0.0)

    def test_bad_cameras_are_named(self):
        bad = [
            (None, "no camera object"),
            ({"projection": "fisheye"}, "camera.projection is 'fisheye'"),
            ({"scale": 0, "centre_u": 320, "centre_v": 240}, "camera.scale is 0"),
            ({"scale": 300, "centre_u": "middle", "centre_v": 240}, "camera.centre_u"),
            (dict(PINHOLE_CAMERA, mount_height=-2), "camera.mount_height is -2"),
            ({"projection": "pinhole", "matrix": MATRIX.tolist()}, "camera.mount_height is None"),
            (dict(PINHOLE_CAMERA, matrix=[[1, 0], [0, 1]]), "camera.matrix"),
            (dict(PINHOLE_CAMERA, matrix=[[0, 0, 1], [0, 1, 1], [0, 0, 1]]), "fx, fy > 0"),
            (dict(PINHOLE_CAMERA, matrix="K"), "camera.matrix"),
            (dict(PINHOLE_CAMERA, distortion=[0.1, 0.2]), "camera.distortion"),
            (dict(PINHOLE_CAMERA, settings={"latency": "soon"}), "camera.settings.latency is 'soon'"),
        ]
        for camera, says in bad:
            with self.assertRaises(client.ProtocolError, msg=repr(camera)) as caught:
                client.Camera(camera)
            self.assertIn(says, str(caught.exception))


# --------------------------------------------------------------------------
# Colours under the realistic camera's light
# --------------------------------------------------------------------------

class ColourTest(unittest.TestCase):
    def analyse(self, robots, ball, rng, moving=False):
        background = photograph([draw_scene([], None)], rng)
        if moving:   # 6 instants over the exposure, the bodies moving 1.2 m/s along +x
            frames = [draw_scene([((p[0] + 1.2 * t, p[1], p[2]), tc, ic) for p, tc, ic in robots],
                                 (ball[0] + 1.2 * t, ball[1])) for t in np.linspace(-0.01, 0, 6)]
        else:
            frames = [draw_scene(robots, ball)]
        image = photograph(frames, rng)
        return cv2.cvtColor(image, cv2.COLOR_BGR2HSV), client.foreground_mask(image, background)

    def test_every_robot_and_the_ball_anywhere(self):
        camera = client.Camera(PINHOLE_CAMERA)
        rng = np.random.default_rng(5)
        places = [(-0.6, 0.5), (0.6, 0.5), (0.6, -0.5), (-0.6, -0.5), (-0.2, 0.2), (0.25, -0.15)]
        for moving in (False, True):
            for trial in range(2):
                robots = []
                for k, team in enumerate(("yellow", "blue")):
                    for robot_id in range(6):
                        x, y = places[robot_id]
                        pose = (x + (0.12 if k else -0.12) + 0.03 * trial, y + 0.02 * trial,
                                rng.uniform(-math.pi, math.pi))
                        robots.append((pose, team_colour(team), identity_colour(robot_id), team, robot_id))
                ball = (0.0 + 0.3 * trial, 0.45)
                hsv, foreground = self.analyse([r[:3] for r in robots], ball, rng, moving)
                shift = 1.2 * 0.005 if moving else 0.0   # a blurred blob: the middle of the exposure
                for pose, team_bgr, identity_bgr, team, robot_id in robots:
                    found = client.find_robot(hsv, foreground, camera, team_bgr, identity_bgr, SIDE)
                    what = f"{team} {robot_id} at {pose} (moving {moving})"
                    self.assertIsNotNone(found, what)
                    self.assertLess(math.hypot(found[0] - pose[0] + shift, found[1] - pose[1]), POSITION_TOLERANCE, what)
                    self.assertLess(abs(client.wrap_angle(found[2] - pose[2])), HEADING_TOLERANCE, what)
                found = client.find_ball(hsv, foreground, camera, BALL_RADIUS)
                self.assertIsNotNone(found)
                self.assertLess(math.hypot(found[0] - ball[0] + shift, found[1] - ball[1]), POSITION_TOLERANCE)

    def test_magenta_and_purple_are_told_apart(self):
        # Same hue; purple is half as bright. Only the brightness beside the
        # team patch separates them: each is found as itself, never as the other.
        camera = client.Camera(PINHOLE_CAMERA)
        rng = np.random.default_rng(9)
        magenta, purple = identity_colour(2), identity_colour(5)
        for team in ("yellow", "blue"):
            for place in [(-0.7, 0.55), (0.0, 0.0), (0.7, -0.55)]:   # a dark corner, the centre, a bright corner
                pose = (place[0], place[1], 0.3)
                for drawn, other in ((magenta, purple), (purple, magenta)):
                    hsv, foreground = self.analyse([(pose, team_colour(team), drawn)], None, rng)
                    self.assertIsNotNone(client.find_robot(hsv, foreground, camera, team_colour(team), drawn, SIDE))
                    self.assertIsNone(client.find_robot(hsv, foreground, camera, team_colour(team), other, SIDE),
                                      f"{drawn} on {team} at {place} taken for {other}")

    def test_white_markings_and_an_empty_field_give_nothing(self):
        camera = client.Camera(PINHOLE_CAMERA)
        rng = np.random.default_rng(2)
        hsv, foreground = self.analyse([], None, rng)
        for colour in client.IDENTITY_COLOURS + list(client.TEAM_COLOURS.values()) + [client.BALL_COLOUR]:
            self.assertEqual(client.find_blobs(hsv, foreground, colour), [], colour)
        self.assertIsNone(client.find_ball(hsv, foreground, camera, BALL_RADIUS))


# --------------------------------------------------------------------------
# A mock server with the pinhole camera, and the clients against it
# --------------------------------------------------------------------------

class MockServer:
    """Speaks docs/protocol.md's lockstep mode to one team client: WELCOME with
    the pinhole camera, a background FRAME, then on every CONTROL step 30 ms of
    a unicycle robot driven by the client's VOLTAGES (or frozen), an image
    taken at each 30 ms camera instant and delivered 60 ms later (two steps);
    every 20th is dropped. Images are raw, full frames (kind 1)."""

    FRAME_PERIOD, DELAY_STEPS, DROP_EVERY = 0.03, 2, 20
    SPEED_PER_VOLT, MOTOR_LAG, TRACK = 0.24, 0.08, 0.075   # m/s per V, s, m between the wheels

    def __init__(self, robot, ball, frozen, seed):
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.pose, self.ball, self.frozen = list(robot), ball, frozen
        self.rng = np.random.default_rng(seed)
        self.voltages = (0.0, 0.0)
        self.wheels = [0.0, 0.0]        # right, left wheel speeds, m/s
        self.time, self.frame = 0.0, 0
        self.history = []               # (time, pose) every ms: for the blur
        self.pending = []               # (deliver at step, frame, time, image)
        self.closest = math.inf         # m, robot centre to ball centre
        self.error = None
        self.thread = threading.Thread(target=self.serve, daemon=True)
        self.thread.start()

    def send(self, conn, msg_type, payload):
        conn.sendall(struct.pack(">IB", len(payload) + 1, msg_type) + payload)

    def receive(self, conn):
        def exactly(n):
            data = b""
            while len(data) < n:
                chunk = conn.recv(n - len(data))
                if not chunk:
                    raise EOFError
                data += chunk
            return data
        (length,) = struct.unpack(">I", exactly(4))
        body = exactly(length)
        return body[0], body[1:]

    def send_frame(self, conn, frame, time, kind, image):
        header = struct.pack(">IdBBH", frame, time, kind, client.ENCODING_RAW, 1)
        data = image.tobytes()
        self.send(conn, client.FRAME, header + struct.pack(">HHHHI", 0, 0, WIDTH, HEIGHT, len(data)) + data)

    def image_now(self):
        # Motion blur: the poses at 3 instants over the exposure, 5 ms apart.
        exposure = [pose for t, pose in self.history if t >= self.time - LIGHT["exposure"] - 1e-9][::5]
        flats = [draw_scene([(pose, team_colour("yellow"), identity_colour(0))], self.ball) for pose in exposure]
        return photograph(flats, self.rng)

    def advance(self, duration):
        for _ in range(int(round(duration / 0.001))):
            if not self.frozen:
                for w in range(2):
                    target = self.SPEED_PER_VOLT * self.voltages[w]
                    self.wheels[w] += (target - self.wheels[w]) * 0.001 / self.MOTOR_LAG
                v, omega = sum(self.wheels) / 2, (self.wheels[0] - self.wheels[1]) / self.TRACK
                x, y, theta = self.pose
                self.pose = [x + v * math.cos(theta) * 0.001, y + v * math.sin(theta) * 0.001,
                             client.wrap_angle(theta + omega * 0.001)]
            self.time = round(self.time + 0.001, 9)
            self.history = self.history[-20:] + [(self.time, tuple(self.pose))]
            self.closest = min(self.closest, math.hypot(self.pose[0] - self.ball[0], self.pose[1] - self.ball[1]))

    def serve(self):
        try:
            conn, _ = self.listener.accept()
            with conn:
                msg_type, payload = self.receive(conn)
                assert msg_type == client.HELLO, msg_type
                hello = json.loads(payload)
                welcome = {"protocol": 1, "server": "mock", "client": 1, "role": hello["role"], "mode": "lockstep",
                           "time": 0.0, "frame": 0, "dt": 0.001, "frame_period": self.FRAME_PERIOD,
                           "ball": {"radius": BALL_RADIUS},
                           "camera": dict(PINHOLE_CAMERA, images="full", encoding="raw"),
                           "robots": [{"index": 0, "name": "yellow0", "team": "yellow", "id": 0,
                                       "side": SIDE, "max_voltage": 7.4}]}
                self.send(conn, client.WELCOME, json.dumps(welcome).encode())
                self.history = [(0.0, tuple(self.pose))]
                self.send_frame(conn, 0, 0.0, client.FRAME_KIND_BACKGROUND,
                                photograph([draw_scene([], None)], self.rng))
                steps = 0
                while True:
                    try:
                        msg_type, payload = self.receive(conn)
                    except (EOFError, ConnectionError):
                        return
                    if msg_type == client.VOLTAGES:
                        count, index, right, left = struct.unpack(">BBdd", payload)
                        assert count == 1 and index == 0, (count, index)
                        self.voltages = (right, left)
                    elif msg_type == client.CONTROL:
                        request = json.loads(payload)
                        assert request["command"] == "step", request
                        self.advance(request["duration"])
                        steps += 1
                        self.frame += 1
                        if self.frame % self.DROP_EVERY:
                            self.pending.append((steps + self.DELAY_STEPS, self.frame, self.time, self.image_now()))
                        while self.pending and self.pending[0][0] <= steps:
                            _, frame, time, image = self.pending.pop(0)
                            self.send_frame(conn, frame, time, client.FRAME_KIND_FULL, image)
                        self.send(conn, client.REPLY, json.dumps({"id": request["id"], "ok": True,
                                                                  "command": "step"}).encode())
        except Exception as e:   # reported by the test
            self.error = e
        finally:
            self.listener.close()


ESTIMATE = re.compile(r"robot \((-?[\d.]+), (-?[\d.]+), (-?\d+) deg\) ball \((-?[\d.]+), (-?[\d.]+)\)")
# A --verbose line's time, voltages and whether the client is backing off (Unstick).
COMMAND = re.compile(r"t=([\d.]+): robot .* -> right ([-+][\d.]+) V left ([-+][\d.]+) V( \(backing off\))?")


class ClientsTest(unittest.TestCase):
    def clients(self):
        programs = [("python", ["/usr/bin/python3", PYTHON_CLIENT])]
        if CPP_CLIENT:
            programs.append(("C++", [CPP_CLIENT]))
        return programs

    def run_client(self, command, server, max_time):
        result = subprocess.run(command + ["--port", str(server.port), "--lockstep", "--verbose",
                                           "--max-time", str(max_time)],
                                capture_output=True, text=True, timeout=120)
        server.thread.join(10)
        self.assertIsNone(server.error, f"the mock server failed: {server.error!r}")
        return result

    def test_still_robot_and_ball_are_measured(self):
        if not CPP_CLIENT:
            print("(VSSIM_EXAMPLE_CLIENT not set: the Python client only)", file=sys.stderr)
        for name, command in self.clients():
            for robot, ball in [((-0.62, 0.48, 2.4), (0.66, -0.52)), ((0.55, -0.45, -0.7), (-0.7, 0.5))]:
                server = MockServer(robot, ball, frozen=True, seed=3)
                result = self.run_client(command, server, 0.4)
                self.assertEqual(result.returncode, 1, result.stdout + result.stderr)   # --max-time: not reached
                self.assertIn("pinhole camera, images 60 ms old", result.stdout)
                estimates = [tuple(map(float, m.groups())) for m in ESTIMATE.finditer(result.stdout)]
                self.assertGreaterEqual(len(estimates), 8, result.stdout)
                for x, y, degrees, bx, by in estimates:
                    what = f"{name}: {robot}, {ball}: estimated {x, y, degrees, bx, by}"
                    self.assertLess(math.hypot(x - robot[0], y - robot[1]), POSITION_TOLERANCE, what)
                    self.assertLess(abs(client.wrap_angle(math.radians(degrees) - robot[2])), HEADING_TOLERANCE, what)
                    self.assertLess(math.hypot(bx - ball[0], by - ball[1]), POSITION_TOLERANCE, what)

    def test_the_robot_reaches_the_ball_through_the_late_lens(self):
        reach = SIDE / 2 + BALL_RADIUS
        for name, command in self.clients():
            for robot, ball in [((-0.5, -0.4, 2.0), (0.6, 0.45)), ((0.6, 0.5, 0.0), (-0.65, -0.3))]:
                server = MockServer(robot, ball, frozen=False, seed=4)
                result = self.run_client(command, server, 10)
                what = f"{name} from {robot} to {ball}: {result.stdout[-600:]}{result.stderr}"
                self.assertEqual(result.returncode, 0, what)
                self.assertIn("reached the ball", result.stdout, what)
                self.assertLess(server.closest, reach + 0.02, what)
                # A robot that moves is never taken for a caught one, noise and lens and all.
                self.assertNotIn("backing off", result.stdout, what)

    def test_a_robot_that_cannot_move_backs_off(self):
        """Unstick (examples/README.md, "Control"): a robot that the voltages
        do not move (frozen) is driven in reverse after 0.5 s, for 0.3 s, once
        in 1.2 s; the noise of the realistic camera does not keep it waiting."""
        for name, command in self.clients():
            server = MockServer((-0.62, 0.48, 2.4), (0.66, -0.52), frozen=True, seed=5)
            result = self.run_client(command, server, 1.2)
            what = f"{name}: {result.stdout[-1500:]}{result.stderr}"
            self.assertEqual(result.returncode, 1, what)   # --max-time: not reached
            self.assertIn("back-offs: 1)", result.stderr, what)
            lines = [(float(t), float(r), float(l), bool(b)) for t, r, l, b in COMMAND.findall(result.stdout)]
            self.assertGreaterEqual(len(lines), 30, what)
            first = lines[0][0]
            backing = [line for line in lines if line[3]]
            self.assertTrue(backing, what)
            start = backing[0][0]
            # Triggered on the first frame 0.5 s after the first command (frames every 30 ms, one in 20 dropped).
            self.assertGreaterEqual(start - first, 0.5 - 1e-6, what)
            self.assertLess(start - first, 0.5 + 0.06 + 1e-6, what)
            # For 0.3 s from there (the frame 0.3 s later drives on), and only then.
            for t, right, left, back in lines:
                self.assertEqual(back, 0 <= t - start < 0.3 - 1e-6, f"t={t}: {what}")
            # The command it reverses: the one just before, the robot being still (driving backwards at 5 V).
            _, right0, left0, _ = [line for line in lines if line[0] < start][-1]
            self.assertGreater(abs(right0) + abs(left0), 2.0, what)
            for t, right, left, back in backing:
                self.assertAlmostEqual(right, backing[0][1], delta=1e-9, msg=what)
                self.assertAlmostEqual(left, backing[0][2], delta=1e-9, msg=what)
                self.assertAlmostEqual(right, -right0, delta=0.3, msg=what)
                self.assertAlmostEqual(left, -left0, delta=0.3, msg=what)


if __name__ == "__main__":
    unittest.main()
