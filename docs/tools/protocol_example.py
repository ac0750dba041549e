#!/usr/bin/python3
"""The worked example of docs/protocol.md, from a real session.

    protocol_example.py VSSIM                  print the section
    protocol_example.py VSSIM --check FILE     exit 1, with a diff, if FILE's section differs
    protocol_example.py VSSIM --write FILE     replace FILE's section in place

VSSIM is the vssim binary. The script starts `VSSIM serve vs_builtin_3v3
--lockstep --port 0`, performs the session the section describes (HELLO as
yellow, WELCOME, the background FRAME, a PLACEMENT and its REPLY, a CONTROL
game_on, the REFEREE and the REPLY, a VOLTAGES, a CONTROL step, FRAME 1,
STATE 1, REPLY), stops the server and writes the Markdown section, from the
line "## A worked example" up to the next "## " heading, with every byte
count, length field and hex dump taken from the bytes sent and received.
The session is deterministic (a fresh server in lockstep mode: its first
client is client 1, and nothing depends on the wall clock), so the section
is the same on every run with the same binary. PNG sizes depend on the
OpenCV/libpng/zlib build: regenerate with --write when they change.

Exit status: 0 done (--check: the section is current), 1 --check found a
difference (or FILE has no such section), 2 the session failed (the server
did not start, did not answer within a few seconds, or answered something
unexpected) or bad usage.

Standard library only.
"""

import argparse
import difflib
import json
import os
import re
import select
import socket
import struct
import subprocess
import sys
import tempfile
import time

HEADING = "## A worked example"
SCENE = "vs_builtin_3v3"
START_TIMEOUT = 10.0  # s for the server to print "listening on ADDR:PORT"
ANSWER_TIMEOUT = 5.0  # s for each message the server owes us

HELLO, VOLTAGES, CONTROL, PLACEMENT = 0x01, 0x02, 0x03, 0x04
WELCOME, FRAME, STATE, REPLY, ERROR, REFEREE = 0x81, 0x82, 0x83, 0x84, 0x85, 0x86
TYPE_NAMES = {HELLO: "HELLO", VOLTAGES: "VOLTAGES", CONTROL: "CONTROL", PLACEMENT: "PLACEMENT", WELCOME: "WELCOME",
              FRAME: "FRAME", STATE: "STATE", REPLY: "REPLY", ERROR: "ERROR", REFEREE: "REFEREE"}
KIND_NAMES = {0: "patches", 1: "full", 2: "background"}
ENCODING_NAMES = {0: "raw", 1: "png", 2: "jpeg"}

# What the client sends (the section shows exactly these bytes).
HELLO_JSON = {"protocol": 1, "role": "yellow", "name": "demo", "state": True}  # images, encoding: defaults
PLACE = {"id": 1, "robots": [{"robot": 1, "x": -0.4, "y": 0.3, "theta": 0.0}]}
GAME_ON = {"command": "game_on", "id": 2}
ROBOT, RIGHT, LEFT = 0, 3.0, -1.5
STEP = {"command": "step", "duration": 0.03, "id": 3}


class SessionError(Exception):
    """The session failed: exit status 2."""


class DocError(Exception):
    """The Markdown file has no (single) worked example section: exit status 1."""


# ---------------------------------------------------------------- the session

def start_server(binary, stderr_file):
    command = [binary, "serve", SCENE, "--lockstep", "--port", "0"]
    try:
        server = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=stderr_file)
    except OSError as e:
        raise SessionError(f"cannot run {binary}: {e}")
    deadline = time.monotonic() + START_TIMEOUT
    text = b""
    while b"\n" not in text:
        left = deadline - time.monotonic()
        if left <= 0:
            return server, SessionError(f"`{' '.join(command)}` did not print \"listening on ADDR:PORT\" "
                                        f"within {START_TIMEOUT:g} s")
        ready, _, _ = select.select([server.stdout], [], [], left)
        if not ready:
            continue
        chunk = os.read(server.stdout.fileno(), 4096)
        if not chunk:
            status = server.wait()
            return server, SessionError(f"`{' '.join(command)}` exited (status {status}) "
                                        f"before it was listening")
        text += chunk
    line = text.split(b"\n", 1)[0].decode(errors="replace")
    match = re.fullmatch(r"listening on (\S+):(\d+)", line)
    if not match:
        return server, SessionError(f"expected \"listening on ADDR:PORT\" from the server, got {line!r}")
    return server, (match.group(1), int(match.group(2)))


