#!/usr/bin/python3
"""A small VSSS team client of the usual kind: FIRASim's vision and commands,
VSSReferee's commands and placements.

It reads FIRASim vision (fira_message.sim_to_ref.Environment, multicast
224.0.0.1:10002 by default), drives one robot to the ball and through it
towards the opponent's goal with wheel-speed commands (Packet.cmd, UDP to
127.0.0.1:20011), listens to the referee (VSSRef_Command, multicast
224.5.23.2:10003), holds its robots still unless the referee says GAME_ON,
and answers each KICKOFF, FREE_BALL, PENALTY_KICK and GOAL_KICK with a
VSSRef_Placement of its robots (224.5.23.2:10004).

Against vssim (examples/firasim/README.md):

    build/app/vssim serve kickoff_3v3 --yellow tcp --firasim --vssref
    /usr/bin/python3 examples/firasim/go_to_ball.py --team yellow --duration 60

Frames and units, as FIRASim and VSSReferee use them: the origin at the
centre of the field, x along the field, y up (m); headings counter-clockwise
from +x (rad in vision, DEGREES in a placement). Sides as in FIRASim (and
`vssim serve --firasim`): blue defends the goal at x < 0 and attacks the one
at x > 0, yellow the other way round; --left-team yellow for vssim's own
layout. Wheel speeds in rad/s, positive forward.

Needs Python 3 and python3-protobuf, and the modules protoc generated from
vssim's .proto files (build/python_proto): --proto-dir, or the environment
variable VSSIM_PYTHON_PROTO, or build/python_proto next to this checkout
(installed: /usr/share/vssim/python_proto, found on its own).
"""

import argparse
import math
import os
import select
import socket
import struct
import sys
import time

# --------------------------------------------------------------------------
# The robot and the field (SI units)
# --------------------------------------------------------------------------

WHEEL_RADIUS = 0.025   # m
WHEEL_BASE = 0.065     # m, between the wheels' contact points
MAX_WHEEL_SPEED = 50.0  # rad/s asked at most (1.25 m/s at the rim)
FIELD_LENGTH = 1.50    # m, goal line to goal line (3 vs 3)
GOAL_X = FIELD_LENGTH / 2

# The controller's gains and distances.
K_DISTANCE = 3.0     # forward speed per metre of distance, 1/s
K_HEADING = 8.0      # turn rate per radian of heading error, 1/s
MAX_SPEED = 0.8      # m/s asked at most
BEHIND_BALL = 0.08   # m: where the robot lines up behind the ball
LINED_UP = 0.03      # m: off the ball-goal line by at most this, the robot pushes
GOAL_AIM = 0.12      # m off the goal's centre, away from a keeper (the mouth is 0.40 m wide)
KEEPER_ZONE = (0.20, 0.35)  # m: an opponent this near the goal line (along x) and centre (along y) keeps goal

# VSSRef enums (vssref_common.proto), by number, so that the pure functions
# below need no generated module.
FOUL_NAMES = {0: "FREE_KICK", 1: "PENALTY_KICK", 2: "GOAL_KICK", 3: "FREE_BALL",
              4: "KICKOFF", 5: "STOP", 6: "GAME_ON", 7: "HALT"}
PENALTY_KICK, GOAL_KICK, FREE_BALL, KICKOFF, GAME_ON = 1, 2, 3, 4, 6
BLUE, YELLOW, NONE = 0, 1, 2


# --------------------------------------------------------------------------
# Pure functions: geometry and the control law (tests/firasim_example_test.py)
# --------------------------------------------------------------------------

def wrap(angle):
    """An angle in rad wrapped to (-pi, pi]."""
    a = math.fmod(angle + math.pi, 2 * math.pi)
    if a <= 0:
        a += 2 * math.pi
    return a - math.pi


def attacks_sign(team, left_team="blue"):
    """+1 when `team` attacks the goal at x > 0 (the team on the left,
    `left_team`: blue in FIRASim's layout), -1 otherwise."""
    return 1.0 if team == left_team else -1.0


def opponent_goal(team, left_team="blue"):
    """The centre of the goal `team` attacks, (x, y) in m."""
    return (attacks_sign(team, left_team) * GOAL_X, 0.0)


