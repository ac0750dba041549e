#!/usr/bin/env bash
# Sets up vssim on Debian 12: installs the missing Debian packages, builds
# (Release), then either starts vssim or runs the whole test suite.
#
#   ./setup.sh run [vssim arguments...]   install, build, start vssim
#   ./setup.sh test                       install, build, run every test (CTest)
#   ./setup.sh test --sanitizers          the same, then the sanitizer and fuzzer
#                                         jobs (tests/sanitizers/run.sh all, about
#                                         30 minutes on two cores; docs/testing.md)
#
# With CI=true, `test` runs the sanitizer and fuzzer jobs too.
# Environment: BUILD_DIR (default: build), JOBS (default: number of cores).
set -euo pipefail
cd "$(dirname "$0")"

mode=${1:-run}
[ $# -gt 0 ] && shift
case "$mode" in
    run|test) ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "setup.sh: unknown mode '$mode' (expected 'run' or 'test')" >&2; exit 2 ;;
esac
sanitizers=no
if [ "$mode" = test ]; then
    [ "${CI:-}" = true ] && sanitizers=yes
    for a in "$@"; do
        case "$a" in
            --sanitizers) sanitizers=yes ;;
            *) echo "setup.sh: unknown option '$a' for test (expected --sanitizers)" >&2; exit 2 ;;
        esac
    done
fi

packages=(g++ cmake make pkg-config qt6-base-dev libeigen3-dev
          libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev libopencv-calib3d-dev
          python3 python3-numpy python3-opencv python3-matplotlib python3-dev pybind11-dev
          libqt6opengl6-dev libsdl2-dev xvfb xauth
          libprotobuf-dev protobuf-compiler python3-protobuf python3-distributed
          libbox2d-dev zlib1g-dev
          dpkg-dev file desktop-file-utils iproute2)
# The sanitizer and fuzzer jobs: libFuzzer is clang's (its runtime in
# libclang-rt-14-dev), llvm-14 symbolizes its reports; GCC's sanitizer
# runtimes come with g++.
[ "$sanitizers" = yes ] && packages+=(clang-14 libclang-rt-14-dev llvm-14)

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
status=0
ctest --test-dir "$build" --output-on-failure -j "$jobs" || status=$?
if [ "$sanitizers" = yes ]; then
    JOBS=$jobs tests/sanitizers/run.sh all || status=1
fi
exit $status
