#!/usr/bin/env bash
# The two commands of the README:
#   tools/dev.sh demo   install what is missing, build, run fovead on its simulated tracker and
#                       the SDK demo (live gaze + latency, then foveated frames on lavapipe)
#   tools/dev.sh test   install what is missing, build, run the whole test suite: ctest, then the
#                       ring/daemon tests under ASan+UBSan and TSan, then the fuzz smoke runs
# Build trees live in build/ (main, asan, tsan, fuzz). Set FOVEA_JOBS to change parallelism.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
jobs="${FOVEA_JOBS:-$(nproc)}"

configure() {  # dir, extra cmake args...
    local dir="$1"; shift
    cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" > "$dir.configure.log" 2>&1 \
        || { cat "$dir.configure.log"; exit 1; }
}
configure_build() { configure "$@"; cmake --build "$1" -j "$jobs"; }
build_targets() {  # dir, targets...: sanitizer trees build only what their test labels run
    local dir="$1"; shift
    cmake --build "$dir" -j "$jobs" --target "$@"
}
# Executables behind the labels the sanitizer runs select (tests not built are skipped by ctest).
asan_targets=(fovead fovea ring_test daemon_config_test daemon_integration_test test_drivers_sim
    test_drivers_serial test_drivers_gazepoint test_drivers_replay gaze_unit_tests hid_parser_test
    usb_test record_tests frame_latency_test frame_latency_daemon_test daemon_calibration_test
    daemon_calibration_integration_test test_drivers_sim_calibration)
tsan_targets=(fovead fovea ring_test daemon_config_test daemon_integration_test frame_latency_test
    frame_latency_daemon_test daemon_calibration_test)

step() { printf '\n== %s ==\n' "$*"; }

stop_demo_daemon() {
    if [ -n "${demo_daemon_pid:-}" ]; then
        kill "$demo_daemon_pid" 2>/dev/null || true
        wait "$demo_daemon_pid" 2>/dev/null || true
    fi
}

run_demo() {
    configure_build build/main
    local bin=build/main instance="demo-$$"
    export FOVEA_RUNTIME_DIR="${FOVEA_RUNTIME_DIR:-/tmp/fovea-demo-$(id -u)}"
    step "fovead --instance $instance (simulated tracker)"
    "$bin/daemon/fovead" --instance "$instance" &
    demo_daemon_pid=$!  # global: the EXIT trap runs after this function has returned
    trap stop_demo_daemon EXIT
    step "live gaze: fovea watch (every 100th sample of 2000)"
    "$bin/tools/fovea" --instance "$instance" watch --count 20 --every 100
    step "fovea status"
    "$bin/tools/fovea" --instance "$instance" status
    if "$bin/tools/fovea" --help 2>/dev/null | grep -q '^ *latency'; then
        step "per-hop latency"
        "$bin/tools/fovea" --instance "$instance" latency --once
    fi
    if "$bin/tools/fovea" --help 2>/dev/null | grep -q '^ *demo'; then
        step "SDK demo: foveated frames on lavapipe from live gaze"
        "$bin/tools/fovea" --instance "$instance" demo --frames "${FOVEA_DEMO_FRAMES:-4}" --out build/demo
        step "per-hop latency with the demo's render hops (sdk rows)"
        "$bin/tools/fovea" --instance "$instance" latency --once
    fi
    step "done"
}

run_tests() {
    step "build (RelWithDebInfo)"
    configure_build build/main
    step "ctest: whole suite"
    (cd build/main && ctest --output-on-failure -j "$jobs" --timeout 900)

    step "ASan+UBSan: ring, daemon, drivers, gaze"
    configure build/asan -DFOVEA_SANITIZE=address,undefined -DFOVEA_BUILD_VK=OFF
    build_targets build/asan "${asan_targets[@]}"
    (cd build/asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
        ctest --output-on-failure -j "$jobs" -L 'ring|daemon|drivers|gaze|hid|usb|record' -LE slow)

    step "TSan: ring and daemon"
    configure build/tsan -DFOVEA_SANITIZE=thread -DFOVEA_BUILD_VK=OFF
    build_targets build/tsan "${tsan_targets[@]}"
    (cd build/tsan && TSAN_OPTIONS=halt_on_error=1 \
        ctest --output-on-failure -j "$jobs" -L 'ring|daemon' -LE slow)

    if [ -f tests/fuzz/CMakeLists.txt ]; then
        step "fuzz smoke (libFuzzer, clang)"
        CC=clang CXX=clang++ configure build/fuzz -DFOVEA_FUZZ=ON -DFOVEA_BUILD_VK=OFF \
            -DFOVEA_BUILD_TESTS=ON
        mapfile -t fuzzers < <(cd tests/fuzz && ls fuzz_*.cpp | sed 's/\.cpp$//')
        build_targets build/fuzz "${fuzzers[@]}"
        (cd build/fuzz && ctest --output-on-failure -L fuzz)
    fi
    step "all tests passed"
}

case "${1:-}" in
    demo) tools/setup/setup.sh; mkdir -p build; run_demo ;;
    test) tools/setup/setup.sh; mkdir -p build; run_tests ;;
    *) echo "usage: tools/dev.sh demo|test" >&2; exit 2 ;;
esac