def wheel_speeds(v, omega, wheel_radius=WHEEL_RADIUS, wheel_base=WHEEL_BASE, limit=MAX_WHEEL_SPEED):
    """Differential drive: body speed v (m/s, forward) and turn rate omega
    (rad/s, counter-clockwise) to (left, right) wheel speeds in rad/s. Both
    scaled down together when one exceeds `limit`, keeping the curvature."""
    right = (v + omega * wheel_base / 2) / wheel_radius
    left = (v - omega * wheel_base / 2) / wheel_radius
    biggest = max(abs(left), abs(right))
    if biggest > limit:
        left, right = left * limit / biggest, right * limit / biggest
    return left, right


def go_to(pose, target, max_speed=MAX_SPEED):
    """(v, omega) that take a robot at pose (x, y, theta) towards target (x, y).
    A target behind the robot is reached driving backwards (a VSSS robot has
    no front): the heading error is then measured from the robot's back."""
    x, y, theta = pose
    dx, dy = target[0] - x, target[1] - y
    distance = math.hypot(dx, dy)
    if distance < 1e-6:
        return 0.0, 0.0
    alpha = wrap(math.atan2(dy, dx) - theta)
    direction = 1.0
    if abs(alpha) > math.pi / 2:
        direction = -1.0
        alpha = wrap(alpha + math.pi)
    v = direction * min(max_speed, K_DISTANCE * distance) * math.cos(alpha)
    omega = K_HEADING * alpha
    return v, omega


def strike_target(robot, ball, goal, behind=BEHIND_BALL):
    """Where a striker at robot (x, y) heads to push the ball at (x, y) into
    the goal at (x, y): to a spot `behind` the ball on the goal-ball line;
    close behind it but off the line, to a point of the line between it and
    the ball (a pursuit that converges onto the line: a robot on wheels
    cannot slide sideways onto it); lined up behind it, through it (the goal
    itself); in front of it, round it."""
    ux, uy = goal[0] - ball[0], goal[1] - ball[1]
    norm = math.hypot(ux, uy) or 1.0
    ux, uy = ux / norm, uy / norm
    rx, ry = robot[0] - ball[0], robot[1] - ball[1]
    along = rx * ux + ry * uy      # < 0: behind the ball
    across = ux * ry - uy * rx     # signed distance from the line, m
    if along < -0.02 and abs(across) < LINED_UP:
        return goal
    if along < -0.02 and abs(across) < 2 * behind:
        k = max(along / 2, -behind)  # m along the line from the ball, < 0
        return (ball[0] + k * ux, ball[1] + k * uy)
    spot = (ball[0] - behind * ux, ball[1] - behind * uy)
    if along < 0:
        return spot
    side = 1.0 if across >= 0 else -1.0  # go round on the side the robot is
    return (spot[0] - side * uy * 0.1, spot[1] + side * ux * 0.1)


def aim_point(team, opponents=(), left_team="blue"):
    """Where in the goal `team` attacks to shoot, (x, y) in m: its centre, or
    GOAL_AIM off it on the far side from an opponent standing in the goal's
    mouth (its keeper), given the opponents' (x, y)."""
    gx, gy = opponent_goal(team, left_team)
    for x, y in opponents:
        if abs(x - gx) < KEEPER_ZONE[0] and abs(y) < KEEPER_ZONE[1]:
            return (gx, -GOAL_AIM if y > 0 else GOAL_AIM)
    return (gx, gy)


def striker_wheels(pose, ball, team, left_team="blue", opponents=()):
    """The whole control law: (left, right) wheel speeds in rad/s for the
    striker at pose (x, y, theta) with the ball at (x, y), shooting past the
    opponents' keeper."""
    target = strike_target(pose[:2], ball, aim_point(team, opponents, left_team))
    return wheel_speeds(*go_to(pose, target))


