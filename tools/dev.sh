#!/usr/bin/env bash
# The two commands of the README:
#   tools/dev.sh demo   install what is missing, build, run fovead on its simulated tracker and
#                       the SDK demo (live gaze + latency, then foveated frames on lavapipe)
#   tools/dev.sh test   install what is missing, build, run the whole test suite but label "slow":
#                       ctest, the 2-minute soak alone, OpenXR through Monado, then the labelled
#                       suite under ASan+UBSan, the ring/daemon labels under TSan (each tree
#                       builds what its labels select and fails on a test not built), then every
#                       fuzz target for 30 s from seed 1; prints each step's wall time
#   tools/dev.sh asan|tsan|fuzz   just that step (what CI runs for it)
# Build trees live in build/ (main, asan, tsan, fuzz). Set FOVEA_JOBS to change parallelism.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
jobs="${FOVEA_JOBS:-$(nproc)}"

configure() {  # dir, extra cmake args...
    local dir="$1"; shift
    cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFOVEA_WERROR=ON "$@" \
        > "$dir.configure.log" 2>&1 \
        || { cat "$dir.configure.log"; exit 1; }
}
configure_build() { configure "$@"; cmake --build "$1" -j "$jobs"; }
# dir, cmake args...: a second configure with the same arguments must leave every build command
# as it was, or each later `tools/dev.sh` run would rebuild what those commands make.
require_same_commands_after_configure() {
    local dir="$1" before
    before=$(ninja -C "$dir" -t commands)
    configure "$@"
    if [ "$(ninja -C "$dir" -t commands)" != "$before" ]; then
        echo "a second configure of $dir changed these build commands:" >&2
        diff <(printf '%s\n' "$before") <(ninja -C "$dir" -t commands) | head -20 >&2
        exit 1
    fi
}
build_targets() {  # dir, targets...
    local dir="$1"; shift
    cmake --build "$dir" -j "$jobs" --target "$@"
}

# What each sanitizer tree runs, as ctest -L / -LE regular expressions over a test's labels (one
# comma-joined label per test, e.g. "integration,daemon"). ASan+UBSan: the whole labelled suite,
# the Vulkan side included (libfovea_vk, the demo, the bench, GPU FLIP on lavapipe; in that tree
# libfovea_vk keeps the drivers the loader opens mapped: sdk/sanitizer/keep_drivers_loaded.cpp),
# except the slow runs (their CI variants are labelled without "slow"), the packaging scripts
# (they install and package the tree; what runs in them is built against the install without the
# sanitizer) and the soak (it times a release fovead against fixed budgets; it runs once, alone,
# in build/main). TSan: the code that runs threads against each other: ring, daemon (calibration
# included), client.
asan_labels='.'
asan_exclude='slow|packaging|soak'
tsan_labels='ring|daemon'
tsan_exclude='slow|packaging|soak'

