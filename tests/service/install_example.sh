#!/bin/bash
# Install the build into a temporary prefix, check the layout, start the installed fovead,
# then build the external example (sdk/examples/gaze_print) with find_package(fovea) and with
# pkg-config and run both against it. abi: FOVEA_RING_ABI_VERSION as CMake read it from ring.h.
set -eu
build=$1 src=$2 abi=$3
tmp=$(mktemp -d /tmp/fvinst.XXXXXX)
daemon_pid=
cleanup() {
    if [ -n "$daemon_pid" ]; then kill "$daemon_pid" 2>/dev/null || true; wait "$daemon_pid" 2>/dev/null || true; fi
    rm -rf "$tmp"
}
trap cleanup EXIT
prefix=$tmp/prefix
fail() { echo "FAIL: $*"; exit 1; }

cmake --install "$build" --prefix "$prefix" > "$tmp/install.log" || { cat "$tmp/install.log"; fail "cmake --install"; }
libdir=$(dirname "$(find "$prefix" -name 'libfovea.so.*' -type f | head -1)")
[ -d "$libdir" ] || fail "libfovea.so not installed"
for f in sbin/fovead bin/fovea lib/systemd/system/fovead.service lib/systemd/system/fovead.socket \
         lib/sysusers.d/fovea.conf lib/udev/rules.d/70-fovea.rules etc/fovea/fovead.toml \
         include/fovea/client.h include/fovea/ring.h include/fovea/client.hpp; do
    [ -e "$prefix/$f" ] || fail "$f not installed"
done
for f in libfovea.so "libfovea.so.$abi" cmake/fovea/foveaConfig.cmake cmake/fovea/foveaConfigVersion.cmake \
         cmake/fovea/foveaTargets.cmake pkgconfig/fovea.pc; do
    [ -e "$libdir/$f" ] || fail "$libdir/$f not installed"
done
soname=$(objdump -p "$libdir/libfovea.so" | awk '/SONAME/ {print $2}')
[ "$soname" = "libfovea.so.$abi" ] || fail "SONAME is '$soname', want libfovea.so.$abi (ring ABI $abi)"
grep -q "^ExecStart=.*/sbin/fovead" "$prefix/lib/systemd/system/fovead.service" || fail "ExecStart"
"$prefix/sbin/fovead" --config "$prefix/etc/fovea/fovead.toml" --check-config || fail "example fovead.toml"

# The installed daemon, on its own instance and runtime directory.
instance=inst$$
export FOVEA_RUNTIME_DIR=$tmp/run
mkdir -p "$FOVEA_RUNTIME_DIR"
"$prefix/sbin/fovead" --instance "$instance" > "$tmp/fovead.log" 2>&1 &
daemon_pid=$!
for _ in $(seq 100); do
    "$prefix/bin/fovea" --instance "$instance" status > /dev/null 2>&1 && break
    sleep 0.05
done
"$prefix/bin/fovea" --instance "$instance" status > /dev/null || { cat "$tmp/fovead.log"; fail "installed fovead did not come up"; }

check_output() {  # $1: name, $2: file
    local n
    n=$(grep -c -E '^[0-9]+ [0-9.]+ [0-9.-]+ [0-9.-]+ [a-z]+$' "$2" || true)
    [ "$n" -eq 50 ] || { cat "$2"; fail "$1: $n sample lines, want 50"; }
    grep -q "^# fovea ABI $abi, instance $instance" "$2" || fail "$1: no header line"
    echo "OK: $1 read 50 samples"
}

# 1) CMake: find_package(fovea) -> fovea::client
cmake -S "$src/sdk/examples/gaze_print" -B "$tmp/ex-cmake" -DCMAKE_PREFIX_PATH="$prefix" \
    > "$tmp/ex-cmake.log" 2>&1 || { cat "$tmp/ex-cmake.log"; fail "example: cmake configure"; }
cmake --build "$tmp/ex-cmake" > "$tmp/ex-cmake-build.log" 2>&1 || { cat "$tmp/ex-cmake-build.log"; fail "example: cmake build"; }
"$tmp/ex-cmake/gaze_print" --instance "$instance" --count 50 > "$tmp/out-cmake" || fail "cmake-built example failed"
check_output find_package "$tmp/out-cmake"

# 2) pkg-config
PKG_CONFIG_PATH="$libdir/pkgconfig" make -s -C "$src/sdk/examples/gaze_print" BUILD="$tmp" \
    > "$tmp/ex-make.log" 2>&1 || { cat "$tmp/ex-make.log"; fail "example: make with pkg-config"; }
"$tmp/gaze_print" --instance "$instance" --count 50 > "$tmp/out-pc" || fail "pkg-config-built example failed"
check_output pkg-config "$tmp/out-pc"

# Both binaries use the installed libfovea, not the build tree's.
for exe in "$tmp/ex-cmake/gaze_print" "$tmp/gaze_print"; do
    used=$(ldd "$exe" | awk -v so="libfovea.so.$abi" '$1 == so {print $3}')
    [ -n "$used" ] && [ "$(realpath "$used")" = "$(realpath "$libdir/libfovea.so.$abi")" ] || { ldd "$exe"; fail "$exe does not use the installed libfovea"; }
done
"$prefix/bin/fovea" --instance "$instance" status > /dev/null
kill -TERM "$daemon_pid"; wait "$daemon_pid"; rc=$?; daemon_pid=
[ $rc -eq 0 ] || fail "installed fovead exited $rc on SIGTERM"
echo "OK: installed into a temporary prefix; example built and ran with find_package and pkg-config"