def placement_for(foul, favoured, quadrant, team, ids=(0, 1, 2), left_team="blue"):
    """Our robots' poses for a stoppage, as [(id, x m, y m, heading DEGREES)]:
    `foul` and `favoured` (VSSRef numbers), the free ball's `quadrant` 1-4.
    Robot ids[0] keeps goal, ids[1] takes the kick, any others wait in our
    half. The referee keeps its own placement when ours breaks its rules."""
    att = attacks_sign(team, left_team)
    own = -att
    ours = favoured == (YELLOW if team == "yellow" else BLUE)
    facing = 0.0 if att > 0 else 180.0
    keeper = (own * 0.70, 0.0, 90.0)
    if foul == KICKOFF:
        kicker = (own * 0.12, 0.0, facing) if ours else (own * 0.30, 0.0, facing)
    elif foul == FREE_BALL:
        bx = (0.375 if quadrant in (1, 4) else -0.375)
        by = (0.25 if quadrant in (1, 2) else -0.25)
        kicker = (bx - att * 0.20, by, facing)
    elif foul == PENALTY_KICK and ours:
        kicker = (att * 0.375 - att * 0.10, 0.0, facing)
    elif foul == PENALTY_KICK:
        kicker = (att * 0.10, 0.30, facing)  # the half away from our goal
    elif foul == GOAL_KICK and ours:
        keeper = (own * 0.71, 0.0, facing)    # behind the ball in our goal area
        kicker = (own * 0.30, 0.30, facing)
    else:
        kicker = (own * 0.30, 0.30, facing)
    others = [(own * 0.35, -0.35, facing), (own * 0.45, 0.45, facing)]
    if foul == FREE_BALL:  # on the other wing, well clear of the ball
        away = -1.0 if quadrant in (1, 2) else 1.0
        others = [(own * 0.35, away * 0.40, facing), (own * 0.10, away * 0.20, facing)]
    elif foul == PENALTY_KICK and not ours:
        others = [(att * 0.10, -0.30, facing), (att * 0.30, 0.45, facing)]
    poses = [keeper, kicker] + others
    return [(robot_id,) + pose for robot_id, pose in zip(ids, poses)]


# --------------------------------------------------------------------------
# The network side
# --------------------------------------------------------------------------

def load_protos(proto_dir):
    """Imports the generated modules (fira_packet_pb2, vssref_*_pb2)."""
    if proto_dir is None:
        proto_dir = os.environ.get("VSSIM_PYTHON_PROTO")
    if proto_dir is None:
        # A checkout's build/python_proto, or the installed package's share/vssim/python_proto.
        here = os.path.dirname(os.path.abspath(__file__))
        candidates = [os.path.join(here, "..", "..", "build", "python_proto"), os.path.join(here, "..", "..", "python_proto")]
        proto_dir = next((c for c in candidates if os.path.isdir(c)), candidates[0])
    sys.path.insert(0, proto_dir)
    try:
        import fira_packet_pb2
        import vssref_command_pb2
        import vssref_placement_pb2
    except ImportError as e:
        sys.exit("go_to_ball.py: cannot import the generated protobuf modules from %s (%s); "
                 "build vssim first or give --proto-dir" % (proto_dir, e))
    return fira_packet_pb2, vssref_command_pb2, vssref_placement_pb2


def is_multicast(address):
    first = int(address.split(".")[0])
    return 224 <= first <= 239


def receiver(address, port, interface):
    """A UDP socket receiving `address`:`port`: a multicast group joined on
    `interface` (an IPv4 address, 127.0.0.1 by default), or a unicast
    address bound."""
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    if is_multicast(address):
        s.bind((address, port))
        membership = struct.pack("4s4s", socket.inet_aton(address), socket.inet_aton(interface))
        s.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, membership)
    else:
        s.bind((address, port))
    s.setblocking(False)
    return s


def sender(interface):
    """A UDP socket for commands and placements; multicast stays on `interface`, TTL 0."""
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 0)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_LOOP, 1)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_IF, socket.inet_aton(interface))
    return s


