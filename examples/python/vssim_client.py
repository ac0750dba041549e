#!/usr/bin/python3
"""A minimal vssim team client: drive one robot to the ball using only the camera.

It shows the whole protocol of docs/protocol.md from a team's side:

  1. connect over TCP and say HELLO as a team (yellow or blue);
  2. read WELCOME (field, camera mapping, our robots) and the *background* FRAME;
  3. for every following FRAME: paste its patches onto a copy of the
     background, find our robot (team patch + identity patch) and the ball by
     colour (hue), map them to the field through WELCOME's camera (the ideal
     orthographic view, or a pinhole lens with distortion: undistorted, then
     cut with the plane of the robot's top face or the ball's centre), predict
     them forward over the image's delay, and answer with VOLTAGES from a
     simple go-to-point controller;
     in real time, a FRAME with another message already waiting behind it is
     skipped, so that a client slower than the camera acts on the newest image;
  4. in lockstep mode (`vssim serve --lockstep`) also advance simulated time
     ourselves with CONTROL {"command": "step"}.

It stops (0 V, exit 0) once the robot touches the ball (as seen on the
image), exits 1 if --max-time simulated seconds pass (from its first image) first and 2 on any
connection or protocol error.

Needs only Python 3, numpy and OpenCV (Debian: python3-numpy python3-opencv):

    /usr/bin/python3 examples/python/vssim_client.py --team yellow --robot 0
"""

import argparse
import json
import math
import select
import socket
import struct
import sys

import cv2
import numpy as np

# --------------------------------------------------------------------------
# Protocol constants (docs/protocol.md, "Framing")
# --------------------------------------------------------------------------

HELLO, VOLTAGES, CONTROL = 0x01, 0x02, 0x03                        # client -> server
WELCOME, FRAME, STATE, REPLY, ERROR = 0x81, 0x82, 0x83, 0x84, 0x85  # server -> client

FRAME_KIND_PATCHES, FRAME_KIND_FULL, FRAME_KIND_BACKGROUND = 0, 1, 2
ENCODING_RAW, ENCODING_PNG, ENCODING_JPEG = 0, 1, 2

STEP_DURATION = 0.03     # s of simulated time per CONTROL step in --lockstep mode
SILENCE_TIMEOUT = 10.0   # s of wall-clock time without any message before giving up

# --------------------------------------------------------------------------
# Camera colours, (B, G, R) as in OpenCV (docs/protocol.md, "The camera")
# --------------------------------------------------------------------------

TEAM_COLOURS = {"yellow": (0, 255, 255), "blue": (255, 0, 0)}
IDENTITY_COLOURS = [          # by the robot's id within its team, then again from red
    (0, 0, 255),      # 0 red
    (0, 255, 0),      # 1 green
    (255, 0, 255),    # 2 magenta
    (255, 255, 0),    # 3 cyan
    (255, 255, 255),  # 4 white (also the field markings: see colour_mask)
    (128, 0, 128),    # 5 purple: magenta's hue at half its brightness (see find_robot)
]
BALL_COLOUR = (0, 128, 255)   # orange: hue 30 deg, between red (0) and yellow (60)

# Colours are told apart by hue, which neither the light's unevenness
# (vignetting, gradients: they scale B, G and R alike) nor blur (it blends a
# patch with the black body: a darker pixel of the same hue) change; a colour
# cast moves it by a few degrees at most. Hues in OpenCV's units (0..180,
# 2 degrees each): red 0, orange 15, yellow 30, green 60, cyan 90, blue 120,
# magenta and purple 150. Orange lies 15 from red and yellow, so +-7 keeps
# every class apart.
HUE_TOLERANCE = 7
MIN_SATURATION = 128          # of 255: coloured patches are saturated, the white one and greys are not
MIN_VALUE = 50                # of 255: darker pixels (the body, the floor) have no reliable hue
WHITE_MAX_SATURATION = 70     # white: low saturation (a colour cast gives it ~20) ...
WHITE_MIN_VALUE = 100         # ... and bright (a vignetted corner still leaves ~160)
# Magenta and purple share a hue: an identity blob's mean brightness (V) over
# its team patch's must be within this factor of the nominal ratio (1 for
# magenta, 0.5 for purple): the two patches lie side by side, under the same light.
BRIGHTNESS_RATIO_TOLERANCE = 1.4
MIN_BLOB_AREA = 10            # px (after the opening): smaller blobs are edge artefacts or noise
FOREGROUND_THRESHOLD = 40     # a pixel is "new" if it differs this much from the background (noise: a few levels)


class ProtocolError(Exception):
    """Anything that ends the session with exit status 2."""


