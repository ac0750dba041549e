#!/usr/bin/env bash
# The sanitizer and fuzzer jobs (docs/testing.md), each in a build directory
# of its own beside the plain build; CI runs all three after the plain suite
# (./setup.sh test with CI=true).
#
#   tests/sanitizers/run.sh asan   the test suite under AddressSanitizer and
#                                  UndefinedBehaviorSanitizer (build-asan/)
#   tests/sanitizers/run.sh tsan   the threaded tests under ThreadSanitizer (build-tsan/)
#   tests/sanitizers/run.sh fuzz   the libFuzzer targets, FUZZ_SECONDS (default 60) each (build-fuzz/)
#   tests/sanitizers/run.sh all    the three, then a table of their build and run times
#
# Environment: JOBS (default: number of cores), FUZZ_SECONDS. The packages
# (clang-14, libclang-rt-14-dev for libFuzzer) are ./setup.sh's to install.
set -euo pipefail
cd "$(dirname "$0")/../.."
here=tests/sanitizers
jobs=${JOBS:-$(nproc)}
fuzz_seconds=${FUZZ_SECONDS:-60}
launcher=()
# A compiler cache, when there is one, only shortens rebuilds.
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# -O2 with line tables: reports name files and lines, and the engine's
# Eigen code stays fast enough for the tests' own time limits (at -O1,
# test_time_of_impact's brute-force search passes Qt Test's 300 s per
# function under ASan). The Python module is not built: Debian's python3 is
# not instrumented, so an instrumented module needs the sanitizer's runtime
# preloaded into python3 (LD_PRELOAD), and there ASan's exception
# interceptor aborts on the exceptions pybind11 throws and catches. The
# Python suites (python_*) run in the plain job only; BatchWorld's threads
# are tested in C++ (test_batch_world) under both sanitizers.
common=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g1" -DVSSIM_PYTHON=OFF
        "${launcher[@]}")
times=()

# "job step seconds" lines for the summary.
timed() {
    local label=$1
    shift
    local start=$SECONDS status=0
    "$@" || status=$?
    times+=("$label $((SECONDS - start)) s")
    echo "sanitizers: $label took $((SECONDS - start)) s (status $status)" >&2
    return $status
}

asan() {
    local b=build-asan
    cmake -S . -B $b "${common[@]}" \
        "-DCMAKE_CXX_FLAGS=-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer" >/dev/null
    timed "asan build" cmake --build $b -j "$jobs" || return 1
    # package_deb (label package) is left out: it repackages the same
    # program and runs it as the plain job does, for minutes.
    # The desktop app's two tests under X (test_gui, bench_gui_smoke) run
    # without leak detection: their leak reports lie in system libraries
    # (libdbus-1, which Qt's GUI library uses, and a library unloaded before
    # the report, so that its frames cannot be named), whose stacks the
    # fast unwinder cuts short, and the exact unwinder
    # (fast_unwind_on_malloc=0) makes test_gui pass its 300 s limit. Our
    # own widgets are leak-checked by the offscreen UI tests.
    local gui='^(test_gui|bench_gui_smoke)$' status=0
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    ASAN_OPTIONS="detect_leaks=1" \
        timed "asan run" ctest --test-dir $b --output-on-failure -j "$jobs" -LE package -E "$gui" || status=1
    ASAN_OPTIONS="detect_leaks=0" \
        timed "asan run (GUI)" ctest --test-dir $b --output-on-failure -j "$jobs" -R "$gui" || status=1
    return $status
}

# The tests whose code runs on more than one thread: those that start the
# engine thread (realtime/engine_thread.h) beside the TCP server, FIRASim's
# server and VSSReferee's bridge, the batched worlds' workers; and the
# engine loop those threads run.
tsan_tests=(test_engine_loop test_server test_firasim test_firasim_wheel_speeds test_vssref test_batch_world)

