#!/usr/bin/env bash
# Sets up vssim on Debian 12: installs the missing Debian packages, builds
# (Release), then either starts vssim or runs the whole test suite.
#
#   ./setup.sh run [vssim arguments...]   install, build, start vssim
#   ./setup.sh test                       install, build, run every test (CTest)
#
# Environment: BUILD_DIR (default: build), JOBS (default: number of cores).
set -euo pipefail
cd "$(dirname "$0")"

mode=${1:-run}
[ $# -gt 0 ] && shift
case "$mode" in
    run|test) ;;
    -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "setup.sh: unknown mode '$mode' (expected 'run' or 'test')" >&2; exit 2 ;;
esac

packages=(g++ cmake make pkg-config qt6-base-dev libeigen3-dev
          libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-calib3d-dev
          python3 python3-numpy python3-opencv python3-matplotlib python3-dev pybind11-dev
          libqt6opengl6-dev libsdl2-dev xvfb xauth
          libprotobuf-dev protobuf-compiler python3-protobuf python3-distributed
          libbox2d-dev zlib1g-dev
          dpkg-dev file desktop-file-utils iproute2)

missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "setup.sh: installing ${missing[*]}" >&2
    sudo=()
    [ "$(id -u)" -eq 0 ] || sudo=(sudo)
    "${sudo[@]}" apt-get update -q
    "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

build=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc)}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$jobs"

if [ "$mode" = run ]; then
    exec "$build/app/vssim" "$@"
fi
ctest --test-dir "$build" --output-on-failure -j "$jobs"
