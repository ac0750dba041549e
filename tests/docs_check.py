#!/usr/bin/env python3
"""The documentation against the program: every command it shows runs, every
relative link resolves.

    docs_check.py --source DIR --build DIR --vssim PATH [commands] [links]

Files: README.md, docs/*.md and the other READMEs (FILES below).

Commands. In a code block (indented by 4 or more spaces, or fenced with
```), a line whose first word, after an optional "$ " prompt and optional
VAR=value assignments, is build/app/vssim, vssim, /usr/bin/python3,
./setup.sh or build/examples/... is a command; a trailing backslash
continues it on the next line and a trailing "# comment" is not part of it.
"vssim WORD: ..." lines are output, not commands. Every ```python block is
run as a script. Each block runs in a fresh temporary directory (so --out
FILE writes there; the commands of a block share it, in order), with HOME
there too, and must exit 0 and print no error
(ERROR_PATTERN) on standard error (nor a Python traceback anywhere). The
mechanical rewrites, so that everything finishes in seconds and nothing
collides with another test:

  - build/app/vssim and a bare vssim are the vssim under test; any other
    build/PATH is PATH in the build tree under test; ~ is the temporary
    HOME. The temporary directory holds symbolic links to the source tree's
    files and folders (examples/..., resources/...) and build/ to the build
    tree, so a command finds what it would find in a checkout.
  - my_scene.json, "your own scene", is written by this test into the
    temporary directory as a copy of resources/scenes/kickoff_3v3.json.
  - vssim serve gets --port (a free port) and --quit-after 1 (or, as the
    server of a client, it runs until the client is done and is then
    stopped with SIGINT, and must exit 0); with --firasim also free ports
    for FIRASim's commands, the vision and VSSReferee's two ports.
  - vssim match gets --half-duration 2 unless it sets one; vssim stress at
    most --scenes 2 and --seconds 1.
  - The TCP example clients get --max-time CLIENT_MAX_TIME (at most) and
    may exit with 1, "--max-time passed" (the built-in team contests the
    ball): they must not fail otherwise (2: connection, protocol, option).
  - The desktop app (vssim alone, vssim gui ...; gui gets --port) runs on
    this test's X server (ctest runs it under xvfb-run): it must still be
    running after GUI_SECONDS, without an error printed; it is then
    terminated.
  - A client (examples/python/vssim_client.py, build/examples/cpp/
    vssim_example_client, examples/firasim/go_to_ball.py) runs against the
    last server command before it in the same file (vssim serve or the app),
    or the one a "server:" marker names, with that server's ports; the
    FIRASim client plays for at most CLIENT_SECONDS and, with the vision on
    127.0.0.1 (no multicast needed), must have seen it.
  - A "$ command" line followed by lines of output: standard output must be
    those lines; a last line "vssim CMD: ..." is standard error's last
    line, compared with its numbers masked (it has the run time).

Markers, an HTML comment on the line just before a code block:

  <!-- docs-check: skip: REASON -->     the block is not run; REASON is required
  <!-- docs-check: server: COMMAND -->  the block's clients run against COMMAND

A command that cannot run here (./setup.sh) without a skip marker fails.

Links: every [text](target) and ![alt](target) outside code whose target is
not a URL must name an existing file or folder (relative to the document),
and a #anchor must be a heading of the target, with GitHub's slugs
(lowercase, punctuation removed, spaces to hyphens, -1, -2 for repeats).

One line per check (file:line, what, result), then "N passed, N failed,
N skipped"; exit status 1 when any failed.
"""

import argparse
import glob
import os
import re
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

FILES = ["README.md", "docs/*.md", "examples/README.md", "examples/*/README.md", "packaging/README.md",
         "batch/README.md", "ui/README.md"]
PREFIXES = ("build/app/vssim", "vssim", "/usr/bin/python3", "./setup.sh", "build/examples/")
ERROR_PATTERN = re.compile(r"error|unknown option|unrecognized|invalid|cannot|can't|failed|traceback|no such",
                           re.IGNORECASE)
TIMEOUT = 120          # s, any one command
GUI_SECONDS = 3.0      # the app must still run after this
CLIENT_SECONDS = 3     # the FIRASim client's --duration
CLIENT_MAX_TIME = 10   # the TCP clients' --max-time (simulated s; exit status 1 when it passes)
CLIENTS = ("examples/python/vssim_client.py", "examples/cpp/vssim_example_client", "examples/firasim/go_to_ball.py")
MARKER = re.compile(r"^\s*<!--\s*docs-check:(.*?)-->\s*$")
ASSIGNMENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*=")


