#!/bin/bash
# CPack builds the .deb; it holds the unit, socket, sysusers and udev files, the library and the
# config, and its postinst creates the users/groups and reloads udev. Exit 77 without dpkg-deb.
# abi: FOVEA_RING_ABI_VERSION as CMake read it from ring.h.
set -eu
build=$1 abi=$2
command -v dpkg-deb >/dev/null 2>&1 || { echo "SKIP: no dpkg-deb"; exit 77; }
tmp=$(mktemp -d /tmp/fvdeb.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
(cd "$build" && cpack -G DEB -B "$tmp" > "$tmp/cpack.log" 2>&1) || { cat "$tmp/cpack.log"; fail "cpack -G DEB"; }
deb=$(ls "$tmp"/*.deb | head -1)
[ -f "$deb" ] || fail "no .deb produced"
dpkg-deb -c "$deb" > "$tmp/contents"
for f in sbin/fovead bin/fovea lib/systemd/system/fovead.service lib/systemd/system/fovead.socket \
         lib/sysusers.d/fovea.conf lib/udev/rules.d/70-fovea.rules "libfovea.so.$abi" fovea.pc \
         foveaConfig.cmake include/fovea/client.h fovea/fovead.toml; do
    grep -q "$f\$" "$tmp/contents" || { cat "$tmp/contents"; fail "$f missing from $(basename "$deb")"; }
done
mkdir "$tmp/control"
dpkg-deb -e "$deb" "$tmp/control"
[ -x "$tmp/control/postinst" ] || fail "no executable postinst"
grep -q "systemd-sysusers .*/sysusers.d/fovea.conf" "$tmp/control/postinst" || fail "postinst does not run sysusers"
grep -q "addgroup --system fovea-admin" "$tmp/control/postinst" || fail "postinst has no fallback for fovea-admin"
grep -q "udevadm control --reload-rules" "$tmp/control/postinst" || fail "postinst does not reload udev"
sh -n "$tmp/control/postinst" && sh -n "$tmp/control/prerm" && sh -n "$tmp/control/postrm" || fail "maintainer script syntax"
echo "OK: $(basename "$deb") ($(stat -c %s "$deb") bytes)"
