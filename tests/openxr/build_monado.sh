#!/usr/bin/env bash
# Build the vendored Monado (../shared/vendor/monado) as test infrastructure: only the in-process
# OpenXR runtime with the null compositor and the simulated HMD, nothing installed anywhere.
# The build is cached outside the clone, keyed by the sources and the options below, so a second
# run does no work:  ${XDG_CACHE_HOME:-$HOME/.cache}/fovea/monado-<key>/
# Prints the runtime manifest's path on stdout (the file XR_RUNTIME_JSON takes).
# Exit 0: built (or cached); 77: the vendored folder is absent (skip); anything else: failure.
#   usage: tests/openxr/build_monado.sh [SOURCE_DIR]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
src="${1:-${FOVEA_MONADO_SOURCE:-$here/../../../shared/vendor/monado}}"
jobs="${FOVEA_JOBS:-$(nproc)}"

if [ ! -f "$src/CMakeLists.txt" ]; then
    echo "monado: no vendored source at $src (see ../shared/vendor/README.md): OpenXR runtime tests skipped" >&2
    exit 77
fi
src="$(cd "$src" && pwd)"

# Everything but the in-process runtime is off: no drivers besides the simulated HMD, no service,
# no IPC, no windowed compositor, no GUI, no tests or samples.
options=(
    -DCMAKE_BUILD_TYPE=Release
    -DBUILD_TESTING=OFF -DXRT_BUILD_SAMPLES=OFF
    -DXRT_FEATURE_COMPOSITOR_MAIN=OFF -DXRT_FEATURE_COMPOSITOR_NULL=ON
    -DXRT_FEATURE_SERVICE=OFF -DXRT_FEATURE_IPC=OFF -DXRT_FEATURE_STEAMVR_PLUGIN=OFF
    -DXRT_OPENXR_INSTALL_ACTIVE_RUNTIME=OFF -DXRT_FEATURE_RENDERDOC=OFF
    -DXRT_FEATURE_TRACING=OFF -DXRT_FEATURE_WINDOW_PEEK=OFF -DXRT_FEATURE_SLAM=OFF
    -DXRT_HAVE_OPENGL=OFF -DXRT_HAVE_OPENGLES=OFF -DXRT_HAVE_EGL=OFF -DXRT_HAVE_SDL2=OFF
    -DXRT_HAVE_WAYLAND=OFF -DXRT_HAVE_XCB=OFF -DXRT_HAVE_XLIB=OFF -DXRT_HAVE_XRANDR=OFF
    -DXRT_HAVE_DBUS=OFF -DXRT_HAVE_SYSTEMD=OFF -DXRT_HAVE_OPENCV=OFF -DXRT_HAVE_HIDAPI=OFF
    -DXRT_HAVE_LIBUSB=OFF -DXRT_HAVE_LIBUVC=OFF -DXRT_HAVE_FFMPEG=OFF -DXRT_HAVE_GST=OFF
    -DXRT_HAVE_JPEG=OFF -DXRT_HAVE_BLUETOOTH=OFF -DXRT_HAVE_PERCETTO=OFF
)
for d in ANDROID ARDUINO DAYDREAM DEPTHAI EUROC HANDTRACKING TWRAP HDK HYDRA ILLIXR NS OHMD \
    OPENGLOVES PSMV PSVR QWERTY REALSENSE REMOTE RIFT_S SURVIVE ULV2 VF VIVE WMR SIMULAVR; do
    options+=("-DXRT_BUILD_DRIVER_$d=OFF")
done
options+=(-DXRT_BUILD_DRIVER_SIMULATED=ON)

# Keyed by the sources, the options and this script (which writes part of the build).
key="$( (cd "$src" && find . -type f ! -path './.git/*' -print0 | sort -z | xargs -0 sha1sum;
         printf '%s\n' "${options[@]}"; cat "$here/build_monado.sh") | sha1sum | cut -c1-12)"
cache="${XDG_CACHE_HOME:-$HOME/.cache}/fovea/monado-$key"
manifest="$cache/build/openxr_monado-dev.json"
mkdir -p "$cache"

# Several test runs may share the cache: one builds, the others wait for it.
exec 9>"$cache/lock"
flock 9
if [ ! -f "$cache/done" ]; then
    echo "monado: building the in-process runtime into $cache (once)" >&2
    start=$(date +%s)
    # The snapshot lacks the header upstream keeps in src/xrt/include/xrt/ that names the OS; the
    # build tree's include directory is on Monado's include path (included as "xrt/..." and,
    # from its neighbours, as "..."), so ours goes there.
    if [ ! -f "$src/src/xrt/include/xrt/xrt_config_os.h" ]; then
        inc="$cache/build/src/xrt/include"
        mkdir -p "$inc/xrt"
        printf '%s\n' '#pragma once' \
            '/* Written by fovea tests/openxr/build_monado.sh (absent from the snapshot). */' \
            '#if defined(__ANDROID__)' '#define XRT_OS_ANDROID' '#define XRT_OS_LINUX' \
            '#define XRT_OS_UNIX' '#elif defined(__linux__)' '#define XRT_OS_LINUX' \
            '#define XRT_OS_UNIX' '#elif defined(_WIN32)' '#define XRT_OS_WINDOWS' '#endif' \
            > "$inc/xrt/xrt_config_os.h"
        cp "$inc/xrt/xrt_config_os.h" "$inc/xrt_config_os.h"
    fi
    cmake -S "$src" -B "$cache/build" -G Ninja "${options[@]}" > "$cache/configure.log" 2>&1 \
        || { tail -n 40 "$cache/configure.log" >&2; exit 1; }
    cmake --build "$cache/build" -j "$jobs" --target openxr_monado > "$cache/build.log" 2>&1 \
        || { tail -n 40 "$cache/build.log" >&2; exit 1; }
    [ -f "$manifest" ] || { echo "monado: built, but $manifest is missing" >&2; exit 1; }
    echo "monado: built in $(( $(date +%s) - start )) s" >&2
    touch "$cache/done"
fi
echo "$manifest"
