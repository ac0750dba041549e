#!/usr/bin/python3
"""Writes the fuzz targets' seed corpora (fuzz/corpus/NAME/), a few valid
inputs each, so that the fuzzers start from inside the formats.

    fuzz/make_corpus.py PROTO_PYTHON_DIR   # BUILD/python_proto (protoc's --python_out)

The scene seeds are copies of resources/scenes/*.json; the rest are built
here from docs/protocol.md's messages and the league's protobuf messages.
"""
import json
import pathlib
import shutil
import struct
import sys

root = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, sys.argv[1] if len(sys.argv) > 1 else str(root.parent / "build" / "python_proto"))
import fira_packet_pb2  # noqa: E402
import vssref_placement_pb2  # noqa: E402


def write(name, files):
    d = root / "corpus" / name
    shutil.rmtree(d, ignore_errors=True)
    d.mkdir(parents=True)
    for file_name, data in files.items():
        (d / file_name).write_bytes(data)


write("fuzz_scene", {p.name: p.read_bytes()
                     for p in sorted((root.parent / "resources" / "scenes").glob("*.json"))})


def message(kind, payload):
    return struct.pack(">IB", len(payload) + 1, kind) + payload


def js(kind, obj):
    return message(kind, json.dumps(obj, separators=(",", ":")).encode())


def entries(kind, items):
    return message(kind, struct.pack(">B", len(items)) + b"".join(struct.pack(">Bdd", r, a, b) for r, a, b in items))


hello = js(1, {"protocol": 1, "role": "yellow", "name": "demo", "images": "patches", "encoding": "png",
                "state": True, "camera": {"latency": 0.05, "jitter": 0.01, "drop": 0.01}})
frame = message(0x82, struct.pack(">IdBBH", 1, 0.03, 0, 1, 1) + struct.pack(">HHHHI", 10, 20, 2, 2, 4) + b"\x89PNG")
# Each seed: a byte choosing the pieces' size (docs: fuzz_client_messages.cpp), then the stream.
write("fuzz_client_messages", {
    "hello_voltages_step": b"\x10" + hello + entries(2, [(0, 3.0, -1.5)]) + js(3, {"command": "step", "duration": 0.03, "id": 3}),
    "placement": b"\xff" + js(1, {"protocol": 1, "role": "blue"}) +
                 js(4, {"id": 1, "robots": [{"robot": 4, "x": 0.4, "y": 0.3, "theta": 0.0}]}),
    "wheel_speeds": b"\x00" + js(1, {"protocol": 1, "role": "yellow", "images": "full", "encoding": "jpeg",
                                       "jpeg_quality": 80}) + entries(5, [(0, 10.0, 12.5), (1, -3.0, 3.0)]),
    "controls": b"\x07" + b"".join(js(3, c) for c in (
        {"command": "pause", "id": 1}, {"command": "resume", "id": 2}, {"command": "stats", "id": 3},
        {"command": "reset", "id": 4}, {"command": "game_on", "id": 5}, {"command": "halt", "id": 6},
        {"command": "call", "call": "free_ball", "team": "yellow", "quadrant": 2, "id": 7},
        {"command": "place_robot", "robot": 0, "x": -0.2, "y": 0.1, "theta": 1.0, "id": 8},
        {"command": "place_ball", "x": 0.1, "y": 0.0, "vx": 0.5, "vy": 0.0, "id": 9},
        {"command": "speed", "speed": 4, "id": 10})),
    "frame": b"\x20" + frame,
})

p = fira_packet_pb2.Packet()
for i, yellow in ((0, True), (1, True), (0, False)):
    c = p.cmd.robot_commands.add()
    c.id, c.yellowteam, c.wheel_left, c.wheel_right = i, yellow, 10.0, -5.0
commands = p.SerializeToString()
p = fira_packet_pb2.Packet()
p.replace.ball.x, p.replace.ball.y, p.replace.ball.vx = 0.1, -0.2, 0.5
r = p.replace.robots.add()
r.position.robot_id, r.position.x, r.position.y, r.position.orientation = 1, -0.3, 0.2, 90.0
r.yellowteam, r.turnon = False, True
r = p.replace.robots.add()
r.position.robot_id, r.yellowteam, r.turnon = 2, True, False
replacement = p.SerializeToString()
write("fuzz_firasim_packet", {"commands": commands, "replacement": replacement, "empty_cmd": b"\x0a\x00"})

m = vssref_placement_pb2.VSSRef_Placement()
m.world.teamColor = 0  # BLUE
for i, (x, y, o) in enumerate(((0.6, 0.0, 180.0), (0.3, 0.2, 170.0), (0.3, -0.2, 190.0))):
    robot = m.world.robots.add()
    robot.robot_id, robot.x, robot.y, robot.orientation = i, x, y, o
blue = m.SerializeToString()
m.world.teamColor = 1  # YELLOW
for robot in m.world.robots:
    robot.x = -robot.x
write("fuzz_vssref_placement", {"blue_kickoff": blue, "yellow": m.SerializeToString()})
