#!/bin/bash
# Installs the build into a temporary prefix and uses the Vulkan module from outside, as a host
# does: the layout (libfovea_vk.so with glslang inside and not exported, the GLSL contract,
# fovea-vk.pc), a CMake project with find_package(fovea) + fovea_check_shading() that renders a
# frame, the same check failing on broken shading, and a pkg-config build.
set -eu
build=$1 src=$2
tmp=$(mktemp -d /tmp/fvvk.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
fail() { echo "FAIL: $*"; exit 1; }

cmake --install "$build" --prefix "$prefix" > "$tmp/install.log" || { cat "$tmp/install.log"; fail "cmake --install"; }
lib=$(find "$prefix" -name 'libfovea_vk.so.*' -type f | head -1)
[ -n "$lib" ] || fail "libfovea_vk.so not installed"
libdir=$(dirname "$lib")
for f in include/fovea/vk/glsl/fovea_frame.glsl include/fovea/vk/glsl/fovea_acuity.glsl \
         include/fovea/vk/glsl/fovea_gbuffer.glsl \
         include/fovea/vk/glsl/fovea_check.shade.comp include/fovea/vk/projection.hpp; do
    [ -e "$prefix/$f" ] || fail "$f not installed"
done
for f in pkgconfig/fovea-vk.pc cmake/fovea/foveaShading.cmake; do
    [ -e "$libdir/$f" ] || fail "$libdir/$f not installed"
done
[ -z "$(find "$prefix" -name 'libfovea_vk.a')" ] || fail "static libfovea_vk.a installed"
# glslang is inside the shared library, local: no host links it, none clashes with a host's own.
exported=$(nm -D --defined-only "$lib" | c++filt | grep -c 'glslang::T[A-Z][a-zA-Z]*::[a-z]' || true)
[ "$exported" -eq 0 ] || fail "libfovea_vk.so exports $exported glslang functions"
nm -D --undefined-only "$lib" | grep -q glslang && fail "libfovea_vk.so needs glslang at run time"
echo "OK: layout ($(du -k "$lib" | cut -f1) KiB libfovea_vk.so)"

cmake -S "$src/tests/vk_hosts/consumer" -B "$tmp/c" -DCMAKE_PREFIX_PATH="$prefix" \
    > "$tmp/c.log" 2>&1 || { cat "$tmp/c.log"; fail "consumer: configure"; }
cmake --build "$tmp/c" > "$tmp/cb.log" 2>&1 || { cat "$tmp/cb.log"; fail "consumer: build"; }
grep -q "Checking .*shading.glsl against the Fovea shading contract" "$tmp/cb.log" \
    || { cat "$tmp/cb.log"; fail "consumer: shading not checked at build time"; }
out=$("$tmp/c/consumer") || fail "consumer did not run"
echo "$out" | grep -q '^consumer ok ' || fail "consumer printed '$out'"
echo "OK: find_package(fovea) consumer: $out"

cmake -S "$src/tests/vk_hosts/consumer" -B "$tmp/bad" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCONSUMER_SHADING="$src/tests/vk_hosts/consumer/bad_shading.glsl" > "$tmp/bad.log" 2>&1 \
    || fail "bad consumer: configure"
if cmake --build "$tmp/bad" --target consumer_shading_check > "$tmp/badb.log" 2>&1; then
    fail "fovea_check_shading() accepted broken shading"
fi
grep -q "undefined_name" "$tmp/badb.log" || { cat "$tmp/badb.log"; fail "check error does not name the fault"; }
echo "OK: fovea_check_shading() rejects broken shading at build time"

PKG_CONFIG_PATH="$libdir/pkgconfig" pkg-config --exists fovea-vk || fail "pkg-config fovea-vk"
glsl=$(PKG_CONFIG_PATH="$libdir/pkgconfig" pkg-config --variable=glsldir fovea-vk)
[ -f "$glsl/fovea_frame.glsl" ] || fail "glsldir '$glsl' has no fovea_frame.glsl"
# shellcheck disable=SC2046
c++ -std=c++20 -DCONSUMER_SHADING="\"$src/tests/vk_hosts/consumer/shading.glsl\"" \
    "$src/tests/vk_hosts/consumer/consumer.cpp" -o "$tmp/consumer-pc" \
    $(PKG_CONFIG_PATH="$libdir/pkgconfig" pkg-config --cflags --libs fovea-vk) \
    -Wl,-rpath,"$libdir" || fail "pkg-config build"
"$tmp/consumer-pc" | grep -q '^consumer ok ' || fail "pkg-config consumer did not run"
echo "OK: pkg-config fovea-vk consumer"

# A second, tiny host on the forward-layers path alone: its own pipeline, no G-buffer, no GLSL.
cmake -S "$src/tests/vk_hosts/tiny_forward_host" -B "$tmp/tiny" -DCMAKE_PREFIX_PATH="$prefix" \
    > "$tmp/tiny.log" 2>&1 || { cat "$tmp/tiny.log"; fail "tiny host: configure"; }
cmake --build "$tmp/tiny" > "$tmp/tinyb.log" 2>&1 || { cat "$tmp/tinyb.log"; fail "tiny host: build"; }
out=$("$tmp/tiny/tiny_forward_host") || { echo "$out"; fail "tiny host failed"; }
echo "OK: $out"

# The glTF viewer from the installed SDK, on the shipped scene of real models (read from
# ../shared/data, never copied): every path this device has, fovea >= 40 dB against its own
# full-rate render (the viewer exits 3 otherwise).
data="${FOVEA_SHARED_DATA_DIR:-$src/../shared/data}"
# Validation as the build says (ctest passes FOVEA_VK_VALIDATION); off is said, not silent.
validation=(--validation)
if [ "${FOVEA_VK_VALIDATION:-ON}" = OFF ]; then
    validation=()
    echo "FOVEA_VK_VALIDATION=OFF: Vulkan validation errors NOT checked (gltf_viewer)"
fi
if [ ! -f "$data/scenes/WaterBottle/glTF/WaterBottle.gltf" ]; then
    echo "SKIP: glTF viewer run: no sample models under $data/scenes"
    exit 0
fi
cmake -S "$src/sdk/examples/gltf_viewer" -B "$tmp/gv" -DCMAKE_PREFIX_PATH="$prefix" \
    > "$tmp/gv.log" 2>&1 || { cat "$tmp/gv.log"; fail "gltf_viewer: configure"; }
cmake --build "$tmp/gv" > "$tmp/gvb.log" 2>&1 || { cat "$tmp/gvb.log"; fail "gltf_viewer: build"; }
"$tmp/gv/gltf_viewer" "$src/sdk/examples/gltf_viewer/scenes/sample_models.toml" \
    --data-dir "$data" --size 640x360 --frames 2 --out "$tmp/frames" "${validation[@]}" \
    > "$tmp/gv.out" 2>&1 || { cat "$tmp/gv.out"; fail "gltf_viewer run"; }
cat "$tmp/gv.out"
grep -q "Checking .*viewer_shading.glsl against the Fovea shading contract" "$tmp/gvb.log" \
    || { cat "$tmp/gvb.log"; fail "gltf_viewer: its fovea_shade() not checked at build time"; }
for p in deferred forward-layers post-only; do
    [ -s "$tmp/frames/$p.png" ] || fail "gltf_viewer wrote no $p.png"
done
echo "OK: gltf_viewer built against the installed SDK rendered the sample scene"
