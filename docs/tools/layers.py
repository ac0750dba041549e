#!/usr/bin/python3
"""vssim's layers as the code has them: which top-level folder includes
which (from the #include lines of every .h and .cpp), checked against the
rule that each layer uses only those below it, and drawn as a picture.

    /usr/bin/python3 docs/tools/layers.py --check              # exit 1 on an include that breaks the rule
    /usr/bin/python3 docs/tools/layers.py --draw docs/images/layers.png

The rule (docs/architecture.md, "Layers"): ALLOWED below, folder by folder.
An include is resolved as the compiler does for this tree: "vssim/..."
against engine/include, game/include, camera/include and batch/include;
"folder/file.h" against runtime/ (its subfolders), then the including
file's own folder (ui/, app/, bench/, python/ include their own files by
bare name), then ui/ and app/, whose targets export their folders.
"""

import argparse
import collections
import os
import re
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

# Bottom to top: the order the picture stacks them in (a row may hold two).
ROWS = [["engine"], ["game", "camera"], ["batch", "runtime"], ["ui", "python"], ["app"], ["bench"]]
ALLOWED = {
    "engine": set(),
    "game": {"engine"},
    "camera": {"engine"},
    "batch": {"game", "engine"},
    "runtime": {"camera", "game", "engine"},
    "ui": {"runtime", "camera", "game", "engine"},
    "python": {"runtime", "batch", "camera", "game", "engine"},
    "app": {"ui", "runtime", "batch", "camera", "game", "engine"},
    "bench": {"app", "ui", "runtime", "batch", "camera", "game", "engine"},
}
INCLUDE_ROOTS = [("engine", "engine/include"), ("game", "game/include"), ("camera", "camera/include"),
                 ("batch", "batch/include"), ("runtime", "runtime")]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def sources():
    for folder in ALLOWED:
        for dirpath, _, files in os.walk(os.path.join(ROOT, folder)):
            for name in files:
                if name.endswith((".h", ".cpp")):
                    yield folder, os.path.join(dirpath, name)


def resolve(path, included):
    """The top-level folder that `included` (as written in `path`) comes from, or None (generated, system)."""
    for folder, root in INCLUDE_ROOTS:
        if os.path.isfile(os.path.join(ROOT, root, included)):
            return folder
    local = os.path.join(os.path.dirname(path), included)
    if os.path.isfile(local):
        return os.path.relpath(local, ROOT).split(os.sep)[0]
    for folder in ("ui", "app"):  # their CMake targets export their folders to the layers above
        if os.path.isfile(os.path.join(ROOT, folder, included)):
            return folder
    return None


def edges():
    """{(from folder, to folder): number of include lines}, and the lines that break the rule."""
    counts = collections.Counter()
    broken = []
    for folder, path in sources():
        with open(path, encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                target = resolve(path, m.group(1))
                if target is None or target == folder:
                    continue
                counts[(folder, target)] += 1
                if target not in ALLOWED[folder]:
                    broken.append("%s:%d: %s includes %s (%s may use %s)" % (
                        os.path.relpath(path, ROOT), number, folder, m.group(1), folder,
                        ", ".join(sorted(ALLOWED[folder])) or "nothing of vssim"))
    return counts, broken


def lines_of_code():
    total = collections.Counter()
    for folder, path in sources():
        with open(path, encoding="utf-8", errors="replace") as f:
            total[folder] += sum(1 for _ in f)
    return total


def draw(counts, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import FancyBboxPatch

    size = lines_of_code()
    width, height, gap = 3.2, 0.9, 0.55
    where = {}
    fig, ax = plt.subplots(figsize=(9, 8))
    for r, row in enumerate(ROWS):
        y = r * (height + gap)
        x0 = (2 * width + 0.6 - (len(row) * width + (len(row) - 1) * 0.6)) / 2
        for c, folder in enumerate(row):
            x = x0 + c * (width + 0.6)
            where[folder] = (x, y)
            ax.add_patch(FancyBboxPatch((x, y), width, height, boxstyle="round,pad=0.02",
                                        facecolor="#dfe9f5" if folder != "engine" else "#f3dfe3",
                                        edgecolor="#334"))
            ax.text(x + width / 2, y + height * 0.62, folder + "/", ha="center", va="center", fontsize=13,
                    weight="bold")
            ax.text(x + width / 2, y + height * 0.28, "%s lines" % format(size[folder], ","), ha="center",
                    va="center", fontsize=9, color="#334")
    for (a, b), n in sorted(counts.items()):
        if b == "engine" or a == "bench":
            continue  # every layer uses the engine, and the benchmarks use every layer: said in the title
        (xa, ya), (xb, yb) = where[a], where[b]
        start = (xa + width / 2, ya)
        end = (xb + width / 2, yb + height)
        ax.annotate("", xy=end, xytext=start,
                    arrowprops=dict(arrowstyle="->", color="#c33" if b not in ALLOWED[a] else "#556",
                                    lw=0.6 + 0.35 * min(n, 30) ** 0.5, alpha=0.8,
                                    connectionstyle="arc3,rad=0.0"))
        ax.text((start[0] + end[0]) / 2, (start[1] + end[1]) / 2, str(n), fontsize=8, color="#223",
                ha="center", va="center", bbox=dict(boxstyle="round,pad=0.15", facecolor="white", edgecolor="none"))
    ax.set_xlim(-0.3, 2 * width + 0.9)
    ax.set_ylim(-0.3, len(ROWS) * (height + gap))
    ax.axis("off")
    ax.set_title("vssim's layers: an arrow and its number are a folder's #include lines into a layer below it\n"
                 "(every layer also includes the engine's headers, and bench/ every layer's: not drawn)\n"
                 "drawn from the code by docs/tools/layers.py; a red arrow would break the rule", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--check", action="store_true", help="exit 1 when an include breaks the layers' rule")
    p.add_argument("--draw", metavar="PNG", help="draw the layers and their includes to PNG")
    args = p.parse_args(argv)
    counts, broken = edges()
    for (a, b), n in sorted(counts.items()):
        print("%-8s -> %-8s %4d include lines" % (a, b, n))
    for line in broken:
        print("BROKEN " + line)
    if args.draw:
        draw(counts, args.draw)
        print("drew %s" % args.draw)
    if args.check:
        print("%d passed, %d failed" % (len(counts) - len({(l.split()[1]) for l in broken}), len(broken)))
        return 1 if broken else 0
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