def stop_server(server):
    if server.poll() is None:
        server.terminate()  # serve stops on SIGTERM
        try:
            server.wait(timeout=5)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait()
    server.stdout.close()


class Connection:
    def __init__(self, address, port):
        try:
            self.sock = socket.create_connection((address, port), timeout=ANSWER_TIMEOUT)
        except OSError as e:
            raise SessionError(f"cannot connect to the server at {address}:{port}: {e}")
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)

    def send(self, kind, payload):
        message = struct.pack(">IB", len(payload) + 1, kind) + payload
        self.sock.sendall(message)
        return message

    def _exactly(self, n, waiting_for):
        data = b""
        while len(data) < n:
            try:
                chunk = self.sock.recv(n - len(data))
            except socket.timeout:
                raise SessionError(f"the server did not answer within {ANSWER_TIMEOUT:g} s (waiting for {waiting_for})")
            if not chunk:
                raise SessionError(f"the server closed the connection (waiting for {waiting_for})")
            data += chunk
        return data

    def receive(self, kind):
        """The next message, which must be of type `kind`: the whole message, length field included."""
        name = TYPE_NAMES[kind]
        header = self._exactly(4, name)
        (length,) = struct.unpack(">I", header)
        body = self._exactly(length, name)
        if body[0] == ERROR:
            raise SessionError(f"the server sent ERROR instead of {name}: {body[1:].decode(errors='replace')}")
        if body[0] != kind:
            raise SessionError(f"expected {name} (0x{kind:02x}), got message type 0x{body[0]:02x}")
        return header + body

    def close(self):
        self.sock.close()


def json_bytes(value):
    return json.dumps(value, separators=(",", ":")).encode()


def run_session(binary):
    """The messages of the session, in order, as (direction, bytes). The
    server is stopped whatever happens."""
    with tempfile.TemporaryFile() as stderr_file:
        server, listening = start_server(binary, stderr_file)
        try:
            if isinstance(listening, SessionError):
                raise listening
            connection = Connection(*listening)
            try:
                messages = [("C→S", connection.send(HELLO, json_bytes(HELLO_JSON)))]
                messages.append(("S→C", connection.receive(WELCOME)))
                messages.append(("S→C", connection.receive(FRAME)))
                messages.append(("C→S", connection.send(PLACEMENT, json_bytes(PLACE))))
                messages.append(("S→C", connection.receive(REPLY)))
                messages.append(("C→S", connection.send(CONTROL, json_bytes(GAME_ON))))
                messages.append(("S→C", connection.receive(REFEREE)))
                messages.append(("S→C", connection.receive(REPLY)))
                messages.append(("C→S", connection.send(VOLTAGES, struct.pack(">BBdd", 1, ROBOT, RIGHT, LEFT))))
                messages.append(("C→S", connection.send(CONTROL, json_bytes(STEP))))
                for kind in (FRAME, STATE, REPLY):
                    messages.append(("S→C", connection.receive(kind)))
            finally:
                connection.close()
        except (SessionError, OSError) as e:
            stop_server(server)
            stderr_file.seek(0)
            log = stderr_file.read().decode(errors="replace").strip()
            raise SessionError(str(e) + (f"\nserver log:\n{log}" if log else ""))
        finally:
            stop_server(server)  # a no-op when already stopped
    return messages


# ------------------------------------------------- JSON shown as it was sent

class Number(str):
    """A JSON number kept as the server wrote it (1, not 1.0)."""


def load_json(payload):
    text = payload.decode()
    value = json.loads(text, parse_int=Number, parse_float=Number)
    if dump_json(value) != text:
        raise SessionError(f"cannot reproduce the server's JSON byte for byte: {text[:80]}...")
    return value


