#!/bin/bash
# fovea.conf through systemd-sysusers into a scratch root: user+group fovea and group fovea-admin
# appear, as the .deb postinst creates them. Exit 77 (skip) without systemd-sysusers.
set -u
conf=$1
command -v systemd-sysusers >/dev/null 2>&1 || { echo "SKIP: no systemd-sysusers"; exit 77; }
root=$(mktemp -d /tmp/fvsysu.XXXXXX)
trap 'rm -rf "$root"' EXIT
mkdir -p "$root/etc"
printf 'root:x:0:0:root:/root:/bin/sh\n' > "$root/etc/passwd"
printf 'root:x:0:\n' > "$root/etc/group"
systemd-sysusers --root="$root" "$conf" || { echo "FAIL: systemd-sysusers rejected $conf"; exit 1; }
grep -q '^fovea:x:[0-9]*:[0-9]*:.*:/usr/sbin/nologin$' "$root/etc/passwd" || { cat "$root/etc/passwd"; echo "FAIL: no system user fovea"; exit 1; }
grep -q '^fovea:x:' "$root/etc/group" || { echo "FAIL: no group fovea"; exit 1; }
grep -q '^fovea-admin:x:' "$root/etc/group" || { echo "FAIL: no group fovea-admin"; exit 1; }
uid=$(awk -F: '$1=="fovea"{print $3}' "$root/etc/passwd")
[ "$uid" -lt 1000 ] || { echo "FAIL: fovea uid $uid is not a system uid"; exit 1; }
echo "OK: sysusers creates fovea (uid $uid), fovea and fovea-admin"