class Results:
    def __init__(self):
        self.passed = self.failed = self.skipped = 0
        self.last = time.monotonic()

    def report(self, where, what, ok, detail=""):
        if ok is None:
            self.skipped += 1
            status = "SKIPPED"
        elif ok:
            self.passed += 1
            status = "ok"
        else:
            self.failed += 1
            status = "FAILED"
        now = time.monotonic()
        took = f" [{now - self.last:.1f} s]" if now - self.last >= 0.5 else ""
        self.last = now
        print(f"{where}: {what}: {status}{' (' + detail + ')' if detail else ''}{took}", flush=True)


# --- reading the Markdown ---------------------------------------------------------------------

class Block:
    def __init__(self, path, line, fenced, lang, lines, marker):
        self.path, self.line, self.fenced, self.lang = path, line, fenced, lang
        self.lines = lines      # [(line number, text)]
        self.marker = marker    # (kind, argument, line number) or None


def read_blocks(path, text, results):
    """The code blocks of one Markdown file, with the marker before each."""
    lines = text.split("\n")
    blocks, i, marker, previous_blank = [], 0, None, True
    while i < len(lines):
        line = lines[i]
        m = MARKER.match(line)
        if m:
            body = m.group(1).strip()
            kind, _, argument = body.partition(":")
            kind, argument = kind.strip(), argument.strip()
            where = f"{path}:{i + 1}"
            if kind not in ("skip", "server"):
                results.report(where, f"marker <!-- docs-check:{m.group(1)}-->", False,
                               "unknown marker: expected skip: REASON or server: COMMAND")
            elif not argument:
                results.report(where, f"marker {kind}", False,
                               "a skip marker needs its reason" if kind == "skip" else "a server marker needs its command")
            else:
                marker = (kind, argument, i + 1)
            previous_blank = True
            i += 1
            continue
        fence = re.match(r"^(\s*)(```+|~~~+)\s*([\w+-]*)", line)
        if fence:
            indent, ticks, lang = fence.groups()
            start, body = i + 1, []
            i += 1
            while i < len(lines) and not lines[i].strip().startswith(ticks):
                body.append((i + 1, lines[i][len(indent):] if lines[i].startswith(indent) else lines[i]))
                i += 1
            blocks.append(Block(path, start, True, lang.lower(), body, marker))
            marker, previous_blank = None, False
            i += 1
            continue
        if previous_blank and line.startswith("    ") and line.strip():
            body, start = [], i + 1
            while i < len(lines) and (lines[i].startswith("    ") or not lines[i].strip()):
                if not lines[i].strip() and not (i + 1 < len(lines) and lines[i + 1].startswith("    ")):
                    break
                body.append((i + 1, lines[i]))
                i += 1
            blocks.append(Block(path, start, False, "", body, marker))
            marker, previous_blank = None, False
            continue
        if line.strip():
            marker = None
        previous_blank = not line.strip()
        i += 1
    return blocks


def command_words(text):
    """The words of a command line (comments dropped), or None when it is not a command."""
    stripped = text.strip()
    prompt = stripped.startswith("$ ")
    if prompt:
        stripped = stripped[2:]
    try:
        words = shlex.split(stripped, comments=True)
    except ValueError:
        return None, prompt
    first = next((w for w in words if not ASSIGNMENT.match(w)), None)
    if first is None or not any(first == p or (p.endswith("/") and first.startswith(p)) for p in PREFIXES):
        return None, prompt
    if first in ("vssim", "build/app/vssim"):
        rest = stripped.split(None, words.index(first) + 1)[words.index(first) + 1:] if len(words) > 1 else []
        if rest and re.match(r"^[\w-]+:", rest[0]):    # "vssim run: file: ..." is output
            return None, prompt
    return words, prompt


class Command:
    def __init__(self, block, line, words, prompt, output):
        self.block, self.line, self.words, self.prompt, self.output = block, line, words, prompt, output
        self.where = f"{block.path}:{line}"
        self.text = " ".join(shlex.quote(w) for w in words)


