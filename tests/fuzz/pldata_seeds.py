#!/usr/bin/env python3
"""Fuzz seeds from real Pupil .pldata files: the first records of every topic, as Pupil stored
them. `datum` writes each record's msgpack datum (fuzz_pupil_datum's input); `bus` writes
[topic length byte, the datum's own topic, datum] (fuzz_pupil_bus's input: the frames Pupil
Capture publishes). Datums over 64 KiB (calibration data) are left out: seeds that large slow
the fuzzer. Standard library only: a .pldata file is a run of msgpack [str topic, bin datum].

usage: pldata_seeds.py datum|bus OUT_DIR PER_TOPIC FILE.pldata...
"""
import os
import struct
import sys


def records(data):
    """(topic, datum) of each record until the first one this simple reader cannot split."""
    pos = 0
    while pos < len(data):
        if data[pos] != 0x92:
            return
        pos += 1
        head = data[pos]
        if 0xA0 <= head <= 0xBF:
            n, pos = head & 0x1F, pos + 1
        elif head == 0xD9:
            n, pos = data[pos + 1], pos + 2
        else:
            return
        topic, pos = data[pos : pos + n], pos + n
        head = data[pos]
        sizes = {0xC4: ("<B", 1), 0xC5: (">H", 2), 0xC6: (">I", 4)}  # bin 8/16/32
        if head not in sizes:
            return
        fmt, width = sizes[head]
        (n,) = struct.unpack(fmt.replace("<", ">"), data[pos + 1 : pos + 1 + width])
        pos += 1 + width
        if pos + n > len(data):
            return
        yield topic, data[pos : pos + n]
        pos += n


def datum_topic(datum, fallback):
    """The datum's "topic" value (a fixstr key followed by a fixstr or str8 value)."""
    at = datum.find(b"\xa5topic")
    if at < 0 or at + 7 >= len(datum):
        return fallback
    pos, head = at + 7, datum[at + 6]
    if 0xA0 <= head <= 0xBF:
        return datum[pos : pos + (head & 0x1F)]
    if head == 0xD9:
        return datum[pos + 1 : pos + 1 + datum[pos]]
    return fallback


def main():
    mode, out, per_topic, files = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4:]
    os.makedirs(out, exist_ok=True)
    for path in files:
        with open(path, "rb") as f:
            data = f.read()
        stem = os.path.splitext(os.path.basename(path))[0]
        seen = {}
        for topic, datum in records(data):
            k = seen.get(topic, 0)
            if k >= per_topic or len(datum) > 65536:
                continue
            seen[topic] = k + 1
            name = "%s_%s_%d" % (stem, topic.decode("ascii", "replace"), k)
            name = "".join(c if c.isalnum() else "_" for c in name)
            bus_topic = datum_topic(datum, topic)[:0xFE]  # 0xff: a message of one frame
            blob = datum if mode == "datum" else bytes([len(bus_topic)]) + bus_topic + datum
            with open(os.path.join(out, name), "wb") as f:
                f.write(blob)


if __name__ == "__main__":
    main()