# --------------------------------------------------------------------------
# The connection: length-prefixed messages over TCP
# --------------------------------------------------------------------------

class Connection:
    """Every message is u32 length (big-endian) + u8 type + payload; length counts type + payload."""

    def __init__(self, host, port):
        try:
            self.sock = socket.create_connection((host, port), timeout=SILENCE_TIMEOUT)
        except OSError as e:
            raise ProtocolError(f"cannot connect to {host}:{port}: {e}") from e
        # Small messages (VOLTAGES, CONTROL) must leave at once, not wait for Nagle.
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.next_id = 1

    def send(self, msg_type, payload):
        try:
            self.sock.sendall(struct.pack(">IB", len(payload) + 1, msg_type) + payload)
        except OSError as e:
            raise ProtocolError(f"connection lost while sending: {e}") from e

    def send_json(self, msg_type, obj):
        self.send(msg_type, json.dumps(obj).encode("utf-8"))

    def send_voltages(self, robot_index, right, left):
        # u8 count, then per robot: u8 index, f64 right, f64 left (big-endian).
        self.send(VOLTAGES, struct.pack(">BBdd", 1, robot_index, right, left))

    def send_control(self, command, **arguments):
        """Sends CONTROL with a fresh id (echoed in the REPLY or ERROR) and returns the id."""
        request_id = self.next_id
        self.next_id += 1
        self.send_json(CONTROL, {"command": command, "id": request_id, **arguments})
        return request_id

    def _receive_exactly(self, n):
        chunks, remaining = [], n
        while remaining > 0:
            try:
                chunk = self.sock.recv(min(remaining, 1 << 20))
            except socket.timeout as e:
                raise ProtocolError(
                    f"no message from the server for {SILENCE_TIMEOUT:.0f} s (is it paused, or in "
                    "lockstep mode while this client runs without --lockstep?)") from e
            except OSError as e:
                raise ProtocolError(f"connection lost: {e}") from e
            if not chunk:
                raise ProtocolError("the server closed the connection")
            chunks.append(chunk)
            remaining -= len(chunk)
        return b"".join(chunks)

    def receive(self):
        """Returns the next message as (type, payload bytes)."""
        (length,) = struct.unpack(">I", self._receive_exactly(4))
        if length < 1:
            raise ProtocolError("malformed message from the server: length 0")
        body = self._receive_exactly(length)
        return body[0], body[1:]

    def more_waiting(self):
        """Whether another message has already arrived (a newer image, usually)."""
        return bool(select.select([self.sock], [], [], 0)[0])

    def close(self):
        self.sock.close()


def parse_json(payload, what):
    try:
        return json.loads(payload.decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as e:
        raise ProtocolError(f"malformed {what} JSON from the server: {e}") from e


def describe_error(error):
    return f"server ERROR {error.get('error')}: {error.get('message')}"


# --------------------------------------------------------------------------
# FRAME: header, patches, decoding
# --------------------------------------------------------------------------

FRAME_HEADER = struct.Struct(">IdBBH")   # frame, time, kind, encoding, count: 16 bytes
PATCH_HEADER = struct.Struct(">HHHHI")   # x, y, w, h, bytes: 12 bytes


def decode_patch(data, encoding, w, h):
    """One patch's bytes -> an h x w x 3 BGR image."""
    if encoding == ENCODING_RAW:          # rows top to bottom, 3 bytes B, G, R per pixel
        if len(data) != w * h * 3:
            raise ProtocolError(f"raw patch of {w}x{h} has {len(data)} bytes")
        return np.frombuffer(data, np.uint8).reshape(h, w, 3)
    if encoding in (ENCODING_PNG, ENCODING_JPEG):
        image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
        if image is None or image.shape[:2] != (h, w):
            raise ProtocolError(f"cannot decode a {w}x{h} patch")
        return image
    raise ProtocolError(f"unknown image encoding {encoding}")


def parse_frame(payload):
    """FRAME payload -> (frame, time, kind, [(x, y, image), ...]), skipping empty patches."""
    if len(payload) < FRAME_HEADER.size:
        raise ProtocolError("truncated FRAME")
    frame, time, kind, encoding, count = FRAME_HEADER.unpack_from(payload, 0)
    offset, patches = FRAME_HEADER.size, []
    for _ in range(count):
        if offset + PATCH_HEADER.size > len(payload):
            raise ProtocolError("truncated FRAME patch header")
        x, y, w, h, size = PATCH_HEADER.unpack_from(payload, offset)
        offset += PATCH_HEADER.size
        data = payload[offset:offset + size]
        if len(data) != size:
            raise ProtocolError("truncated FRAME patch data")
        offset += size
        if w > 0 and h > 0:               # w = h = 0: that body is outside the image
            patches.append((x, y, decode_patch(data, encoding, w, h)))
    return frame, time, kind, patches


def paste(image, x, y, patch):
    h, w = patch.shape[:2]
    if y + h > image.shape[0] or x + w > image.shape[1]:
        raise ProtocolError(f"patch {w}x{h} at ({x}, {y}) lies outside the image")
    image[y:y + h, x:x + w] = patch


# --------------------------------------------------------------------------
# Vision: colour blobs -> robot pose and ball position
# --------------------------------------------------------------------------

# cv2.undistortPointsIter's stopping rule: to 1e-12 in normalised coordinates
# (about 2e-12 m on the field), instead of cv2.undistortPoints' 5 iterations
# (about 0.2 mm off in a corner with the realistic lens).
UNDISTORT_CRITERIA = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 50, 1e-12)


