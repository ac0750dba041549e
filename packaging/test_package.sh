#!/bin/sh
# CTest `package_deb`: build the .deb with CPack, check its control fields,
# unpack it into a temporary root and run the installed vssim from there.
#
#   packaging/test_package.sh BUILD_DIR
#
# Needs cpack, dpkg-deb, dpkg-shlibdeps (dpkg-dev) and file. Each failed step
# prints "package_deb: FAIL: ..." and exits 1.
set -u

fail() { echo "package_deb: FAIL: $*" >&2; exit 1; }
step() { echo "package_deb: $*"; }

[ $# -eq 1 ] || { echo "usage: $0 BUILD_DIR" >&2; exit 2; }
build=$(cd "$1" 2>/dev/null && pwd) || fail "no build directory '$1'"
[ -f "$build/CPackConfig.cmake" ] || fail "$build/CPackConfig.cmake missing: configure with cmake first"

version=$(sed -n 's/^set(CPACK_PACKAGE_VERSION "\(.*\)")$/\1/p' "$build/CPackConfig.cmake")
[ -n "$version" ] || fail "no CPACK_PACKAGE_VERSION in $build/CPackConfig.cmake"

for tool in cpack dpkg-deb dpkg-shlibdeps file readelf; do
    command -v "$tool" >/dev/null 2>&1 || case $tool in
        dpkg-shlibdeps) fail "dpkg-shlibdeps not found: install dpkg-dev (apt-get install dpkg-dev)" ;;
        file) fail "'file' not found: CPack needs it for SHLIBDEPS (apt-get install file)" ;;
        readelf) fail "readelf not found: install binutils" ;;
        *) fail "$tool not found" ;;
    esac
done

tmp=$(mktemp -d "${TMPDIR:-/tmp}/vssim-package.XXXXXX") || fail "mktemp failed"
trap 'rm -rf "$tmp"' EXIT INT TERM

# 1. The package. (-B: into the temporary directory, not the build dir.)
step "cpack -G DEB (version $version)"
if ! (cd "$build" && cpack -G DEB -B "$tmp/out") >"$tmp/cpack.log" 2>&1; then
    cat "$tmp/cpack.log" >&2
    fail "cpack -G DEB failed (log above)"
fi
arch=$(dpkg --print-architecture 2>/dev/null || echo amd64)
deb="$tmp/out/vssim_${version}_${arch}.deb"
[ -f "$deb" ] || { ls -l "$tmp/out" >&2; fail "expected package $deb not produced (files above)"; }
step "built $(basename "$deb"), $(du -k "$deb" | cut -f1) KiB"

# 2. Control fields: Depends filled in by dpkg-shlibdeps.
dpkg-deb -I "$deb" >"$tmp/info" 2>&1 || { cat "$tmp/info" >&2; fail "dpkg-deb -I failed"; }
grep -q '^ Package: vssim$' "$tmp/info" || fail "control: Package is not vssim"
grep -q "^ Version: $version\$" "$tmp/info" || fail "control: Version is not $version"
grep -q '^ Section: science$' "$tmp/info" || fail "control: Section is not science"
depends=$(sed -n 's/^ Depends: //p' "$tmp/info")
[ -n "$depends" ] || { cat "$tmp/info" >&2; fail "control: no Depends line (dpkg-shlibdeps did not run?)"; }
step "Depends: $depends"
for lib in libqt6core6 libqt6gui6 libqt6widgets6 libqt6network6 libopencv-core libopencv-imgproc libopencv-imgcodecs libsdl2 libprotobuf libc6; do
    echo "$depends" | grep -q "$lib" || fail "control: Depends lacks $lib: $depends"
done
grep -q '^ Recommends: .*python3-numpy' "$tmp/info" || fail "control: Recommends lacks python3-numpy (the Python module)"
grep -q '^ Suggests: .*python3-opencv' "$tmp/info" || fail "control: Suggests lacks python3-opencv"
grep -q '^ Suggests: .*python3-distributed' "$tmp/info" || fail "control: Suggests lacks python3-distributed (vssim.distributed)"
grep -q '^ Suggests: .*python3-protobuf' "$tmp/info" || fail "control: Suggests lacks python3-protobuf (the FIRASim example)"

