#!/usr/bin/env python3
"""Independent XDF reader (Python standard library only), used by the record tests to check that
Fovea's files follow the XDF 1.0 specification chunk by chunk, the way pyxdf reads them.

Usage: xdf_reader.py FILE [--allow-truncated] [--require-footers]
Prints a JSON summary: per stream name its id, channel_count, format, labels, sample count,
first/last time stamp, first/last row and per-channel sums (NaN skipped). Exits non-zero with
a message on the first violation.
"""
import json
import math
import struct
import sys
import xml.etree.ElementTree as ET

BOUNDARY_UUID = bytes((0x43, 0xA5, 0x46, 0xDC, 0xCB, 0xF5, 0x41, 0x0F,
                       0xB3, 0x0E, 0xD5, 0x46, 0x73, 0x83, 0xCB, 0xE4))
FORMATS = {"float32": ("<f", 4), "double64": ("<d", 8), "int8": ("<b", 1),
           "int16": ("<h", 2), "int32": ("<i", 4), "int64": ("<q", 8), "string": (None, 0)}


class Violation(Exception):
    pass


class Reader:
    def __init__(self, data):
        self.data = data
        self.pos = 0

    def take(self, n):
        if self.pos + n > len(self.data):
            raise EOFError
        b = self.data[self.pos:self.pos + n]
        self.pos += n
        return b

    def varlen(self):
        nbytes = self.take(1)[0]
        if nbytes == 1:
            return self.take(1)[0]
        if nbytes == 4:
            return struct.unpack("<I", self.take(4))[0]
        if nbytes == 8:
            return struct.unpack("<Q", self.take(8))[0]
        raise Violation("invalid variable-length integer prefix %d at byte %d" % (nbytes, self.pos - 1))


def clean(row):
    return [None if isinstance(v, float) and math.isnan(v) else v for v in row]