def commands_of(block):
    commands, lines, k = [], block.lines, 0
    while k < len(lines):
        number, text = lines[k]
        while text.rstrip().endswith("\\") and k + 1 < len(lines):
            k += 1
            text = text.rstrip()[:-1] + " " + lines[k][1].strip()
        words, prompt = command_words(text)
        k += 1
        if not words:
            continue
        output = []
        if prompt:
            while k < len(lines) and not lines[k][1].strip().startswith("$ "):
                output.append(lines[k][1][4:] if lines[k][1].startswith("    ") else lines[k][1])
                k += 1
            while output and not output[-1].strip():
                output.pop()
        commands.append(Command(block, number, words, prompt, output))
    return commands


# --- running ------------------------------------------------------------------------------------

def free_port(kind=socket.SOCK_STREAM):
    with socket.socket(socket.AF_INET, kind) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for_port(port, proc, seconds=20.0):
    """Until something accepts on 127.0.0.1:port (the server has started), the server
    exits or the time is up; a server with a UDP side opens it before its TCP port."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline and proc.poll() is None:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            time.sleep(0.2)    # our probe connection's HELLO timeout is the server's business
            return
        except OSError:
            time.sleep(0.1)


def set_option(argv, name, value, only_if_absent=False):
    """argv with --name value (replacing the doc's, unless only_if_absent)."""
    if name in argv:
        if only_if_absent:
            return argv
        k = argv.index(name)
        return argv[:k + 1] + [str(value)] + argv[k + 2:]
    return argv + [name, str(value)]


def cap_option(argv, name, most, integer):
    value = float(argv[argv.index(name) + 1]) if name in argv else None
    if value is None or value > most:
        argv = set_option(argv, name, int(most) if integer else most)
    return argv


class Runner:
    def __init__(self, args, results):
        self.source, self.build, self.vssim, self.results = args.source, args.build, args.vssim, results

    # The doc's words as this build's: binary, build tree, source files, ~.
    def localise(self, words, home):
        env, argv = {}, []
        for w in words:
            if not argv and ASSIGNMENT.match(w):
                name, _, value = w.partition("=")
                env[name] = self.path_word(value, home)
                continue
            if not argv and w in ("vssim", "build/app/vssim"):
                argv.append(self.vssim)
                continue
            argv.append(self.path_word(w, home))
        return env, argv

    def path_word(self, w, home):
        if w.startswith("~/"):
            return os.path.join(home, w[2:])
        if w.startswith("build/"):
            return os.path.join(self.build, w[len("build/"):])
        return w

    def environment(self, home, extra):
        env = dict(os.environ)
        env.update({"HOME": home, "PYTHONPATH": os.path.join(self.build, "python"),
                    "VSSIM_PYTHON_PROTO": os.path.join(self.build, "python_proto"),
                    "XDG_RUNTIME_DIR": os.path.join(home, ".runtime")})
        os.makedirs(env["XDG_RUNTIME_DIR"], mode=0o700, exist_ok=True)
        env.update(extra)
        return env

    def workdir(self):
        """A temporary directory that looks like the source tree: its files and folders
        as symbolic links, build/ the build tree under test; what a command writes
        lands in the directory itself."""
        d = tempfile.mkdtemp(prefix="vssim-docs-")
        for name in os.listdir(self.source):
            if name not in ("build", ".git"):
                os.symlink(os.path.join(self.source, name), os.path.join(d, name))
        os.symlink(self.build, os.path.join(d, "build"))
        shutil.copy(os.path.join(self.source, "resources/scenes/kickoff_3v3.json"), os.path.join(d, "my_scene.json"))
        return d

    @staticmethod
    def kind(argv):
        """run, serve, gui, match, ... or client, python, other."""
        if argv and os.path.basename(argv[0]) == "vssim":
            sub = next((a for a in argv[1:] if not a.startswith("-")), None)
            if len(argv) == 1:
                return "gui"
            return sub if sub else "option"
        if any(a.endswith(c) for a in argv[:2] for c in CLIENTS):
            return "client"
        return "other"

    def shorten(self, argv, kind, prompt):
        if kind == "match" and not prompt:
            argv = set_option(argv, "--half-duration", 2, only_if_absent=True)
        if kind == "stress":
            if "--only" not in argv:
                argv = cap_option(argv, "--scenes", 2, True)
            argv = cap_option(argv, "--seconds", 1, False)
        return argv

    # A server's argv with free ports, and the ports, for its clients.
    def server_argv(self, argv, kind):
        ports = {"tcp": free_port()}
        argv = set_option(argv, "--port", ports["tcp"])
        if kind == "serve" and ("--firasim" in argv or "--firasim-sync" in argv):
            ports.update(command=free_port(socket.SOCK_DGRAM), vision=free_port(socket.SOCK_DGRAM))
            argv = set_option(argv, "--firasim-port", ports["command"])
            argv = set_option(argv, "--vision-port", ports["vision"])
            if "--vssref" in argv:
                ports.update(referee=free_port(socket.SOCK_DGRAM), placement=free_port(socket.SOCK_DGRAM))
                argv = set_option(argv, "--vssref-command-port", ports["referee"])
                argv = set_option(argv, "--vssref-placement-port", ports["placement"])
        return argv, ports

    @staticmethod
    def client_argv(argv, ports):
        if argv[-1].endswith("go_to_ball.py") or any(a.endswith("go_to_ball.py") for a in argv):
            for name, key in (("--command-port", "command"), ("--vision-port", "vision"),
                              ("--referee-port", "referee"), ("--placement-port", "placement")):
                if key in ports:
                    argv = set_option(argv, name, ports[key])
            return cap_option(argv, "--duration", CLIENT_SECONDS, True)
        return cap_option(set_option(argv, "--port", ports["tcp"]), "--max-time", CLIENT_MAX_TIME, True)

    def check_output(self, stdout, stderr, returncode, expected_status=0):
        problems = []
        if returncode != expected_status:
            problems.append(f"exit status {returncode}")
        bad = [l for l in stderr.splitlines() if ERROR_PATTERN.search(l)]
        bad += [l for l in stdout.splitlines() if "Traceback" in l]
        if bad:
            problems.append("printed: " + bad[0].strip()[:160])
        return problems

    def run(self, argv, env, cwd, timeout=TIMEOUT):
        try:
            p = subprocess.run(argv, env=env, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               stdin=subprocess.DEVNULL, text=True, timeout=timeout)
            return p.returncode, p.stdout, p.stderr
        except subprocess.TimeoutExpired as e:
            out = e.stdout.decode() if isinstance(e.stdout, bytes) else (e.stdout or "")
            return "timeout", out, f"did not finish in {timeout} s"
        except OSError as e:
            return "not started", "", str(e)

    def start(self, argv, env, cwd):
        return subprocess.Popen(argv, env=env, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                stdin=subprocess.DEVNULL, text=True, start_new_session=True)

    @staticmethod
    def stop(proc, sig):
        if proc.poll() is None:
            proc.send_signal(sig)
        try:
            out, err = proc.communicate(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            out, err = proc.communicate()
        return proc.returncode, out, err

    def run_gui(self, argv, env, cwd):
        """Starts the app; it must be running after GUI_SECONDS. Returns the process."""
        proc = self.start(argv, env, cwd)
        deadline = time.monotonic() + GUI_SECONDS
        while time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.1)
        return proc

    def command(self, cmd, home, server_command=None):
        extra, argv = self.localise(cmd.words, home)
        env = self.environment(home, extra)
        kind = self.kind(argv)
        argv = self.shorten(argv, kind, cmd.prompt)
        shown = " ".join(cmd.words)
        if argv[0].endswith("setup.sh"):
            self.results.report(cmd.where, shown, False,
                                "setup.sh builds and runs the suite itself: it needs a skip marker saying so")
            return
        if kind == "client":
            self.client(cmd, argv, env, home, server_command)
            return
        if kind == "gui":
            if len(argv) > 1:
                argv = set_option(argv, "--port", free_port())
            proc = self.run_gui(argv, env, home)
            alive = proc.poll() is None
            status, out, err = self.stop(proc, signal.SIGTERM)
            problems = [] if alive else [f"exited with status {status} before {GUI_SECONDS} s"]
            problems += self.check_output(out, err, 0)[1:] if alive else self.check_output(out, err, status)[1:]
            self.results.report(cmd.where, shown, not problems, "; ".join(problems) or
                                f"ran {GUI_SECONDS} s, then terminated")
            return
        if kind == "serve":
            argv, _ = self.server_argv(argv, kind)
            argv = set_option(argv, "--quit-after", 1, only_if_absent=True)
        status, out, err = self.run(argv, env, home)
        problems = self.check_output(out, err, status)
        if cmd.prompt and cmd.output:
            problems += self.compare_output(cmd.output, out, err)
        note = "as shown: " + " ".join(a.replace(home + "/", "").replace(self.build, "build")
                                       .replace(self.source + "/", "") for a in argv[1:])
        self.results.report(cmd.where, shown, not problems, "; ".join(problems) or note)

    @staticmethod
    def compare_output(expected, out, err):
        stderr_line = None
        if expected and re.match(r"^vssim [\w-]+: ", expected[-1]):
            stderr_line = expected[-1]
            expected = expected[:-1]
            while expected and not expected[-1].strip():
                expected.pop()
        got = out.rstrip("\n").split("\n")
        problems = []
        if [l.rstrip() for l in got] != [l.rstrip() for l in expected]:
            diff = next((k for k in range(max(len(got), len(expected)))
                         if k >= len(got) or k >= len(expected) or got[k].rstrip() != expected[k].rstrip()), 0)
            problems.append(f"output differs from the doc's at its line {diff + 1}: the doc shows "
                            f"{expected[diff].strip() if diff < len(expected) else '(nothing)'!r}, "
                            f"the program prints {got[diff].strip() if diff < len(got) else '(nothing)'!r}")
        if stderr_line is not None:
            mask = lambda s: re.sub(r"\d+(\.\d+)?", "N", s.strip())
            last = err.rstrip("\n").split("\n")[-1] if err.strip() else ""
            if mask(last) != mask(stderr_line):
                problems.append(f"standard error ends with {last!r}, the doc shows {stderr_line!r}")
        return problems

    def client(self, cmd, argv, env, home, server_command):
        shown = " ".join(cmd.words)
        if server_command is None:
            self.results.report(cmd.where, shown, False, "a client with no server before it in the file "
                                "and no server marker")
            return
        s_extra, s_argv = self.localise(shlex.split(server_command.text, comments=True), home)
        s_kind = self.kind(s_argv)
        s_argv, ports = self.server_argv(s_argv, s_kind)
        server = self.start(s_argv, self.environment(home, s_extra), home)
        wait_for_port(ports["tcp"], server)
        argv = self.client_argv(argv, ports)
        status, out, err = self.run(argv, env, home, timeout=60)
        # The TCP clients exit with 1 when --max-time passed before the robot reached
        # the ball (the built-in blue team contests it): they played, by their own rule.
        gave_up = status == 1 and "--max-time" in argv
        problems = self.check_output(out, err, status, 1 if gave_up else 0)
        alive = server.poll() is None
        s_status, s_out, s_err = self.stop(server, signal.SIGTERM if s_kind == "gui" else signal.SIGINT)
        if not alive:
            problems.append(f"its server ({server_command.where}) exited early, status {s_status}: "
                            f"{s_err.strip()[-200:]}")
        elif s_kind != "gui":
            problems += ["server: " + p for p in self.check_output(s_out, s_err, s_status)]
        tail = (out.strip().split("\n") or [""])[-1][:100]
        seen = re.search(r"vision packets (\d+)", out)
        # Over unicast it must have seen the vision; multicast needs a route some
        # machines lack (docs/firasim.md), so there only that it ran.
        unicast = "--vision-address" in argv and argv[argv.index("--vision-address") + 1] == "127.0.0.1"
        if any(a.endswith("go_to_ball.py") for a in argv) and unicast and not (seen and int(seen.group(1)) > 0):
            problems.append("the FIRASim client saw no vision packet")
        self.results.report(cmd.where, shown, not problems, "; ".join(problems) or
                            f"against {server_command.where}'s server; "
                            f"{'exit status 1, --max-time passed; ' if gave_up else ''}last line: {tail}")

    def python_block(self, block):
        home = self.workdir()
        try:
            script = os.path.join(home, "block.py")
            with open(script, "w") as f:
                f.write("\n".join(t for _, t in block.lines) + "\n")
            env = self.environment(home, {})
            status, out, err = self.run(["/usr/bin/python3", script], env, home)
            problems = self.check_output(out, err, status)
            last = (out.strip().split("\n") or [""])[-1][:100]
            self.results.report(f"{block.path}:{block.line}", f"python block ({len(block.lines)} lines)",
                                not problems, "; ".join(problems) or f"last line: {last}")
        finally:
            shutil.rmtree(home, ignore_errors=True)


def check_commands(args, documents, results):
    runner = Runner(args, results)
    for path, text in documents:
        server = None
        for block in read_blocks(path, text, results):
            commands = commands_of(block)
            python = block.fenced and block.lang == "python"
            if not commands and not python:
                continue
            marker = block.marker
            if marker and marker[0] == "skip":
                for c in commands:
                    results.report(c.where, " ".join(c.words), None, marker[1])
                if python:
                    results.report(f"{path}:{block.line}", "python block", None, marker[1])
                continue
            block_server = None
            if marker and marker[0] == "server":
                words, _ = command_words(marker[1])
                if not words:
                    results.report(f"{path}:{marker[2]}", "server marker", False, "not a vssim command")
                    continue
                block_server = Command(block, marker[2], words, False, [])
            if python:
                runner.python_block(block)
            home = runner.workdir()     # shared by the block's commands, in order
            try:
                for c in commands:
                    kind = Runner.kind(runner.localise(c.words, "/")[1])
                    runner.command(c, home, block_server or server)
                    if kind in ("serve", "gui"):
                        server = c
            finally:
                shutil.rmtree(home, ignore_errors=True)


# --- links --------------------------------------------------------------------------------------

def slug(heading):
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)   # a link: its text
    text = text.strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)                      # punctuation, backticks, emphasis
    return text.replace(" ", "-")


