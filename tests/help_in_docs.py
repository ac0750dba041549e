#!/usr/bin/python3
"""Every option of every vssim command is documented: each `--option` that
`vssim COMMAND --help` lists appears, as `--option`, on the doc pages of that
command. The man pages are made from the same --help texts (packaging/), so
they agree with the docs too.

    /usr/bin/python3 tests/help_in_docs.py build/app/vssim
"""

import os
import re
import subprocess
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
PAGES = {  # the pages that document each command
    "run": ["docs/headless.md", "docs/model.md", "docs/scenes.md", "docs/game.md"],
    "serve": ["docs/protocol.md", "docs/firasim.md"],
    "match": ["docs/game.md"],
    "stress": ["docs/model.md", "docs/headless.md"],
    "gui": ["docs/app.md"],
}
OPTION = re.compile(r"--[a-z][a-z0-9-]*")


def main(argv):
    vssim = argv[1]
    passed = failed = 0
    for command, pages in PAGES.items():
        text = subprocess.run([vssim, command, "--help"], capture_output=True, text=True, timeout=60,
                              env={k: v for k, v in os.environ.items() if k != "DISPLAY"})
        if text.returncode != 0:
            print("FAIL vssim %s --help exited %d: %s" % (command, text.returncode, text.stderr.strip()))
            failed += 1
            continue
        options = sorted(set(OPTION.findall(text.stdout)) - {"--help", "--help-all"})
        documented = set()
        for page in pages:
            with open(os.path.join(ROOT, page), encoding="utf-8") as f:
                documented |= set(OPTION.findall(f.read()))
        for option in options:
            if option in documented:
                passed += 1
            else:
                failed += 1
                print("FAIL vssim %s %s: in --help, on none of %s" % (command, option, ", ".join(pages)))
        print("vssim %s: %d options, pages %s" % (command, len(options), ", ".join(pages)))
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