def main():
    args = sys.argv[1:]
    path = args[0]
    allow_truncated = "--allow-truncated" in args
    require_footers = "--require-footers" in args
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"XDF:":
        raise Violation("missing XDF: magic")
    r = Reader(data)
    r.pos = 4
    streams = {}
    file_header = False
    boundaries = 0
    chunk_tags = []
    truncated = False
    while r.pos < len(data):
        start = r.pos
        try:
            length = r.varlen()
            body = r.take(length)
        except EOFError:
            if not allow_truncated:
                raise Violation("chunk at byte %d runs past the end of the file" % start)
            truncated = True
            break
        if length < 2:
            raise Violation("chunk length %d < 2 at byte %d" % (length, start))
        tag = struct.unpack("<H", body[:2])[0]
        c = Reader(body[2:])
        chunk_tags.append(tag)
        if not file_header and tag != 1:
            raise Violation("first chunk is tag %d, not FileHeader" % tag)
        if tag == 1:
            if file_header:
                raise Violation("second FileHeader")
            file_header = True
            info = ET.fromstring(c.data.decode("utf-8"))
            if info.findtext("version") != "1.0":
                raise Violation("FileHeader version is not 1.0")
        elif tag == 2:
            sid = struct.unpack("<I", c.take(4))[0]
            if sid in streams:
                raise Violation("duplicate StreamHeader %d" % sid)
            info = ET.fromstring(c.data[c.pos:].decode("utf-8"))
            for req in ("name", "type", "channel_count", "nominal_srate", "channel_format"):
                if info.find(req) is None:
                    raise Violation("stream %d header lacks <%s>" % (sid, req))
            fmt = info.findtext("channel_format")
            if fmt not in FORMATS:
                raise Violation("stream %d: unknown channel_format %s" % (sid, fmt))
            nch = int(info.findtext("channel_count"))
            labels = [ch.findtext("label") for ch in info.iter("channel")]
            if labels and len(labels) != nch:
                raise Violation("stream %d: %d channel labels for %d channels" % (sid, len(labels), nch))
            srate = float(info.findtext("nominal_srate"))
            streams[sid] = {"id": sid, "name": info.findtext("name"), "type": info.findtext("type"),
                            "channel_count": nch, "format": fmt, "labels": labels,
                            "srate": srate, "stamps": [], "rows": [], "footer": None,
                            "clock_offsets": 0}
        elif tag == 3:
            sid = struct.unpack("<I", c.take(4))[0]
            if sid not in streams:
                raise Violation("Samples for unknown stream %d" % sid)
            s = streams[sid]
            n = c.varlen()
            code, size = FORMATS[s["format"]]
            tdiff = 1.0 / s["srate"] if s["srate"] > 0 else 0.0
            for _ in range(n):
                tsb = c.take(1)[0]
                if tsb == 8:
                    ts = struct.unpack("<d", c.take(8))[0]
                elif tsb == 0:
                    ts = (s["stamps"][-1] if s["stamps"] else 0.0) + tdiff
                else:
                    raise Violation("TimeStampBytes %d" % tsb)
                if code is None:
                    row = [c.take(c.varlen()).decode("utf-8") for _ in range(s["channel_count"])]
                else:
                    row = list(struct.unpack("<" + code[1] * s["channel_count"],
                                             c.take(size * s["channel_count"])))
                s["stamps"].append(ts)
                s["rows"].append(row)
            if c.pos != len(c.data):
                raise Violation("Samples chunk of stream %d has %d trailing bytes" % (sid, len(c.data) - c.pos))
        elif tag == 4:
            sid, _t, _o = struct.unpack("<Idd", c.data)
            if sid not in streams:
                raise Violation("ClockOffset for unknown stream %d" % sid)
            streams[sid]["clock_offsets"] += 1
        elif tag == 5:
            if c.data != BOUNDARY_UUID:
                raise Violation("Boundary chunk with wrong UUID")
            boundaries += 1
        elif tag == 6:
            sid = struct.unpack("<I", c.take(4))[0]
            if sid not in streams:
                raise Violation("StreamFooter for unknown stream %d" % sid)
            info = ET.fromstring(c.data[c.pos:].decode("utf-8"))
            streams[sid]["footer"] = {"sample_count": int(info.findtext("sample_count")),
                                      "first_timestamp": float(info.findtext("first_timestamp")),
                                      "last_timestamp": float(info.findtext("last_timestamp"))}
        # unknown tags are skipped, as the specification asks
    out = {"boundaries": boundaries, "chunks": len(chunk_tags), "truncated": truncated, "streams": {}}
    for s in streams.values():
        n = len(s["stamps"])
        if s["footer"] is not None:
            if s["footer"]["sample_count"] != n:
                raise Violation("stream %s footer says %d samples, file has %d" %
                                (s["name"], s["footer"]["sample_count"], n))
            if n and (s["footer"]["first_timestamp"] != s["stamps"][0] or
                      s["footer"]["last_timestamp"] != s["stamps"][-1]):
                raise Violation("stream %s footer time stamps disagree with samples" % s["name"])
        elif require_footers:
            raise Violation("stream %s has no StreamFooter" % s["name"])
        sums = [0.0] * s["channel_count"]
        if s["format"] != "string":
            for row in s["rows"]:
                for k, v in enumerate(row):
                    if not math.isnan(v):
                        sums[k] += v
        out["streams"][s["name"]] = {
            "id": s["id"], "channel_count": s["channel_count"], "format": s["format"],
            "labels": s["labels"], "count": n, "has_footer": s["footer"] is not None,
            "clock_offsets": s["clock_offsets"],
            "first_ts": s["stamps"][0] if n else None, "last_ts": s["stamps"][-1] if n else None,
            "first_row": clean(s["rows"][0]) if n else None,
            "last_row": clean(s["rows"][-1]) if n else None,
            "sums": sums}
    json.dump(out, sys.stdout, allow_nan=True)


if __name__ == "__main__":
    try:
        main()
    except Violation as e:
        print("XDF violation: %s" % e, file=sys.stderr)
        sys.exit(2)
