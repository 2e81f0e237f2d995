#!/bin/bash
# systemd-analyze verify on fovead.service + fovead.socket. The unit is filled in with the
# just-built fovead (verify checks that ExecStart exists). Any warning fails the test: verify
# exits 0 on unknown keys and only prints them. Exit 77 (skip) when systemd-analyze cannot run.
set -u
unit_in=$1 socket=$2 fovead=$3 work=$4
if ! command -v systemd-analyze >/dev/null 2>&1; then
    echo "SKIP: systemd-analyze is not installed"; exit 77
fi
rm -rf "$work" && mkdir -p "$work"
sed "s|@FOVEA_SBINDIR@/fovead|$fovead|" "$unit_in" > "$work/fovead.service"
cp "$socket" "$work/fovead.socket"
out=$(cd "$work" && SYSTEMD_LOG_LEVEL=notice systemd-analyze verify "$work/fovead.service" \
      "$work/fovead.socket" 2>&1)
rc=$?
if [ $rc -ne 0 ] && echo "$out" | grep -qiE "Failed to (initialize|connect|allocate)|not been booted|Permission denied.*manager"; then
    echo "SKIP: systemd-analyze cannot run here: $out"; exit 77
fi
[ -z "$out" ] || echo "$out"
[ $rc -eq 0 ] || { echo "FAIL: systemd-analyze verify exited $rc"; exit 1; }
[ -z "$out" ] || { echo "FAIL: systemd-analyze verify printed warnings"; exit 1; }
# The properties the issue requires, so a later edit cannot silently drop one.
for want in "Type=notify" "WatchdogSec=" "RuntimeDirectory=fovea" "User=fovea" "Group=fovea" \
            "ProtectSystem=strict" "NoNewPrivileges=yes" "PrivateTmp=yes" "Restart=on-failure" \
            "DevicePolicy=closed" "DeviceAllow=char-hidraw" "DeviceAllow=char-usb_device" \
            "DeviceAllow=char-ttyACM" "DeviceAllow=char-ttyUSB"; do
    grep -q "^$want" "$work/fovead.service" || { echo "FAIL: fovead.service lacks $want"; exit 1; }
done
grep -q "^DeviceAllow=" <(grep -v -E "^DeviceAllow=char-(hidraw|usb_device|ttyACM|ttyUSB) " \
    "$work/fovead.service") && { echo "FAIL: DeviceAllow beyond the tracker classes"; exit 1; }
echo "OK: fovead.service and fovead.socket verify cleanly"