# Test targets whose labels match regex $2 and not $3, from the manifest CMake writes into the
# build tree $1 (tests/CMakeLists.txt: "target TAB labels TAB executable" per gtest discovery).
labelled_targets() {
    awk -F'\t' -v inc="$2" -v exc="$3" '$2 ~ inc && (exc == "" || $2 !~ exc) { print $1 }' \
        "$1/fovea_tests.tsv" | sort -u
}
# Fails when a selected test executable was not built: ctest would list it as an unlabelled
# <target>_NOT_BUILT test, which its -L filter then drops without a word.
require_built() {  # dir, include, exclude
    local missing
    missing=$(awk -F'\t' -v inc="$2" -v exc="$3" \
        '$2 ~ inc && (exc == "" || $2 !~ exc) && system("test -x \"" $3 "\"") != 0 { print $1 }' \
        "$1/fovea_tests.tsv" | sort -u | tr '\n' ' ')
    if [ -n "$missing" ]; then
        echo "FAIL: selected tests not built in $1: $missing" >&2
        exit 1
    fi
}
# Configures tree $2, builds what the selected labels need (their executables, and fovead and the
# fovea CLI that the integration tests run), checks all of it was built, then runs exactly those
# labels. Each part is its own timed step.
run_labelled() {  # name, dir, include, exclude, cmake args..., --, environment for ctest...
    local name="$1" dir="$2" inc="$3" exc="$4" targets cmake_args=()
    shift 4
    while [ "$#" -gt 0 ] && [ "$1" != "--" ]; do cmake_args+=("$1"); shift; done
    shift
    step "$name: configure $dir"
    configure "$dir" "${cmake_args[@]}"
    mapfile -t targets < <(labelled_targets "$dir" "$inc" "$exc")
    if [ "${#targets[@]}" -eq 0 ]; then
        echo "FAIL: no test in $dir has labels matching '$inc'" >&2
        exit 1
    fi
    step "$name: build ${#targets[@]} test executables, fovead, fovea"
    echo "${targets[*]}"
    build_targets "$dir" fovead fovea "${targets[@]}"
    require_built "$dir" "$inc" "$exc"
    step "$name: ctest -L '$inc' -LE '$exc'"
    (cd "$dir" && env "$@" ctest --output-on-failure --no-tests=error -j "$jobs" --timeout 900 \
        -L "$inc" -LE "$exc")
}

# Every step prints its wall time and the CPU time of the processes it ran when the next one
# starts, and the table of all of them at exit (also after a failure), so the CI budget (~40 min
# on 2 cores) is measured, not guessed: on a loaded machine CPU seconds / jobs estimates the wall
# time of an idle one.
step_name="" step_start=$SECONDS step_cpu=0 run_start=$SECONDS step_times=()
cpu_file="${TMPDIR:-/tmp}/fovea-dev-times.$$"
children_cpu() {  # sets $cpu: user + system seconds of every finished child process so far
    times > "$cpu_file"  # a builtin: in this shell, not in a subshell that has no children
    cpu=$(awk 'NR == 2 { gsub(/s/, ""); split($1, u, "m"); split($2, y, "m");
                         print int(u[1] * 60 + u[2] + y[1] * 60 + y[2]) }' "$cpu_file")
    rm -f "$cpu_file"
}
end_step() {
    if [ -n "$step_name" ]; then
        local took=$((SECONDS - step_start)) cpu
        children_cpu
        cpu=$((cpu - step_cpu))
        printf '== %s: %d s wall, %d s CPU ==\n' "$step_name" "$took" "$cpu"
        step_times+=("$(printf '%6d s %6d s CPU  %s' "$took" "$cpu" "$step_name")")
    fi
    step_name=""
}
step() {
    end_step
    local cpu
    children_cpu
    step_name="$*" step_start=$SECONDS step_cpu=$cpu
    printf '\n== %s ==\n' "$*"
}
print_step_times() {
    end_step
    [ "${#step_times[@]}" -gt 0 ] || return 0
    printf '\n== step times ==\n'
    printf '%s\n' "${step_times[@]}"
    local cpu
    children_cpu
    printf '%6d s %6d s CPU  total\n' "$((SECONDS - run_start))" "$cpu"
}

stop_demo_daemon() {
    if [ -n "${demo_daemon_pid:-}" ]; then
        kill "$demo_daemon_pid" 2>/dev/null || true
        wait "$demo_daemon_pid" 2>/dev/null || true
    fi
}