def anchors(text):
    seen, result, fenced = {}, set(), False
    for line in text.split("\n"):
        if re.match(r"^\s*(```|~~~)", line):
            fenced = not fenced
            continue
        m = None if fenced else re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m:
            s = slug(m.group(1))
            n = seen.get(s, 0)
            result.add(s if n == 0 else f"{s}-{n}")
            seen[s] = n + 1
        for a in re.findall(r'<a\s+(?:name|id)="([^"]+)"', line):
            result.add(a)
    return result


def check_links(args, documents, results):
    link = re.compile(r"(!?)\[((?:[^\[\]]|\[[^\]]*\])*)\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
    for path, text in documents:
        code = set()
        for block in read_blocks(path, text, Results()):
            code.update(n for n, _ in block.lines)
            if block.fenced:
                code.update((block.line - 1, block.line + len(block.lines)))
        for number, line in enumerate(text.split("\n"), 1):
            if number in code:
                continue
            for image, label, target in link.findall(re.sub(r"`[^`]*`", "", line)):
                if re.match(r"^[a-z][a-z0-9+.-]*:", target):     # http:, https:, mailto:
                    continue
                file_part, _, anchor = target.partition("#")
                base = os.path.dirname(os.path.join(args.source, path))
                target_path = os.path.normpath(os.path.join(base, file_part)) if file_part else \
                    os.path.join(args.source, path)
                what = f"{'image' if image else 'link'} {target}"
                if not os.path.exists(target_path):
                    results.report(f"{path}:{number}", what, False, "no such file")
                    continue
                if anchor:
                    if not target_path.endswith(".md") or os.path.isdir(target_path):
                        results.report(f"{path}:{number}", what, False, "an anchor into a file that is not Markdown")
                        continue
                    with open(target_path, encoding="utf-8") as f:
                        if anchor not in anchors(f.read()):
                            results.report(f"{path}:{number}", what, False,
                                           f"no heading with the anchor #{anchor} in "
                                           f"{os.path.relpath(target_path, args.source)}")
                            continue
                results.report(f"{path}:{number}", what, True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--source", required=True, help="the source tree (the docs)")
    parser.add_argument("--build", required=True, help="the build tree (build/ in the docs)")
    parser.add_argument("--vssim", required=True, help="the vssim program (build/app/vssim in the docs)")
    parser.add_argument("checks", nargs="*", choices=["commands", "links"], default=[])
    parser.add_argument("--file", action="append", help="only these documents (paths in the source tree)")
    args = parser.parse_args()
    args.source, args.build = os.path.abspath(args.source), os.path.abspath(args.build)
    args.vssim = os.path.abspath(args.vssim)
    checks = args.checks or ["commands", "links"]
    paths = []
    for pattern in FILES:
        for p in sorted(glob.glob(os.path.join(args.source, pattern))):
            rel = os.path.relpath(p, args.source)
            if rel not in paths and (not args.file or rel in args.file):
                paths.append(rel)
    documents = [(p, open(os.path.join(args.source, p), encoding="utf-8").read()) for p in paths]
    results = Results()
    start = time.monotonic()
    if "links" in checks:
        check_links(args, documents, results)
    if "commands" in checks:
        check_commands(args, documents, results)
    print(f"{results.passed} passed, {results.failed} failed, {results.skipped} skipped "
          f"({len(documents)} documents, {time.monotonic() - start:.0f} s)")
    return 1 if results.failed or results.passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