def dump_json(value):
    if isinstance(value, Number):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, dict):
        return "{" + ",".join(json.dumps(k, ensure_ascii=False) + ":" + dump_json(v) for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ",".join(dump_json(v) for v in value) + "]"
    return json.dumps(value)


def abbreviated(value, shown):
    """`value` as JSON with only the keys in `shown` (a dict: key -> True for
    the whole value, or a nested `shown`); each run of left-out keys is
    "...". A list shows its first element, abbreviated by the same
    `shown`, then "..."."""
    if isinstance(value, list):
        first = abbreviated(value[0], shown) if value else ""
        return "[" + first + (",..." if len(value) > 1 else "") + "]"
    parts = []
    for key, item in value.items():
        if key in shown:
            text = dump_json(item) if shown[key] is True else abbreviated(item, shown[key])
            parts.append(json.dumps(key) + ":" + text)
        elif not parts or parts[-1] != "...":
            parts.append("...")
    return "{" + ",".join(parts) + "}"


def wrapped(text, first_indent, width=100):
    """Abbreviated JSON `text` starting at column `first_indent`, broken
    after top-level commas so that lines stay within `width` where they can;
    continuation lines start one column after the opening brace."""
    pieces, depth, start = [], 0, 0
    for i, c in enumerate(text):
        if c in "{[":
            depth += 1
        elif c in "}]":
            depth -= 1
        elif c == "," and depth == 1:
            pieces.append(text[start:i + 1])
            start = i + 1
    pieces.append(text[start:])
    lines, line, column = [], "", first_indent
    for piece in pieces:
        if line and column + len(line) + len(piece) > width:
            lines.append(line)
            line, column = "", first_indent + 1
        line += piece
    lines.append(line)
    return ("\n" + " " * (first_indent + 1)).join(lines)


# ----------------------------------------------------------- the Markdown

def hexdump(data):
    return " ".join(f"{b:02x}" for b in data)


def grouped(n):
    return f"{n:,}"


def prose_number(x):
    return repr(x).replace("-", "\u2212")


NUMBER_WORDS = ["no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten", "eleven",
                "twelve"]


def in_words(n):
    return NUMBER_WORDS[n] if n < len(NUMBER_WORDS) else str(n)


def plural(n, one, many):
    return f"{n} {one if n == 1 else many}"


class Dump:
    """Lines of an indented (code) block: rows of hex fields, each with its
    label in the line below, the columns aligned."""

    def __init__(self):
        self.lines = []

    def fields(self, prefix, fields, column=None):
        """One row: `prefix` (direction) then `fields`, (hex, label) pairs;
        with `column`, the row starts there instead (a continuation).
        Returns the column of each field."""
        start = 4 + len(prefix) + 1 if column is None else column
        hex_line = " " * 4 + prefix + " " if column is None else " " * column
        label_line = " " * start
        columns, at = [], start
        for i, (hex_text, label) in enumerate(fields):
            width = max(len(hex_text), len(label)) + 2 if i + 1 < len(fields) else 0
            columns.append(at)
            hex_line += hex_text.ljust(width)
            label_line += label.ljust(width)
            at += width
        self.lines += [hex_line.rstrip(), label_line.rstrip()]
        return columns

    def json_message(self, prefix, message, text):
        """A JSON message: length and type in hex, then the JSON `text` (as sent or abbreviated)."""
        head = " " * 4 + f"{prefix} {hexdump(message[:4])}  {message[4]:02x}  "
        self.lines.append(head + wrapped(text, len(head)))

    def text(self):
        return "\n".join(self.lines) + "\n"


def frame_fields(message):
    """A FRAME, decoded: (its header's values, its header as (hex, label)
    fields, [(each patch's values and hex, its image data)])."""
    payload = message[5:]
    frame, sim_time, kind, encoding, count = struct.unpack(">IdBBH", payload[:16])
    header = [
        (hexdump(payload[0:4]), f"frame {frame}"),
        (hexdump(payload[4:12]), f"time {sim_time!r}"),
        (hexdump(payload[12:13]), KIND_NAMES.get(kind, str(kind))),
        (hexdump(payload[13:14]), ENCODING_NAMES.get(encoding, str(encoding))),
        (hexdump(payload[14:16]), plural(count, "patch", "patches")),
    ]
    patches, at = [], 16
    for _ in range(count):
        x, y, w, h, size = struct.unpack(">HHHHI", payload[at:at + 12])
        patches.append(({"x": x, "y": y, "w": w, "h": h, "bytes": size,
                         "hex": [hexdump(payload[at + i:at + i + 2]) for i in (0, 2, 4, 6)] +
                                [hexdump(payload[at + 8:at + 12])]},
                        payload[at + 12:at + 12 + size]))
        at += 12 + size
    if at != len(payload):
        raise SessionError(f"FRAME {frame}: {len(payload) - at} bytes after its {count} patches")
    return {"frame": frame, "time": sim_time, "kind": kind, "encoding": encoding, "count": count}, header, patches


def frame_rows(dump, message, more_label=""):
    """A FRAME: its header and its first patch (the others are left out)."""
    (length,) = struct.unpack(">I", message[:4])
    _, header, patches = frame_fields(message)
    columns = dump.fields("S→C", [(hexdump(message[:4]), f"length {length}"), (hexdump(message[4:5]), "FRAME")] +
                          header)
    patch, data = patches[0]
    signature = hexdump(data[:8]) + " ..."
    dump.fields("", [(patch["hex"][0], f"x {patch['x']}"), (patch["hex"][1], f"y {patch['y']}"),
                     (patch["hex"][2], f"w {patch['w']}"), (patch["hex"][3], f"h {patch['h']}"),
                     (patch["hex"][4], f"{patch['bytes']} bytes"), (signature, "PNG data" + more_label)],
                column=columns[2])


def section(messages):
    (_, hello), (_, welcome), (_, background), (_, placement), (_, placed), (_, game_on), (_, referee), \
        (_, game_on_reply), (_, voltages), (_, control), (_, frame1), (_, state), (_, reply) = messages
    welcome_json = load_json(welcome[5:])
    state_json = load_json(state[5:])
    for message in (reply, placed, game_on_reply, referee):
        load_json(message[5:])  # checks it is shown byte for byte
    robots = len(welcome_json["robots"])
    bg_info, _, bg_patches = frame_fields(background)
    f1_info, _, f1_patches = frame_fields(frame1)
    if (bg_info["kind"], bg_info["count"], f1_info["kind"], f1_info["count"]) != (2, 1, 0, robots + 1) or \
            bg_info["encoding"] != 1 or f1_info["encoding"] != 1:
        raise SessionError("the FRAMEs are not a PNG background then PNG patches of the robots and the ball")
    bg_patch = bg_patches[0][0]
    f1_data = sum(p["bytes"] for p, _ in f1_patches)
    length = lambda message: struct.unpack(">I", message[:4])[0]
    out = []

    out.append(f"""{HEADING}

A yellow team client on `vssim serve {SCENE} --lockstep`, a match
against the built-in blue team (bytes in hex; `C→S` client to server).
Generated from a real session by `docs/tools/protocol_example.py`, which
rewrites this section (`--write docs/protocol.md`); the test
`protocol_example_current` fails when it is out of date.

HELLO, {len(hello) - 5} bytes of JSON (`images` and `encoding` left at their defaults:
PNG patches):

""")
    dump = Dump()
    dump.fields("C→S", [(hexdump(hello[:4]), f"length {length(hello)}"), (hexdump(hello[4:5]), "HELLO"),
                        (hexdump(hello[5:18]) + " ...", hello[5:].decode())])
    out.append(dump.text())

    out.append(f"""
WELCOME ({grouped(len(welcome) - 5)} bytes of JSON, abbreviated; `length` {grouped(length(welcome))}):

""")
    dump = Dump()
    dump.json_message("S→C", welcome, abbreviated(welcome_json, {
        "ball": True, "camera": {"centre_u": True, "scale": True}, "client": True, "dt": True,
        "game": {"blue": True, "referee": True, "state": {"phase": True}, "yellow": True},
        "mode": True, "robots": {"id": True, "index": True}}))
    out.append(dump.text())

    out.append(f"""
The background, a FRAME of kind {bg_info['kind']}, PNG, one {bg_patch['w']} × {bg_patch['h']} patch of \
{grouped(bg_patch['bytes'])} bytes:

""")
    dump = Dump()
    frame_rows(dump, background)
    out.append(dump.text())

    out.append(f"""
The game starts stopped for yellow's kick-off, the robots in the referee's
kick-off places. During STOP the team may place its own robots: a PLACEMENT
({len(placement) - 5} bytes of JSON) moving robot {PLACE['robots'][0]['robot']}, which the server checks against the
kick-off's rules and answers with a REPLY:

""")
    dump = Dump()
    dump.json_message("C→S", placement, placement[5:].decode())
    dump.json_message("S→C", placed, placed[5:].decode())
    out.append(dump.text())

    out.append(f"""
Rather than wait {prose_number(float(welcome_json['game']['stop_duration']))} s for GAME_ON, the client calls it (CONTROL `game_on`); every
client gets a REFEREE ({grouped(len(referee) - 5)} bytes of JSON, `length` {grouped(length(referee))}), then this one its REPLY:

""")
    dump = Dump()
    dump.json_message("C→S", game_on, game_on[5:].decode())
    dump.json_message("S→C", referee, referee[5:].decode())
    dump.json_message("S→C", game_on_reply, game_on_reply[5:].decode())
    out.append(dump.text())

    out.append(f"""
VOLTAGES: robot {ROBOT}, right {prose_number(RIGHT)} V, left {prose_number(LEFT)} V:

""")
    dump = Dump()
    dump.fields("C→S", [(hexdump(voltages[:4]), f"length {length(voltages)}"), (hexdump(voltages[4:5]), "VOLTAGES"),
                        (hexdump(voltages[5:6]), plural(voltages[5], "entry", "entries")),
                        (hexdump(voltages[6:7]), f"robot {voltages[6]}"),
                        (hexdump(voltages[7:15]), f"right {struct.unpack('>d', voltages[7:15])[0]!r}"),
                        (hexdump(voltages[15:23]), f"left {struct.unpack('>d', voltages[15:23])[0]!r}")])
    out.append(dump.text())

    out.append(f"""
CONTROL step of {round(STEP['duration'] * 1000)} ms ({len(control) - 5} bytes of JSON):

""")
    dump = Dump()
    dump.json_message("C→S", control, control[5:].decode())
    out.append(dump.text())

    out.append(f"""
The server answers with FRAME {f1_info['frame']} (patches: {in_words(f1_info['count'])} of them, \
{in_words(robots)} robots then the
ball, {grouped(f1_data)} bytes of PNG in all; `length` {grouped(length(frame1))}), STATE {state_json['frame']} \
(`length` {grouped(length(state))})
and the REPLY:

""")
    dump = Dump()
    frame_rows(dump, frame1, f", then {in_words(f1_info['count'] - 1)} more patches")
    dump.json_message("S→C", state, abbreviated(state_json, {
        "ball": True, "frame": True, "game": {"goals": True, "phase": True},
        "robots": {"index": True, "left_voltage": True, "right_voltage": True}, "time": True}))
    dump.json_message("S→C", reply, reply[5:].decode())
    out.append(dump.text())
    out.append("\n")
    return "".join(out)


# ------------------------------------------------------------- the doc file

def split_doc(text, path):
    """(before, section, after) of a Markdown text: the section runs from the
    line HEADING up to, not including, the next "## " heading."""
    lines = text.splitlines(keepends=True)
    starts = [i for i, line in enumerate(lines) if line.rstrip("\n") == HEADING]
    if len(starts) != 1:
        raise DocError(f"{path}: expected one line \"{HEADING}\", found {len(starts)}")
    start = starts[0]
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("## ")), len(lines))
    return "".join(lines[:start]), "".join(lines[start:end]), "".join(lines[end:])