# 3. Unpack into a temporary root and check the files.
root="$tmp/root"
dpkg-deb -x "$deb" "$root" || fail "dpkg-deb -x failed"
for f in \
    usr/bin/vssim \
    usr/libexec/vssim/vssim-full \
    usr/bin/vssim-example-client \
    usr/share/applications/vssim.desktop \
    usr/share/icons/hicolor/48x48/apps/vssim.png \
    usr/share/icons/hicolor/128x128/apps/vssim.png \
    usr/share/icons/hicolor/256x256/apps/vssim.png \
    usr/share/icons/hicolor/scalable/apps/vssim.svg \
    usr/share/vssim/scenes/kickoff_3v3.json \
    usr/share/vssim/scenes/robot_hits_ball.json \
    usr/share/vssim/examples/README.md \
    usr/share/vssim/examples/python/vssim_client.py \
    usr/share/vssim/examples/cpp/vssim_client.cpp \
    usr/share/vssim/examples/firasim/go_to_ball.py \
    usr/share/vssim/examples/firasim/README.md \
    usr/share/vssim/proto/fira_packet.proto \
    usr/share/vssim/proto/vssref_command.proto \
    usr/share/vssim/python_proto/fira_packet_pb2.py \
    usr/share/vssim/docs/protocol.md \
    usr/share/doc/vssim/README.md \
    usr/share/doc/vssim/copyright \
    usr/lib/python3/dist-packages/vssim/__init__.py \
    usr/lib/python3/dist-packages/vssim/env/__init__.py \
    usr/lib/python3/dist-packages/vssim/env/vector.py \
    usr/lib/python3/dist-packages/vssim/distributed/__init__.py \
    usr/lib/python3/dist-packages/vssim/distributed/worker.py \
    usr/share/doc/vssim/docs/distributed.md \
    usr/share/doc/vssim/docs/images/train_go_to_ball.png \
    usr/share/vssim/examples/python/train_go_to_ball.py \
    usr/share/doc/vssim/docs/python.md \
    usr/share/man/man1/vssim.1.gz \
    usr/share/man/man1/vssim-gui.1.gz \
    usr/share/man/man1/vssim-run.1.gz \
    usr/share/man/man1/vssim-serve.1.gz \
    usr/share/man/man1/vssim-match.1.gz \
    usr/share/man/man1/vssim-stress.1.gz \
    usr/share/man/man1/vssim-demo.1.gz \
    usr/share/doc/vssim/docs/protocol.md \
    usr/share/doc/vssim/docs/scenes.md \
    usr/share/doc/vssim/docs/model.md \
    usr/share/doc/vssim/docs/performance.md \
    usr/share/doc/vssim/docs/game.md \
    usr/share/doc/vssim/docs/firasim.md \
    usr/share/doc/vssim/docs/images/speed_loop_step.png \
    usr/share/doc/vssim/docs/images/app.png \
    usr/share/doc/vssim/docs/performance/scale.png; do
    [ -f "$root/$f" ] || fail "not in the package: /$f"
done
for x in usr/bin/vssim usr/libexec/vssim/vssim-full usr/bin/vssim-example-client usr/share/vssim/examples/python/vssim_client.py \
         usr/share/vssim/examples/firasim/go_to_ball.py; do
    [ -x "$root/$x" ] || fail "not executable: /$x"
done
nscenes=$(ls "$root/usr/share/vssim/scenes/"*.json | wc -l)
[ "$nscenes" -ge 6 ] || fail "only $nscenes example scenes in /usr/share/vssim/scenes"
for x in usr/bin/vssim usr/libexec/vssim/vssim-full; do
    if readelf -d "$root/$x" | grep -qE 'RPATH|RUNPATH'; then
        fail "/$x has an RPATH: $(readelf -d "$root/$x" | grep -E 'RPATH|RUNPATH')"
    fi
done
grep -q '^Exec=vssim gui' "$root/usr/share/applications/vssim.desktop" || fail "vssim.desktop: Exec is not 'vssim gui ...'"
if command -v desktop-file-validate >/dev/null 2>&1; then
    desktop-file-validate "$root/usr/share/applications/vssim.desktop" || fail "desktop-file-validate rejects vssim.desktop"
else
    step "desktop-file-validate not installed (desktop-file-utils): vssim.desktop not validated"
fi
step "files: OK ($nscenes scenes)"

# Licence: Debian's machine-readable copyright file, MIT (Expat).
grep -q '^Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/$' "$root/usr/share/doc/vssim/copyright" \
    || fail "copyright: no DEP-5 Format line"
grep -q '^License: Expat$' "$root/usr/share/doc/vssim/copyright" || fail "copyright: no 'License: Expat'"
grep -q '^ Permission is hereby granted, free of charge' "$root/usr/share/doc/vssim/copyright" \
    || fail "copyright: the licence text is missing"

# Man pages: one per command, from its --help, and each renders without warnings.
for page in vssim vssim-gui vssim-run vssim-serve vssim-match vssim-stress vssim-demo; do
    file="$root/usr/share/man/man1/$page.1.gz"
    title=$(echo "$page" | tr a-z A-Z)
    gzip -dc "$file" | grep -q "^\.TH $title 1 " || fail "$page.1.gz: no .TH $title 1 line"
    if command -v groff >/dev/null 2>&1; then
        text=$(gzip -dc "$file" | groff -man -Tutf8 -ww -P-c -P-b -P-u 2>"$tmp/groff.err") || fail "$page.1.gz: groff failed"
        [ ! -s "$tmp/groff.err" ] || { cat "$tmp/groff.err" >&2; fail "$page.1.gz: groff warnings (above)"; }
        echo "$text" | grep -q "SYNOPSIS" || fail "$page.1.gz: no SYNOPSIS when rendered"
    fi