def camera_number(camera, key, positive=False, where="camera"):
    """WELCOME's <where>.<key> as a float, or a ProtocolError that names it."""
    value = camera.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or (positive and value <= 0):
        raise ProtocolError(f"WELCOME's {where}.{key} is {value!r}: expected a finite"
                            f"{' positive' if positive else ''} number")
    return float(value)


class Camera:
    """Pixel -> field, from WELCOME's "camera" (docs/protocol.md, "The camera").

    "orthographic" (also a camera without "projection", from older servers):
    the ideal top view, u = centre_u + scale x, v = centre_v - scale y, in
    continuous coordinates where pixel column i covers u in [i, i+1) (its
    centre at u = i + 0.5). Every height looks the same.

    "pinhole": a camera "mount_height" m above the field centre looking straight
    down, u along +x and v along -y, through a lens with OpenCV's distortion
    model; pixel centres at integer coordinates (OpenCV's convention, so a
    centroid of pixel indices goes in as it is). A pixel is undistorted to
    normalised image coordinates (x_n, y_n) = ((u - cx) / fx, (v - cy) / fy)
    before distortion (cv2.undistortPoints with WELCOME's "matrix" and
    "distortion"), then its viewing ray is cut with the horizontal plane z of
    what was seen:  x = x_n (height - z),  y = -y_n (height - z).
    The plane matters (parallax): a robot's patches lie on its top face, z =
    side, which at 0.7 m from the centre appears 2.7 cm farther out than the
    floor point under it would; the ball is seen around its centre, z = radius.

    `delay` is how old an image is when it arrives: the camera's latency, half
    its jitter and half its exposure (a blurred blob is where the body was in
    the middle of the exposure), from WELCOME's "camera"."settings"; 0 without them."""

    def __init__(self, welcome_camera):
        if not isinstance(welcome_camera, dict):
            raise ProtocolError("WELCOME has no camera object")
        self.projection = welcome_camera.get("projection", "orthographic")
        if self.projection == "orthographic":
            self.scale = camera_number(welcome_camera, "scale", positive=True)
            self.centre_u = camera_number(welcome_camera, "centre_u")
            self.centre_v = camera_number(welcome_camera, "centre_v")
        elif self.projection == "pinhole":
            # The camera's height above the field, m: "mount_height" ("height"
            # is the image's, px), else the camera settings' "height".
            settings = welcome_camera.get("settings")
            if "mount_height" in welcome_camera or not isinstance(settings, dict) or "height" not in settings:
                self.height = camera_number(welcome_camera, "mount_height", positive=True)
            else:
                self.height = camera_number(settings, "height", positive=True, where="camera.settings")
            try:
                self.matrix = np.array(welcome_camera.get("matrix"), dtype=np.float64)
                self.distortion = np.array(welcome_camera.get("distortion", [0.0] * 5), dtype=np.float64)
            except (TypeError, ValueError) as e:
                raise ProtocolError(f"WELCOME's camera.matrix or camera.distortion is not numbers: {e}") from e
            if (self.matrix.shape != (3, 3) or not np.all(np.isfinite(self.matrix))
                    or self.matrix[0, 0] <= 0 or self.matrix[1, 1] <= 0
                    or not np.allclose(self.matrix[2], [0.0, 0.0, 1.0])):
                raise ProtocolError(f"WELCOME's camera.matrix is {welcome_camera.get('matrix')!r}: expected "
                                    "[[fx, 0, cx], [0, fy, cy], [0, 0, 1]] with fx, fy > 0")
            if self.distortion.ndim != 1 or self.distortion.size not in (4, 5) \
                    or not np.all(np.isfinite(self.distortion)):
                raise ProtocolError(f"WELCOME's camera.distortion is {welcome_camera.get('distortion')!r}: "
                                    "expected [k1, k2, p1, p2, k3]")
        else:
            raise ProtocolError(f"WELCOME's camera.projection is {self.projection!r}: "
                                "expected \"orthographic\" or \"pinhole\"")
        settings = welcome_camera.get("settings") or {}
        if not isinstance(settings, dict):
            raise ProtocolError("WELCOME's camera.settings is not an object")
        self.delay = sum(weight * camera_number(settings, key, where="camera.settings") for key, weight in
                         (("latency", 1.0), ("jitter", 0.5), ("exposure", 0.5)) if key in settings)

    def to_field(self, pixels, z):
        """Pixel coordinates (column, row) in OpenCV's convention (pixel centres
        at integers: a centroid of pixel indices), an N x 2 array or one pair,
        of things at height z m -> their field (x, y) in m, N x 2."""
        pixels = np.asarray(pixels, dtype=np.float64).reshape(-1, 2)
        if self.projection == "orthographic":
            u, v = pixels[:, 0] + 0.5, pixels[:, 1] + 0.5
            return np.column_stack(((u - self.centre_u) / self.scale, (self.centre_v - v) / self.scale))
        if not z < self.height:
            raise ValueError(f"a point at z = {z} m is not below the camera ({self.height} m)")
        normalised = cv2.undistortPointsIter(pixels.reshape(-1, 1, 2), self.matrix, self.distortion,
                                             None, None, UNDISTORT_CRITERIA).reshape(-1, 2)
        depth = self.height - z
        return np.column_stack((normalised[:, 0] * depth, -normalised[:, 1] * depth))