def parse_args(argv):
    p = argparse.ArgumentParser(
        description="Drive one robot to the ball and towards the opponent's goal over FIRASim's "
                    "interface, obeying VSSReferee's commands (examples/firasim/README.md).")
    p.add_argument("--team", choices=("yellow", "blue"), default="yellow",
                   help="our team; default yellow")
    p.add_argument("--left-team", choices=("blue", "yellow"), default="blue",
                   help="the team that defends the goal at x < 0: blue in FIRASim's layout (the default, "
                        "and vssim serve --firasim's), yellow in vssim's own (--left-team yellow there)")
    p.add_argument("--robot", type=int, default=1, help="id of the robot that goes for the ball; default 1")
    p.add_argument("--duration", type=float, default=30.0,
                   help="seconds of wall time to play, then stop the robots and exit; default 30")
    p.add_argument("--vision-address", default="224.0.0.1", help="vision group or unicast address; default 224.0.0.1")
    p.add_argument("--vision-port", type=int, default=10002, help="default 10002")
    p.add_argument("--command-address", default="127.0.0.1", help="the simulator's command address; default 127.0.0.1")
    p.add_argument("--command-port", type=int, default=20011, help="default 20011")
    p.add_argument("--referee-address", default="224.5.23.2",
                   help="VSSRef_Command group or unicast address; default 224.5.23.2")
    p.add_argument("--referee-port", type=int, default=10003, help="default 10003")
    p.add_argument("--placement-address", default="224.5.23.2",
                   help="where VSSRef_Placement goes; default 224.5.23.2")
    p.add_argument("--placement-port", type=int, default=10004, help="default 10004")
    p.add_argument("--interface", default="127.0.0.1",
                   help="IPv4 address of the interface for multicast; default 127.0.0.1 (loopback)")
    p.add_argument("--ignore-referee", action="store_true",
                   help="play without waiting for GAME_ON (no referee speaks VSSReferee's protocol)")
    p.add_argument("--proto-dir", default=None,
                   help="directory of the generated *_pb2.py modules (default: $VSSIM_PYTHON_PROTO, "
                        "else build/python_proto of this checkout)")
    return p.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    fira, vssref_command, vssref_placement = load_protos(args.proto_dir)
    yellow = args.team == "yellow"
    vision = receiver(args.vision_address, args.vision_port, args.interface)
    referee = receiver(args.referee_address, args.referee_port, args.interface)
    out = sender(args.interface)

    def send_wheels(speeds):
        """speeds: {robot id: (left, right)} in rad/s."""
        packet = fira.Packet()
        for robot_id, (left, right) in speeds.items():
            c = packet.cmd.robot_commands.add()
            c.id, c.yellowteam, c.wheel_left, c.wheel_right = robot_id, yellow, left, right
        out.sendto(packet.SerializeToString(), (args.command_address, args.command_port))

    ids = [0, 1, 2]             # our robots, from vision
    foul = None                 # the referee's last command, or None before any
    answered = None             # the stoppage we answered (foul, team, quadrant, half)
    counts = {"vision": 0, "referee": 0, "placements": 0, "commands": 0}
    end = time.monotonic() + args.duration
    # Zero wheel speeds once at the start: a simulator in lockstep on the
    # commands (vssim serve --firasim-sync) that started before this client
    # waits for a command packet before it sends the next vision.
    send_wheels({robot_id: (0.0, 0.0) for robot_id in ids})
    try:
        while time.monotonic() < end:
            ready, _, _ = select.select([vision, referee], [], [], 0.1)
            if referee in ready:
                data = referee.recv(65536)
                command = vssref_command.VSSRef_Command()
                try:
                    command.ParseFromString(data)
                except Exception:
                    continue
                counts["referee"] += 1
                if foul != command.foul:
                    print("referee: %s %s" % (FOUL_NAMES.get(command.foul, command.foul),
                                              {0: "blue", 1: "yellow", 2: ""}.get(command.teamcolor, "")),
                          flush=True)
                foul = command.foul
                key = (command.foul, command.teamcolor, command.foulQuadrant, command.gameHalf)
                if command.foul in (KICKOFF, FREE_BALL, PENALTY_KICK, GOAL_KICK) and key != answered:
                    answered = key
                    placement = vssref_placement.VSSRef_Placement()
                    placement.world.teamColor = YELLOW if yellow else BLUE
                    for robot_id, x, y, degrees in placement_for(command.foul, command.teamcolor,
                                                                 command.foulQuadrant, args.team, ids,
                                                                 args.left_team):
                        r = placement.world.robots.add()
                        r.robot_id, r.x, r.y, r.orientation = robot_id, x, y, degrees
                    out.sendto(placement.SerializeToString(), (args.placement_address, args.placement_port))
                    counts["placements"] += 1
                elif command.foul == GAME_ON:
                    answered = None
            if vision in ready:
                data = vision.recv(65536)
                env = fira.Environment()
                try:
                    env.ParseFromString(data)
                except Exception:
                    continue
                counts["vision"] += 1
                robots = env.frame.robots_yellow if yellow else env.frame.robots_blue
                opponents = [(r.x, r.y) for r in (env.frame.robots_blue if yellow else env.frame.robots_yellow)]
                ids = sorted(r.robot_id for r in robots) or ids
                speeds = {r.robot_id: (0.0, 0.0) for r in robots}
                playing = args.ignore_referee or foul == GAME_ON
                for r in robots:
                    if playing and r.robot_id == args.robot and env.frame.HasField("ball"):
                        ball = (env.frame.ball.x, env.frame.ball.y)
                        speeds[r.robot_id] = striker_wheels((r.x, r.y, r.orientation), ball, args.team,
                                                            args.left_team, opponents)
                send_wheels(speeds)
                counts["commands"] += 1
    except KeyboardInterrupt:
        pass
    finally:
        send_wheels({robot_id: (0.0, 0.0) for robot_id in ids})
    print("vision packets %(vision)d, referee commands %(referee)d, wheel commands %(commands)d, "
          "placements %(placements)d" % counts)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