done
gzip -dc "$root/usr/share/man/man1/vssim-run.1.gz" | grep -q -- '\\-\\-duration' || fail "vssim-run.1.gz: --duration is not documented"
gzip -dc "$root/usr/share/man/man1/vssim-match.1.gz" | grep -q -- '\\-\\-seed' || fail "vssim-match.1.gz: --seed is not documented"
step "copyright and man pages: OK"

# The installed documentation speaks of the installed program, not of a build tree.
if grep -rn 'build/app/vssim\|build/examples/cpp' "$root/usr/share/doc/vssim" "$root/usr/share/vssim/examples/README.md"; then
    fail "the installed docs (lines above) name build-tree paths"
fi
grep -q 'vssim run robot_hits_ball' "$root/usr/share/doc/vssim/README.md" || fail "installed README: no 'vssim run robot_hits_ball' example"

# 4. Run the installed program, with nothing from the build tree.
out=$(env -u LD_LIBRARY_PATH "$root/usr/bin/vssim" --version 2>&1) || fail "vssim --version failed: $out"
echo "$out" | grep -q "$version" || fail "vssim --version prints '$out', not $version"
# vssim serve runs the installed vssim-full, found from vssim's own path.
out=$(env -u LD_LIBRARY_PATH "$root/usr/bin/vssim" serve --help 2>&1) || fail "vssim serve --help failed: $out"
echo "$out" | grep -q -- "--lockstep" || fail "vssim serve --help (through vssim-full) prints: $out"

csv="$tmp/run.csv"
(cd "$tmp" && env -u LD_LIBRARY_PATH -u DISPLAY -u WAYLAND_DISPLAY \
    "$root/usr/bin/vssim" run "$root/usr/share/vssim/scenes/robot_hits_ball.json" --duration 0.5 --sample 0.1) \
    >"$csv" 2>"$tmp/run.err" || { cat "$tmp/run.err" >&2; fail "installed vssim run robot_hits_ball.json failed"; }
header='t,body,x,y,theta,v,omega,e_right,e_left,omega_right,omega_left,i_right,i_left'
[ "$(head -n 1 "$csv")" = "$header" ] || fail "vssim run: CSV header is '$(head -n 1 "$csv")', expected '$header'"
balls=$(grep -c '^[0-9.e+-]*,ball,' "$csv")
[ "$balls" -ge 6 ] || { head -n 20 "$csv" >&2; fail "vssim run: $balls rows for the ball, expected 6 (t = 0, 0.1, ..., 0.5)"; }
last=$(grep ',ball,' "$csv" | tail -n 1 | cut -d, -f1)
awk -v t="$last" 'BEGIN { exit !(t > 0.49 && t < 0.51) }' || fail "vssim run: last ball row at t = $last, expected 0.5"
x0=$(grep ',ball,' "$csv" | head -n 1 | cut -d, -f3)
x1=$(grep ',ball,' "$csv" | tail -n 1 | cut -d, -f3)
awk -v a="$x0" -v b="$x1" 'BEGIN { exit !(b > a + 0.1) }' || fail "vssim run: the robot did not push the ball (ball x $x0 -> $x1)"
step "installed vssim run: OK ($(($(wc -l <"$csv") - 1)) rows, $balls for the ball)"

# 5. The installed Python module, for Debian's python3, with nothing from the build tree.
pymod=$(ls "$root"/usr/lib/python3/dist-packages/vssim/_vssim.cpython-*.so 2>/dev/null | head -n 1)
[ -n "$pymod" ] || fail "not in the package: /usr/lib/python3/dist-packages/vssim/_vssim.cpython-*.so"
if readelf -d "$pymod" | grep -qE 'RPATH|RUNPATH'; then fail "$(basename "$pymod") has an RPATH"; fi
if [ -x /usr/bin/python3 ] && /usr/bin/python3 -c "import numpy" 2>/dev/null; then
    out=$(cd "$tmp" && env -u LD_LIBRARY_PATH PYTHONPATH="$root/usr/lib/python3/dist-packages" /usr/bin/python3 -c "
import vssim, vssim.env, vssim.distributed
assert vssim.__file__.startswith('$root/'), vssim.__file__
eps = vssim.distributed.run_episodes(None, 'kickoff_3v3', [1, 2], 0.3)
assert eps.ok.all() and eps.steps.tolist() == [300, 300], (eps.errors, eps.steps)
w = vssim.World('kickoff_3v3')
w.step(0.5)
env = vssim.env.VssimVectorEnv('GoToBall', num_envs=2)
obs, _ = env.reset(seed=0)
print(vssim.__version__, w.time, obs.shape)
" 2>&1) || fail "the installed Python module does not work: $out"
    echo "$out" | grep -q "^$version 0.5 (2, 12)\$" || fail "the installed Python module printed '$out'"
    step "installed Python module: OK ($(basename "$pymod"))"
else
    step "/usr/bin/python3 with numpy not installed: the installed Python module not run"
fi

echo "package_deb: PASS"