tsan() {
    local b=build-tsan
    cmake -S . -B $b "${common[@]}" "-DCMAKE_CXX_FLAGS=-fsanitize=thread -fno-omit-frame-pointer" >/dev/null
    # test_firasim runs the vssim program too (add_dependencies).
    timed "tsan build" cmake --build $b -j "$jobs" --target "${tsan_tests[@]}" || return 1
    local regex
    regex="^($(IFS='|'; echo "${tsan_tests[*]}"))\$"
    # ignore_noninstrumented_modules=1: Qt, OpenCV, libproxy and the rest
    # are not instrumented, so TSan sees none of their own loads and stores
    # and none of the ordering their futex-based mutexes give (Qt's queued
    # signals, its post-event list, QThread::wait), but it did see the libc
    # calls they make (memmove, strlen, free): reports between two such
    # calls were all false (Qt's post-event list, Qt's libproxy thread
    # handing a proxy query back, Qt Test's watchdog ending). Our own code's
    # accesses are all checked. die_after_fork=0: QProcess's child of a
    # multi-threaded test (the vssim program started by test_firasim) only
    # execs, so it is let live.
    TSAN_OPTIONS="suppressions=$PWD/$here/tsan.supp:ignore_noninstrumented_modules=1:die_after_fork=0:second_deadlock_stack=1:halt_on_error=1" \
        timed "tsan run" ctest --test-dir $b --output-on-failure -j "$jobs" -R "$regex"
}

fuzz() {
    local b=build-fuzz
    # -O1, as libFuzzer's documentation builds: comparisons stay visible to its tracing.
    cmake -S . -B $b "${common[@]}" "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" -DCMAKE_CXX_COMPILER=clang++-14 \
        -DVSSIM_FUZZ=ON -DBUILD_TESTING=OFF >/dev/null
    timed "fuzz build" cmake --build $b -j "$jobs" --target fuzz || return 1
    # JOBS fuzzers at a time, each on one core; the crashes of an earlier run go.
    rm -rf $b/crashes
    local start=$SECONDS status=0 name work running=0
    for name in fuzz_scene fuzz_client_messages fuzz_firasim_packet fuzz_vssref_placement; do
        # New inputs go to a scratch corpus; the committed seeds are read only.
        # A crash leaves its input in $b/crashes/ (a regression test's input).
        work=$b/corpus/$name
        mkdir -p "$work" $b/crashes
        if [ $running -ge "$jobs" ]; then
            wait -n || status=1
            running=$((running - 1))
        fi
        echo "sanitizers: $name for $fuzz_seconds s" >&2
        "$b/fuzz/$name" -max_total_time="$fuzz_seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
            -artifact_prefix="$b/crashes/$name-" "$work" "fuzz/corpus/$name" 2>"$b/$name.log" &
        running=$((running + 1))
    done
    while [ $running -gt 0 ]; do
        wait -n || status=1
        running=$((running - 1))
    done
    for name in fuzz_scene fuzz_client_messages fuzz_firasim_packet fuzz_vssref_placement; do
        # The last lines say what was found; the whole log stays in $b.
        grep -E '^(stat::number_of_executed_units|stat::peak_rss_mb)|DONE' "$b/$name.log" | sed "s/^/$name: /" >&2 ||
            tail -n 60 "$b/$name.log" >&2
    done
    if ls $b/crashes/* >/dev/null 2>&1; then
        echo "sanitizers: the fuzzers found inputs that fail, in $b/crashes/:" >&2
        ls $b/crashes >&2
        status=1
    fi
    times+=("fuzz run $((SECONDS - start)) s")
    return $status
}

status=0
case "${1:-}" in
    asan) asan ;;
    tsan) tsan ;;
    fuzz) fuzz ;;
    all)
        # Every job runs even when one fails; the status says whether any did.
        asan || status=1
        tsan || status=1
        fuzz || status=1
        ;;
    *) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
printf 'sanitizers: %s\n' "${times[@]}" >&2
exit $status