run_demo() {
    configure_build build/main "${main_flags[@]}"
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

# The OpenXR eye gaze layer through a real runtime: the vendored Monado, built once and cached
# outside the clone (tests/openxr/build_monado.sh), then the `openxr` label with it, then the
# layer's xrLocateSpace benchmark (table + CSV). Skipped where ../shared/vendor/monado is absent.
run_openxr_checks() {
    step "OpenXR: eye gaze layer through the vendored Monado"
    local manifest rc=0
    manifest=$(FOVEA_JOBS="$jobs" tests/openxr/build_monado.sh) || rc=$?
    if [ "$rc" -eq 77 ]; then return 0; fi
    [ "$rc" -eq 0 ] || exit "$rc"
    (cd build/main && FOVEA_MONADO_RUNTIME_JSON="$manifest" ctest --output-on-failure -L openxr)
    FOVEA_MONADO_RUNTIME_JSON="$manifest" build/main/tests/openxr/openxr_locate_bench \
        --csv build/openxr_locate_bench.csv 2> build/openxr_locate_bench.log
}

run_main_suite() {
    step "format (clang-format, .clang-format)"
    tools/check_format.sh
    step "build (RelWithDebInfo, warnings as errors)"
    configure_build build/main "${main_flags[@]}"
    step "configure again: no build command changes (so a later demo rebuilds nothing)"
    require_same_commands_after_configure build/main "${main_flags[@]}"
    step "ctest: whole suite but 'slow' and the soak"
    require_built build/main . ''
    (cd build/main && ctest --output-on-failure -j "$jobs" --timeout 900 -LE 'slow|soak')
}

# The soak (tests/soak) holds fovead to latency and loss budgets: it runs alone, not beside -j
# tests that would take its 2 cores.
run_soak() {
    step "soak: 2 minutes"
    (cd build/main && ctest --output-on-failure --no-tests=error -L soak)
}

# Every tree keeps line tables only (-g1): file:line and function names in backtraces and
# sanitizer reports, without the type and variable info of -g that costs ~18 % of compile time.
# Sanitizer and fuzz trees compile at -O1 (what the sanitizers' docs advise): half the compiler
# time of -O2 (event_detector.cpp under ASan: 4.6 s against 8.3 s CPU), the CI's largest cost.
main_flags=(-DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG"
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG")
sanitizer_flags=(-DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG"
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG")

run_asan() {
    run_labelled "ASan+UBSan" build/asan "$asan_labels" "$asan_exclude" "${sanitizer_flags[@]}" \
        -DFOVEA_SANITIZE=address,undefined -DFOVEA_BUILD_VK=ON -- \
        ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions="$root/tests/sanitizers/lsan.supp" \
        UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
}

run_tsan() {
    run_labelled "TSan" build/tsan "$tsan_labels" "$tsan_exclude" "${sanitizer_flags[@]}" \
        -DFOVEA_SANITIZE=thread -DFOVEA_BUILD_VK=OFF -- TSAN_OPTIONS=halt_on_error=1
}

run_fuzz_smoke() {
    step "fuzz: configure build/fuzz (libFuzzer, clang)"
    CC=clang CXX=clang++ configure build/fuzz "${sanitizer_flags[@]}" -DFOVEA_FUZZ=ON \
        -DFOVEA_BUILD_VK=OFF -DFOVEA_BUILD_TESTS=ON
    local fuzzers
    mapfile -t fuzzers < <(cd tests/fuzz && ls fuzz_*.cpp | sed 's/\.cpp$//')
    step "fuzz: build ${#fuzzers[@]} targets"
    build_targets build/fuzz "${fuzzers[@]}"
    step "fuzz smoke: every target 30 s from seed 1, two at a time"
    (cd build/fuzz && ctest --output-on-failure --no-tests=error -j 2 -L fuzz)
}

run_tests() {
    run_main_suite
    run_soak
    run_openxr_checks
    run_asan
    run_tsan
    run_fuzz_smoke
    step "all tests passed"
}

case "${1:-}" in
    demo) tools/setup/setup.sh; mkdir -p build; run_demo ;;
    test) tools/setup/setup.sh; mkdir -p build; trap print_step_times EXIT; run_tests ;;
    asan | tsan | fuzz)
        mkdir -p build; trap print_step_times EXIT
        case "$1" in asan) run_asan ;; tsan) run_tsan ;; fuzz) run_fuzz_smoke ;; esac ;;
    *) echo "usage: tools/dev.sh demo|test|asan|tsan|fuzz" >&2; exit 2 ;;
esac