def main():
    parser = argparse.ArgumentParser(description="The worked example of docs/protocol.md, from a real session.")
    parser.add_argument("vssim", help="the vssim binary")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--check", metavar="FILE", help="exit 1, with a diff, if FILE's worked example differs")
    mode.add_argument("--write", metavar="FILE", help="replace FILE's worked example in place")
    args = parser.parse_args()

    doc_path = args.check or args.write
    try:
        if doc_path:  # a missing section fails before the server starts
            with open(doc_path, encoding="utf-8") as f:
                before, current, after = split_doc(f.read(), doc_path)
        generated = section(run_session(args.vssim))
    except DocError as e:
        print(f"protocol_example.py: {e}", file=sys.stderr)
        return 1
    except (SessionError, OSError) as e:
        print(f"protocol_example.py: {e}", file=sys.stderr)
        return 2

    if args.check:
        if current == generated:
            return 0
        sys.stdout.writelines(difflib.unified_diff(current.splitlines(keepends=True),
                                                   generated.splitlines(keepends=True),
                                                   f"{doc_path} (now)", f"{doc_path} (from the session)"))
        print(f"protocol_example.py: the worked example in {doc_path} is out of date; regenerate it with\n"
              f"  {sys.argv[0]} {args.vssim} --write {doc_path}", file=sys.stderr)
        return 1
    if args.write:
        if current != generated:
            with open(doc_path, "w", encoding="utf-8") as f:
                f.write(before + generated + after)
        return 0
    sys.stdout.write(generated)
    return 0


if __name__ == "__main__":
    sys.exit(main())