def hsv_of(bgr):
    """A colour's nominal (hue 0..180, saturation, value) in OpenCV's HSV."""
    return [int(c) for c in cv2.cvtColor(np.uint8([[bgr]]), cv2.COLOR_BGR2HSV)[0, 0]]


def colour_class(hsv, bgr, min_value):
    """Where the HSV image has colour bgr's class: its hue (within the
    tolerance, around the circle: 180 = 0), saturated, and at least min_value
    bright; for white, little saturation."""
    hue, saturation, _ = hsv_of(bgr)
    h, s, v = cv2.split(hsv)
    if saturation == 0:   # white: any hue
        return (s <= WHITE_MAX_SATURATION) & (v >= min_value)
    difference = np.abs(h.astype(np.int16) - hue)
    difference = np.minimum(difference, 180 - difference)
    return (difference <= HUE_TOLERANCE) & (s >= MIN_SATURATION) & (v >= min_value)


def find_blobs(hsv, foreground, bgr):
    """Blobs of colour bgr's class as (centroid (column, row), area px, mean value V), largest first.

    The class's bright pixels (V >= MIN_VALUE; white: WHITE_MIN_VALUE) among
    the foreground ones (those that differ from the background: that keeps
    the white field markings and the grey walls out of the white class); a
    3x3 opening removes what is one or two pixels wide (anti-aliased fringes,
    isolated noisy pixels, the markings' crossings); blobs still under
    MIN_BLOB_AREA pixels are dropped."""
    white = hsv_of(bgr)[1] == 0
    bright = colour_class(hsv, bgr, WHITE_MIN_VALUE if white else MIN_VALUE)
    mask = np.where(bright, np.uint8(255), np.uint8(0)) & foreground
    mask = cv2.morphologyEx(mask, cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
    count, labels, stats, centroids = cv2.connectedComponentsWithStats(mask)
    areas = stats[:, cv2.CC_STAT_AREA]
    values = np.bincount(labels.ravel(), weights=hsv[..., 2].ravel(), minlength=count) / np.maximum(areas, 1)
    blobs = [(centroids[i], int(areas[i]), float(values[i])) for i in range(1, count) if areas[i] >= MIN_BLOB_AREA]
    return sorted(blobs, key=lambda blob: -blob[1])


def foreground_mask(image, background):
    difference = cv2.absdiff(image, background).max(axis=2)
    return np.where(difference > FOREGROUND_THRESHOLD, 255, 0).astype(np.uint8)


def find_robot(hsv, foreground, camera, team_bgr, identity_bgr, side):
    """Our robot's (x, y, theta) in the field frame, or None if not seen.

    The patches lie on the robot's top face: their centroids are mapped to the
    field at z = side. Each identity blob is paired with the nearest team blob:
    on the robot their centres are 0.5 side apart, so pairs farther than 0.75
    side are rejected. (The other team's robot with the same id has the same
    identity colour, but a team patch of the other colour.) Identity colours
    of the same hue (magenta, purple) differ in brightness: the identity
    blob's mean V over the team blob's must be near the nominal ratio."""
    team_blobs = find_blobs(hsv, foreground, team_bgr)
    identity_blobs = find_blobs(hsv, foreground, identity_bgr)
    if not team_blobs or not identity_blobs:
        return None
    team_xy = camera.to_field([blob[0] for blob in team_blobs], side)
    identity_xy = camera.to_field([blob[0] for blob in identity_blobs], side)
    expected_ratio = hsv_of(identity_bgr)[2] / hsv_of(team_bgr)[2]
    best = None
    for i, (_, _, identity_value) in enumerate(identity_blobs):
        for t, (_, _, team_value) in enumerate(team_blobs):
            if abs(math.log(identity_value / team_value / expected_ratio)) > math.log(BRIGHTNESS_RATIO_TOLERANCE):
                continue
            distance = float(np.linalg.norm(identity_xy[i] - team_xy[t]))
            if distance <= 0.75 * side and (best is None or distance < best[0]):
                best = (distance, team_xy[t], identity_xy[i])
    if best is None:
        return None
    _, (tx, ty), (ix, iy) = best
    # Centre: midpoint of the two patches; heading: from team patch to identity patch.
    return (tx + ix) / 2, (ty + iy) / 2, math.atan2(iy - ty, ix - tx)


def find_ball(hsv, foreground, camera, radius):
    blobs = find_blobs(hsv, foreground, BALL_COLOUR)
    if not blobs:
        return None
    x, y = camera.to_field(blobs[0][0], radius)[0]   # the largest orange blob, seen around the ball's centre
    return float(x), float(y)


class Predictor:
    """Where a body is now, from an image `delay` s old: constant velocity.

    An image shows the world as it was `delay` s ago (Camera.delay: 55 to 60
    ms with the realistic camera), while the voltages we send act from now
    on; steering from the image as it is would chase where the robot was (at
    1.2 m/s, 6.6 cm back) and overshoot every turn. So each body is moved
    forward by its velocity times the delay. The velocity is the change
    between consecutive images over their time difference (frame times:
    skipped or dropped frames are accounted for), smoothed over about two
    images; a gap longer than MAX_GAP starts again from rest. With the ideal
    camera, delay 0: the image as it is."""

    SMOOTHING = 0.5   # weight of the newest velocity
    MAX_GAP = 0.2     # s

    def __init__(self, delay, angular):
        self.delay, self.angular = delay, angular   # angular: the last coordinate is an angle
        self.last = self.last_time = None
        self.velocity = None

    def update(self, time, observed):
        observed = np.asarray(observed, dtype=np.float64)
        if self.delay <= 0:
            return tuple(float(c) for c in observed)
        velocity = np.zeros_like(observed)
        if self.last is not None and 0 < time - self.last_time <= self.MAX_GAP:
            change = observed - self.last
            if self.angular:
                change[-1] = wrap_angle(change[-1])
            velocity = change / (time - self.last_time)
            if self.velocity is not None:
                velocity = self.SMOOTHING * velocity + (1 - self.SMOOTHING) * self.velocity
        self.last, self.last_time, self.velocity = observed, time, velocity
        predicted = observed + velocity * self.delay
        if self.angular:
            predicted[-1] = wrap_angle(predicted[-1])
        return tuple(float(c) for c in predicted)


# --------------------------------------------------------------------------
# Control: a go-to-point controller for a differential-drive robot
# --------------------------------------------------------------------------

TURN_GAIN = 1.2        # V of differential voltage per rad of heading error
DISTANCE_GAIN = 20.0   # V of common voltage per m of distance
CRUISE_VOLTAGE = 5.0   # V: the common voltage never exceeds this (~1.2 m/s)


def wrap_angle(a):
    """An angle in (-pi, pi]."""
    return math.atan2(math.sin(a), math.cos(a))


class GoToPoint:
    """Heading error -> differential voltage, distance -> common voltage.

    VSSS robots are symmetric, so when the target is behind the robot it
    simply drives backwards (heading + pi) instead of turning around. A little
    hysteresis keeps it from hesitating between the two when the target is
    nearly sideways."""

    def __init__(self, max_voltage):
        self.max_voltage = max_voltage
        self.backwards = False

    def command(self, robot, target):
        x, y, theta = robot
        dx, dy = target[0] - x, target[1] - y
        error = wrap_angle(math.atan2(dy, dx) - theta)        # heading error driving forwards
        switch_at = math.pi / 2 + (-0.3 if self.backwards else 0.3)
        self.backwards = abs(error) > switch_at
        if self.backwards:
            error = wrap_angle(error - math.pi)               # heading error driving backwards
        direction = -1.0 if self.backwards else 1.0

        # Slow down while the robot does not face the target (|error| <= ~pi/2 here).
        common = min(DISTANCE_GAIN * math.hypot(dx, dy), CRUISE_VOLTAGE) * max(math.cos(error), 0.0)
        differential = TURN_GAIN * error                      # > 0: turn left (counter-clockwise)

        # Stay within +-max_voltage on both wheels, giving priority to turning.
        differential = max(-self.max_voltage, min(self.max_voltage, differential))
        common = min(common, self.max_voltage - abs(differential))
        common *= direction
        return common + differential, common - differential   # (right, left)


# --------------------------------------------------------------------------
# Getting unstuck
# --------------------------------------------------------------------------

STUCK_TIME = 0.5        # s of simulated time (frame times)
STUCK_DISTANCE = 0.01   # m: a still robot's estimates stay within 3 mm
STUCK_TURN = 0.2        # rad: and within 4 degrees (0.07 rad) of its heading
BACK_OFF_TIME = 0.3     # s
DRIVEN_VOLTAGE = 2.0    # V: |right| + |left| at least this asks for motion
TIME_SLACK = 1e-6       # s: frame times carry rounding; a frame at a limit counts as there


class Unstick:
    """Backs a robot off when it is caught.

    A robot caught on a goal post or in a corner (the post in front of one
    face and the robot's own corner inside the goal mouth, say) can neither
    drive on (its wheels do not slip sideways) nor turn there: the go-to-point
    law keeps pushing it in. When the commands have asked for motion for
    STUCK_TIME while the robot, as the images show it, moved less than
    STUCK_DISTANCE and turned less than STUCK_TURN, it drives its last command
    in reverse for BACK_OFF_TIME, then carries on."""

    def __init__(self):
        self.anchor = None              # (x, y, theta), m and rad: where the robot was when it last moved
        self.anchor_time = 0.0          # s (frame time): and when
        self.last_time = -1.0           # s: the last frame time seen (a `reset` starts time again)
        self.back_off_start = None      # s (frame time): when the last back-off began
        self.back_off = (0.0, 0.0)      # V (right, left)
        self.back_offs = 0              # how many so far

    def backing_off(self, time):
        return (self.back_off_start is not None and time >= self.back_off_start
                and time - self.back_off_start < BACK_OFF_TIME - TIME_SLACK)

    def forget(self):
        """The robot not seen in this frame: its motion is not known, so the wait starts again."""
        self.anchor = None

    def voltages(self, time, pose, command):
        """The voltages (right, left) to send at `time` for `command`, the robot seen at `pose`."""
        if time < self.last_time:       # time went back (a reset): what came before is gone
            count = self.back_offs
            self.__init__()
            self.back_offs = count
        self.last_time = time
        if self.backing_off(time):
            return self.back_off
        driven = abs(command[0]) + abs(command[1]) >= DRIVEN_VOLTAGE
        moved = self.anchor is not None and (
            math.hypot(pose[0] - self.anchor[0], pose[1] - self.anchor[1]) > STUCK_DISTANCE
            or abs(wrap_angle(pose[2] - self.anchor[2])) > STUCK_TURN)
        if self.anchor is None or moved or not driven:
            self.anchor, self.anchor_time = pose, time
            return command
        if time - self.anchor_time < STUCK_TIME - TIME_SLACK:
            return command
        self.back_off = (-command[0], -command[1])
        self.back_off_start = time
        self.back_offs += 1
        self.anchor = None              # measured again from after the back-off
        return self.back_off


# --------------------------------------------------------------------------
# The session
# --------------------------------------------------------------------------

VISION_HELP = """\
vision (examples/README.md):
  colours   pixels that differ from the background by > 40 are classed by hue (OpenCV HSV,
            +-7 of red 0, orange 15, yellow 30, green 60, cyan 90, blue 120, magenta/purple 150;
            saturation >= 128, V >= 50; white: saturation <= 70, V >= 100), so uneven light,
            the colour cast and blur leave them alone; purple is magenta at half the team
            patch's brightness. Masks are opened 3x3, blobs under 10 px dropped.
  field     orthographic camera: x = (c + 0.5 - centre_u) / scale, y = (centre_v - r - 0.5) / scale
            for a centroid (c, r) of pixel indices. Pinhole camera: (c, r) undistorted with
            WELCOME's matrix and distortion (cv2.undistortPoints) to (x_n, y_n), then
            x = x_n (mount_height - z), y = -y_n (mount_height - z) at the height z seen:
            z = side for the patches on the robot's top face, z = radius for the ball.
  latency   robot and ball are moved forward by their velocity (from the last images)
            times the delay: --delay, or latency + jitter/2 + exposure/2 from the settings.
control (examples/README.md):
  unstuck   a robot that has not moved 1 cm or turned 0.2 rad in the images for 0.5 s while
            driven (|right| + |left| >= 2 V; caught on a goal post or in a corner) drives its
            last command in reverse for 0.3 s.
exit status: 0 ball reached, 1 --max-time passed, 2 connection, protocol or option error."""


def parse_arguments():
    parser = argparse.ArgumentParser(
        description="vssim example team client: drives one robot to the ball using only the camera images.",
        epilog=VISION_HELP, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--host", default="127.0.0.1", help="server address (default 127.0.0.1)")
    parser.add_argument("--port", type=int, default=10030, help="server port (default 10030)")
    parser.add_argument("--team", choices=["yellow", "blue"], default="yellow", help="team (default yellow)")
    parser.add_argument("--robot", type=int, default=0, metavar="ID",
                        help="the robot's id within the team, i.e. its identity colour (default 0)")
    parser.add_argument("--encoding", choices=["png", "raw", "jpeg"], default="png",
                        help="image encoding (default png)")
    parser.add_argument("--lockstep", action="store_true",
                        help="step simulated time ourselves, 0.03 s per decision (for `vssim serve --lockstep`)")
    parser.add_argument("--max-time", type=float, default=20.0, metavar="S",
                        help="give up (exit 1) after S simulated seconds (default 20)")
    parser.add_argument("--delay", type=float, default=None, metavar="S",
                        help="how old an image is on arrival, s: the robot and the ball are predicted S s "
                             "forward (default: from WELCOME's camera settings, latency + jitter/2 + "
                             "exposure/2; 0 for the ideal camera)")
    parser.add_argument("--verbose", action="store_true", help="print the estimates at every frame")
    args = parser.parse_args()
    if args.delay is not None and not (math.isfinite(args.delay) and 0 <= args.delay <= 1):
        parser.error(f"--delay {args.delay:g}: expected 0 to 1 s")
    if args.robot < 0:
        parser.error(f"--robot {args.robot}: expected an id >= 0")
    if not (math.isfinite(args.max_time) and args.max_time > 0):
        parser.error(f"--max-time {args.max_time:g}: expected a positive number of seconds")
    return args


def wait_for_welcome(conn):
    while True:
        msg_type, payload = conn.receive()
        if msg_type == WELCOME:
            return parse_json(payload, "WELCOME")
        if msg_type == ERROR:   # e.g. role_taken: the other team's client already drives it
            raise ProtocolError(describe_error(parse_json(payload, "ERROR")))
        # Anything else before WELCOME is unexpected but harmless: skip it.


def our_robot(welcome, team, robot_id):
    for robot in welcome["robots"]:
        if robot["team"] == team and robot["id"] == robot_id:
            return robot
    ids = [r["id"] for r in welcome["robots"] if r["team"] == team]
    raise ProtocolError(f"the scene has no {team} robot with id {robot_id} ({team} ids: {ids})")


def run(args):
    conn = Connection(args.host, args.port)
    conn.send_json(HELLO, {"protocol": 1, "role": args.team, "name": "vssim example client (Python)",
                           "images": "patches", "encoding": args.encoding})
    welcome = wait_for_welcome(conn)

    camera = Camera(welcome.get("camera"))
    delay = camera.delay if args.delay is None else args.delay
    robot = our_robot(welcome, args.team, args.robot)
    index, side, max_voltage = robot["index"], float(robot["side"]), float(robot["max_voltage"])
    ball_radius = float(welcome["ball"]["radius"])
    team_bgr = TEAM_COLOURS[args.team]
    identity_bgr = IDENTITY_COLOURS[args.robot % len(IDENTITY_COLOURS)]
    reach_distance = side / 2 + ball_radius + 0.015
    controller = GoToPoint(max_voltage)
    unstick = Unstick()
    robot_predictor, ball_predictor = Predictor(delay, angular=True), Predictor(delay, angular=False)
    print(f"connected to {welcome.get('server')} ({welcome.get('mode')} mode) as {args.team}: "
          f"driving {robot['name']} (index {index}) to the ball; {camera.projection} camera"
          + (f", images {delay * 1000:.0f} ms old" if delay > 0 else ""))
    if welcome.get("mode") == "lockstep" and not args.lockstep:
        print("note: the server is in lockstep mode: time only advances when a client steps it "
              "(use --lockstep to do it from this client)", file=sys.stderr)

    background = None
    step_id = None        # id of our CONTROL step awaiting its REPLY (lockstep only)
    last_estimate = "nothing seen yet"
    start_time = None  # s, simulated time of the first image
    skipped = 0        # images passed over because a newer one had already arrived

    def stop():
        conn.send_voltages(index, 0.0, 0.0)

    while True:
        msg_type, payload = conn.receive()

        if msg_type == ERROR:
            error = parse_json(payload, "ERROR")
            if error.get("fatal") or (step_id is not None and error.get("id") == step_id):
                hint = " (step needs `vssim serve --lockstep`, or a paused server)" if error.get("id") == step_id else ""
                raise ProtocolError(describe_error(error) + hint)
            print(f"warning: {describe_error(error)}", file=sys.stderr)   # not fatal: carry on
            continue
        if msg_type == REPLY:
            reply = parse_json(payload, "REPLY")
            if args.lockstep and step_id is not None and reply.get("id") == step_id:
                # The FRAME of that step came before this REPLY and has been answered
                # with VOLTAGES already: advance time again.
                step_id = conn.send_control("step", duration=STEP_DURATION)
            continue              # a REPLY we did not ask for: nothing to do
        if msg_type != FRAME:
            continue              # STATE (we did not ask for it), WELCOME again, unknown types: skip

        # In real time, act on the newest image: when more has already arrived
        # behind this FRAME, this client is behind the camera, and a newer
        # image is on its way (lockstep: every step's FRAME counts).
        if (not args.lockstep and len(payload) > 12 and payload[12] != FRAME_KIND_BACKGROUND
                and conn.more_waiting()):
            skipped += 1
            continue

        frame, time, kind, patches = parse_frame(payload)
        if kind == FRAME_KIND_BACKGROUND:
            if len(patches) != 1:
                raise ProtocolError("background FRAME without exactly one patch")
            background = patches[0][2].copy()
            if args.lockstep and step_id is None:
                step_id = conn.send_control("step", duration=STEP_DURATION)   # get the first image
            continue
        if background is None:
            raise ProtocolError("FRAME before the background FRAME")

        # Rebuild the full camera image: a fresh copy of the background, patches pasted in order.
        image = background.copy()
        for x, y, patch in patches:
            paste(image, x, y, patch)

        foreground = foreground_mask(image, background)
        hsv = cv2.cvtColor(image, cv2.COLOR_BGR2HSV)
        pose = find_robot(hsv, foreground, camera, team_bgr, identity_bgr, side)
        seen = pose               # as the image shows it (Unstick: no prediction's noise)
        ball = find_ball(hsv, foreground, camera, ball_radius)
        # Where they are now, the image being `delay` s old (Predictor).
        if pose is not None:
            pose = robot_predictor.update(time, pose)
        if ball is not None:
            ball = ball_predictor.update(time, ball)

        if pose is None or ball is None:
            right = left = 0.0    # lost sight of something: wait for a better image
            unstick.forget()
            last_estimate = f"robot {'not ' if pose is None else ''}seen, ball {'not ' if ball is None else ''}seen"
            if args.verbose:
                print(f"frame {frame} t={time:.3f}: {last_estimate}")
        else:
            distance = math.hypot(ball[0] - pose[0], ball[1] - pose[1])
            last_estimate = (f"robot ({pose[0]:.3f}, {pose[1]:.3f}) ball ({ball[0]:.3f}, {ball[1]:.3f})")
            if distance <= reach_distance:
                stop()
                notes = [f"{skipped} older images skipped"] if skipped else []
                notes += [f"back-offs: {unstick.back_offs}"] if unstick.back_offs else []
                print(f"reached the ball at t={time:.2f} s (frame {frame}): {last_estimate}"
                      + (f" ({', '.join(notes)})" if notes else ""))
                return 0
            right, left = unstick.voltages(time, seen, controller.command(pose, ball))
            if args.verbose:
                print(f"frame {frame} t={time:.3f}: robot ({pose[0]:.3f}, {pose[1]:.3f}, "
                      f"{math.degrees(pose[2]):.0f} deg) ball ({ball[0]:.3f}, {ball[1]:.3f}) "
                      f"distance {distance:.3f} m -> right {right:+.2f} V left {left:+.2f} V"
                      + (" (backing off)" if unstick.backing_off(time) else ""))

        if start_time is None:
            start_time = time  # --max-time counts from the first image: the server may have run a while
        if time - start_time >= args.max_time:
            stop()
            print(f"did not reach the ball within {args.max_time:g} s of simulated time from the first image "
                  f"(t={time:.2f} s, frame {frame}; last estimate: {last_estimate}; back-offs: {unstick.back_offs})",
                  file=sys.stderr)
            return 1
        conn.send_voltages(index, right, left)


def main():
    args = parse_arguments()
    try:
        return run(args)
    except ProtocolError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except (KeyError, TypeError, ValueError) as e:   # a WELCOME without the fields we need
        print(f"error: unexpected WELCOME from the server ({type(e).__name__}: {e})", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 2


if __name__ == "__main__":
    sys.exit(main())
