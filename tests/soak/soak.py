#!/usr/bin/env python3
"""Soak: one fovead with several devices under abuse for --minutes, then a kill -9 mid-recording.

Devices: the simulated tracker at 2 kHz, the serial simulator on a pty (corrupt bytes, reopened
every 20 s), a Gazepoint server restarted every 15 s. Around them: 8 ring readers (`fovea watch`;
4 run throughout, 4 are kill -9ed and restarted one per second), a ZeroMQ subscriber, a recording,
and an abusive control-socket client (bursts of 1000 connections, slow writers, oversize requests,
invalid UTF-8, random JSON) while a prober asks for status every 100 ms.

Checks: status p99 <= 100 ms; the readers that ran throughout and the ZeroMQ subscriber saw every
published sample in order (index gaps are lost samples); RSS, fds and threads flat; after kill -9
and `fovea repair` the recording lacks at most the last flush interval; a restarted fovead is
seen by every surviving reader. fovead's RSS (with its anonymous, file and shared parts), fds and
threads go to resources.csv once a second. The last line is `lost N` (samples lost; must be 0)
and the exit status is 0 only when every check passed.
"""
import argparse
import json
import multiprocessing
import os
import random
import re
import resource
import signal
import socket
import struct
import subprocess
import sys
import threading
import time

SIM_RATE_HZ = 2000
FLUSH_MS = 250
INDEX = re.compile(rb"#(\d+)\s")
RESOURCE_COLUMNS = ("t_s", "pid", "rss_kb", "anon_kb", "file_kb", "shmem_kb", "fds", "threads")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def request(sock, req, timeout=2.0):
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
        s.settimeout(timeout)
        s.connect(sock)
        s.sendall((json.dumps(req) + "\n").encode())
        buf = b""
        while not buf.endswith(b"\n"):
            chunk = s.recv(65536)
            if not chunk:
                break
            buf += chunk
        return json.loads(buf)


def dump_stacks(pid, path):
    """Where fovead's threads are when it does not answer (needs gdb)."""
    if not os.path.exists("/usr/bin/gdb"):
        return
    with open(path, "w") as f:
        try:
            subprocess.run(["gdb", "-p", str(pid), "-batch", "-ex", "thread apply all bt 30"],
                           stdout=f, stderr=subprocess.STDOUT, timeout=20, check=False)
        except (OSError, subprocess.TimeoutExpired) as e:  # no ptrace in some sandboxes
            f.write("gdb: %s\n" % e)
    print("fovead's stacks: %s" % path, flush=True)


def probe_status(sock, csv_path, t0, stop, restarting, bursting, daemon_pid):
    """Asks for status every 100 ms and writes `t_s,ms,bursting,error` per request. It runs in
    its own process: among the harness's threads its timing would include waits for Python's
    GIL (the abuser builds a quarter of a GiB of requests per burst), not only fovead's answer."""
    dumped = False
    with open(csv_path, "w", buffering=1) as out:
        out.write("t_s,ms,bursting,error\n")
        while not stop.is_set():
            t = time.monotonic()
            error = ""
            try:
                request(sock, {"cmd": "status"}, timeout=5.0)
            except OSError as e:
                error = str(e).replace(",", ";")
            ms = (time.monotonic() - t) * 1000.0
            if not (error and restarting.is_set()):  # no daemon to answer while it restarts
                out.write("%.3f,%.2f,%d,%s\n" % (t - t0, ms, bursting.is_set(), error))
            if error and not restarting.is_set() and not dumped:
                dumped = True
                dump_stacks(daemon_pid.value, os.path.dirname(csv_path) + "/fovead.stacks.txt")
            # The same 100 ms pace after a failure: a refused connect returns at once.
            time.sleep(max(0.0, 0.1 - (time.monotonic() - t)))


class Soak:
    def __init__(self, a):
        self.a = a
        self.out = os.path.abspath(a.out)
        os.makedirs(self.out, exist_ok=True)
        self.instance = "soak%d" % os.getpid()
        self.env = dict(os.environ, FOVEA_RUNTIME_DIR=self.out + "/run",
                        FOVEA_STATE_DIR=self.out + "/state")
        os.makedirs(self.out + "/run", exist_ok=True)
        self.fovead = os.path.join(a.build, "daemon/fovead")
        self.fovea = os.path.join(a.build, "tools/fovea")
        self.sock = "%s/run/%s.sock" % (self.out, self.instance)
        self.procs = []
        self.failures = []
        self.stop = threading.Event()
        self.quiet = threading.Event()
        self.mp = multiprocessing.get_context("spawn")  # no fork of a threaded harness
        self.restarting, self.bursting = self.mp.Event(), self.mp.Event()
        self.status_stop = self.mp.Event()
        self.status_csv = self.out + "/status.csv"
        self.resources_csv = self.out + "/resources.csv"
        self.resources = []  # RESOURCE_COLUMNS, one row a second
        self.abuse = {"bursts": 0, "connections": 0, "refused": 0}
        self.t0 = time.monotonic()

    # ---- processes -------------------------------------------------------------------------
    def spawn(self, args, name, **kw):
        log = open("%s/%s.log" % (self.out, name), "ab")
        p = subprocess.Popen(args, env=self.env, stdout=kw.pop("stdout", log), stderr=log, **kw)
        self.procs.append(p)
        return p

    def fail(self, what):
        self.failures.append(what)
        print("FAIL: " + what, flush=True)

    def request(self, req, timeout=2.0):
        return request(self.sock, req, timeout)

    def start_daemon(self):
        self.daemon = self.spawn([self.fovead, "--instance", self.instance, "--config",
                                  self.out + "/fovead.toml"], "fovead")
        deadline = time.time() + 20
        while time.time() < deadline:
            try:
                self.request({"cmd": "status"})
                return
            except OSError:
                time.sleep(0.1)
        raise SystemExit("fovead did not answer within 20 s (see %s/fovead.log)" % self.out)

    # ---- background activity ---------------------------------------------------------------
    def sampler(self):
        with open(self.resources_csv, "w") as csv:
            csv.write(",".join(RESOURCE_COLUMNS) + "\n")
            while not self.stop.is_set():
                pid = self.daemon.pid
                try:
                    st = open("/proc/%d/status" % pid).read()
                    kb = {k: int(re.search(r"%s:\s+(\d+)" % k, st).group(1))
                          for k in ("VmRSS", "RssAnon", "RssFile", "RssShmem")}
                    thr = int(re.search(r"Threads:\s+(\d+)", st).group(1))
                    fds = len(os.listdir("/proc/%d/fd" % pid))
                    # Bursts hold 1000 fds; a restart has a new pid.
                    if not self.restarting.is_set() and not self.bursting.is_set():
                        row = (time.monotonic() - self.t0, pid, kb["VmRSS"], kb["RssAnon"],
                               kb["RssFile"], kb["RssShmem"], fds, thr)
                        self.resources.append(row)
                        csv.write("%.1f,%d,%d,%d,%d,%d,%d,%d\n" % row)
                        csv.flush()
                except (OSError, AttributeError):
                    pass
                time.sleep(1.0)

    def abuser(self):
        rng = random.Random(20)
        garbage = [b"\xff\xfe\xc3\x28 not utf-8\n", b'{"cmd": "status", "x": "\xed\xa0\x80"}\n',
                   b"{" * 5000 + b"\n", b"[1,2,3]\n", b'{"cmd": 7}\n', b'{"cmd":"nope"}\n',
                   b'{"cmd":"latency.report","hops":{"publish_to_read":{"count":1e300}}}\n']
        while not self.stop.wait(8.0):
            if self.restarting.is_set() or self.quiet.is_set():
                continue
            conns = []
            self.bursting.set()
            for _ in range(1000):
                try:
                    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
                    s.setblocking(False)
                    s.connect(self.sock)
                    conns.append(s)
                except OSError:
                    self.abuse["refused"] += 1
                    s.close()
            self.abuse["bursts"] += 1
            self.abuse["connections"] += len(conns)
            # Slow writers: a byte at a time across the burst.
            for step in range(20):
                for s in conns[step::20]:
                    try:
                        s.send(b'{"cmd":')
                    except OSError:
                        pass
                time.sleep(0.05)
            for i, s in enumerate(conns):
                try:
                    if i % 4 == 0:
                        s.send(b"x" * (1 << 20))  # oversize, no newline
                    elif i % 4 == 1:
                        s.send(rng.choice(garbage))
                    elif i % 4 == 2:
                        obj = {rng.choice(["cmd", "path", "user"]): rng.random() for _ in range(3)}
                        s.send(json.dumps(obj).encode() + b"\n")
                except OSError:
                    pass
            time.sleep(0.5)
            for s in conns:
                s.close()
            time.sleep(0.5)  # the daemon closes its ends
            self.bursting.clear()

    def reader(self, i, churn):
        name = "reader%d" % i
        while not self.stop.is_set():
            p = self.spawn([self.fovea, "--instance", self.instance, "watch", "--wait", "30"],
                           "%s.%d" % (name, int(time.time() * 1000)),
                           stdout=open("%s/%s.out" % (self.out, name), "ab"))
            if not churn:
                self.steady.append((i, p))
                return
            self.stop.wait(1.0 + (i % 4) * 0.25)
            p.send_signal(signal.SIGKILL)
            p.wait()

    def periodic(self, args, name, every):
        while not self.stop.is_set():
            p = self.spawn(args, "%s.%d" % (name, int(time.time())))
            if self.stop.wait(every):
                break
            p.terminate()
            p.wait()

    # ---- the run ---------------------------------------------------------------------------
    def run(self):
        pty = self.out + "/serial.pty"
        gp_port, zmq_port = free_port(), free_port()
        with open(self.out + "/fovead.toml", "w") as f:
            f.write('[ring]\nslots = 16384\n'
                    '[[device]]\ndriver = "sim"\nrate_hz = %d\nseed = 11\n'
                    '[[device]]\ndriver = "serial"\nport = "%s"\n'
                    '[[device]]\ndriver = "gazepoint"\naddress = "127.0.0.1:%d"\n'
                    '[zmq]\npublish = "tcp://127.0.0.1:%d"\nsend_hwm = 1000000\n'
                    % (SIM_RATE_HZ, pty, gp_port, zmq_port))
        self.steady = []
        threading.Thread(target=self.periodic, daemon=True, args=(
            [self.fovea, "simulate", "serial", "--link", pty, "--corrupt", "0.01",
             "--reopen-every", "20"], "serial", 1e9)).start()
        threading.Thread(target=self.periodic, daemon=True, args=(
            [self.fovea, "simulate", "gazepoint", "--port", str(gp_port), "--garbage", "0.01"],
            "gazepoint", 15.0)).start()
        self.start_daemon()
        zmq_out = open(self.out + "/zmq.out", "wb")
        self.zmq = self.spawn([self.fovea, "watch", "--zmq", "tcp://127.0.0.1:%d" % zmq_port,
                               "--wait", "30"], "zmq", stdout=zmq_out)
        for i in range(8):
            threading.Thread(target=self.reader, args=(i, i >= 4), daemon=True).start()
        time.sleep(2.0)
        rec = self.out + "/soak.xdf"
        r = self.request({"cmd": "record.start", "path": rec, "flush_ms": FLUSH_MS})
        if not r.get("ok"):
            raise SystemExit("record.start: %s" % r)
        self.daemon_pid = self.mp.Value("i", self.daemon.pid)
        self.prober = self.mp.Process(target=probe_status, daemon=True, args=(
            self.sock, self.status_csv, self.t0, self.status_stop, self.restarting,
            self.bursting, self.daemon_pid))
        self.prober.start()
        for fn in (self.sampler,) + (() if self.a.no_abuse else (self.abuser,)):
            threading.Thread(target=fn, daemon=True).start()
        end = time.monotonic() + self.a.minutes * 60
        while time.monotonic() < end:
            time.sleep(1.0)
            if self.daemon.poll() is not None:
                raise SystemExit("fovead exited (%s) during the soak" % self.daemon.returncode)

        self.quiet.set()  # the abuser stops; the last figures come from a calm daemon
        time.sleep(2.0)
        first = self.request({"cmd": "status"}, timeout=10.0)
        time.sleep(1.0)
        before = self.request({"cmd": "status"}, timeout=10.0)
        self.recorded_rate = (self.recorded(before) - self.recorded(first)) / 1.0
        self.restarting.set()
        self.log_at_kill = os.path.getsize(self.out + "/fovead.log")
        self.daemon.send_signal(signal.SIGKILL)
        self.daemon.wait()
        killed_at = time.monotonic()
        self.start_daemon()
        self.daemon_pid.value = self.daemon.pid
        restarted = time.monotonic()
        self.restarting.clear()
        time.sleep(5.0)
        self.stop.set()
        self.status_stop.set()
        self.prober.join(10.0)
        return self.report(before, rec, killed_at, restarted)

    # ---- checks ----------------------------------------------------------------------------
    @staticmethod
    def watch_indices(path):
        """The ring index of every sample line of a `fovea watch` output, in order."""
        with open(path, "rb") as f:
            for line in f:
                m = INDEX.search(line)
                if m:
                    yield int(m.group(1))

    def gaps(self, path):
        """(samples, gaps, restarts) in a watch output: indices must step by one."""
        last, n, lost, restarts = None, 0, 0, 0
        for idx in self.watch_indices(path):
            n += 1
            if last is not None:
                if idx < last:
                    restarts += 1  # a new daemon numbers from 0 again
                elif idx > last + 1:
                    lost += idx - last - 1
            last = idx
        return n, lost, restarts

    def indices(self, path):
        """Ring indices of the first daemon's samples in a watch output, and whether lines
        from a restarted daemon (indices starting again) followed."""
        first, restarted, last = [], False, -1
        for idx in self.watch_indices(path):
            # Devices interleave by < 1 s (a quiet device's held samples are settled within a
            # tick); a new ring starts again at 0, far below where the old one was.
            if idx + 10000 < last and 2 * idx < last:
                restarted = True
            if restarted:
                continue
            first.append(idx)
            last = max(last, idx)
        return first, restarted

    def check_zmq(self, publisher):
        """ZeroMQ carries each device's final samples (after the look-ahead), so devices
        interleave; every ring index in the window both saw must arrive once. `publisher` is
        the first fovead's [zmq] status: what it sent, and what it could not (full queue)."""
        ring, _ = self.indices("%s/reader%d.out" % (self.out, self.steady[0][0]))
        zmq, restarted = self.indices(self.out + "/zmq.out")
        if not zmq or not ring:
            self.fail("zmq subscriber received nothing")
            return 0
        got = set(zmq)
        dupes = len(zmq) - len(got)
        lo, hi = max(min(zmq), min(ring)), min(max(zmq), max(ring)) - 5000
        missing = sum(1 for i in ring if lo <= i <= hi and i not in got)
        print("zmq subscriber: %d samples, %d of the ring's %d in [%d, %d] missing, %d twice; "
              "followed the restart: %s" % (len(zmq), missing,
                                            sum(1 for i in ring if lo <= i <= hi), lo, hi,
                                            dupes, restarted))
        print("zmq publisher: %s sent, %s failed to send"
              % (publisher.get("sent", "?"), publisher.get("failed", "?")))
        if dupes:
            self.fail("zmq delivered %d samples twice" % dupes)
        if not restarted:
            self.fail("zmq subscriber did not follow the restarted fovead")
        return missing

    def xdf_samples(self, path):
        d = open(path, "rb").read()
        counts, fmt = {}, {}
        p = 4
        while p < len(d):
            nb = d[p]
            length = int.from_bytes(d[p + 1:p + 1 + nb], "little")
            tag = struct.unpack("<H", d[p + 1 + nb:p + 3 + nb])[0]
            c = d[p + 3 + nb:p + 1 + nb + length]
            if tag == 2:
                sid = struct.unpack("<I", c[:4])[0]
                name = re.search(rb"<name>([^<]*)</name>", c)
                fmt[sid] = name.group(1).decode() if name else str(sid)
            elif tag == 3:
                sid = struct.unpack("<I", c[:4])[0]
                k = c[4]
                counts[fmt.get(sid, sid)] = counts.get(fmt.get(sid, sid), 0) + \
                    int.from_bytes(c[5:5 + k], "little")
            p += 1 + nb + length
        return counts

    @staticmethod
    def recorded(status):
        r = status.get("recording", {})
        return sum(int(r.get(k, 0)) for k in ("raw_samples", "gaze_samples", "latency_samples"))

    def steady_resources(self):
        """Second half of the samples of the fovead that ran the soak (not the one restarted
        after the kill -9: a fresh process says nothing about growth)."""
        pts = [r for r in self.resources if r[1] == self.resources[0][1]] if self.resources else []
        return pts[len(pts) // 2:]

    def slope_per_hour(self, col):
        pts = self.steady_resources()
        if len(pts) < 5:
            return 0.0
        t0 = pts[0][0]
        xs = [(p[0] - t0) / 3600.0 for p in pts]
        ys = [p[RESOURCE_COLUMNS.index(col)] for p in pts]
        mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
        var = sum((x - mx) ** 2 for x in xs)
        return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / var if var else 0.0

    def report(self, before, rec, killed_at, restarted):
        lost = 0
        rows = [r.split(",", 3) for r in open(self.status_csv).read().splitlines()[1:]]
        for t, _, _, error in rows:
            if error:
                self.fail("status request failed at %s s: %s" % (t, error))

        def percentiles(ms):
            ms = sorted(ms)
            if not ms:
                return float("inf"), "none"
            p99 = ms[min(len(ms) - 1, int(0.99 * len(ms)))]
            return p99, "%d requests, p50 %.1f ms, p99 %.1f ms, max %.1f ms" % (
                len(ms), ms[len(ms) // 2], p99, ms[-1])
        answered = [(float(ms), b == "1") for _, ms, b, error in rows if not error]
        p99, line = percentiles([ms for ms, _ in answered])
        print("status: %s (timeline: %s)" % (line, self.status_csv))
        print("status during abuse bursts: %s" % percentiles([m for m, b in answered if b])[1])
        print("status between bursts: %s" % percentiles([m for m, b in answered if not b])[1])
        if p99 > 100.0:
            self.fail("status p99 %.1f ms > 100 ms" % p99)
        print("abuse: %(bursts)d bursts, %(connections)d connections, %(refused)d refused"
              % self.abuse)

        for dev in before["devices"]:
            print("device %s %s: samples %d published %d frames_dropped %d frames_lost %d "
                  "resyncs %d reconnects %d" % (dev["id"], dev["driver"], dev["samples"],
                                                dev["published"], dev["frames_dropped"],
                                                dev["frames_lost"], dev["resyncs"],
                                                dev["reconnects"]))
            if dev["driver"] == "sim" and dev["samples"] - dev["published"] > 1:
                # Live publishing: every sim sample is published as it arrives.
                lost += dev["samples"] - dev["published"] - 1
                self.fail("sim: %d samples not published" % (dev["samples"] - dev["published"]))

        # A stalled loop makes the simulated tracker skip the samples it could not deliver.
        skipped = 0
        with open(self.out + "/fovead.log", "rb") as f:
            for line in f.read(self.log_at_kill).decode(errors="replace").splitlines():
                m = re.search(r"\[drv\.sim\] loop stalled: skipped (\d+) samples", line)
                if m:
                    skipped += int(m.group(1))
                    print("fovead: " + line.strip())
        sim = [d for d in before["devices"] if d["driver"] == "sim"]
        counted = sim[0]["frames_lost"] if sim else 0
        # Counted drops, not losses: the status counts them (frames_lost) and the log says why.
        print("sim drops: %d samples skipped while fovead's loop stalled; status counts %d"
              % (skipped, counted))
        if skipped > counted:
            lost += skipped - counted
            self.fail("%d sim samples skipped but not counted" % (skipped - counted))

        for i, p in self.steady:
            n, gap, restarts = self.gaps("%s/reader%d.out" % (self.out, i))
            print("reader%d (throughout): %d samples, %d missing, %d daemon restarts seen"
                  % (i, n, gap, restarts))
            lost += gap
            if restarts < 1 or p.poll() is not None:
                self.fail("reader%d did not follow the restarted fovead" % i)
        lost += self.check_zmq(before.get("zmq", {}))

        subprocess.run([self.fovea, "repair", rec], env=self.env, check=False,
                       stdout=subprocess.DEVNULL)
        counts = self.xdf_samples(rec)
        in_file = sum(counts.values())
        # What the recorder had been handed at the last status, less one flush interval's worth
        # at the rate it was being handed samples, must all be in the repaired file.
        allowance = int(self.recorded_rate * FLUSH_MS / 1000.0) + 1
        missing = max(0, self.recorded(before) - in_file)
        print("recording after kill -9 + repair: %d samples in the file (%s); the recorder had "
              "%d; allowed to miss %d (%d ms at %.0f/s)"
              % (in_file, counts, self.recorded(before), allowance, FLUSH_MS,
                 self.recorded_rate))
        if missing > allowance:
            lost += missing - allowance
            self.fail("recording lost %d samples (> one flush interval, %d)"
                      % (missing, allowance))

        pts = self.steady_resources()
        if len(pts) >= 5:
            first, last = pts[0], pts[-1]
            col = RESOURCE_COLUMNS.index
            print("fovead resources (2nd half, %s): RSS %d -> %d kB (%.0f kB/h; anon %d -> %d, "
                  "%.0f kB/h; shmem %d -> %d), fds %d -> %d, threads %d -> %d"
                  % (self.resources_csv, first[col("rss_kb")], last[col("rss_kb")],
                     self.slope_per_hour("rss_kb"), first[col("anon_kb")], last[col("anon_kb")],
                     self.slope_per_hour("anon_kb"), first[col("shmem_kb")],
                     last[col("shmem_kb")], first[col("fds")], last[col("fds")],
                     first[col("threads")], last[col("threads")]))
            if self.slope_per_hour("rss_kb") > 64 * 1024 and self.a.minutes >= 10:
                self.fail("RSS grows %.0f kB/h" % self.slope_per_hour("rss_kb"))
            if last[col("threads")] > first[col("threads")]:
                self.fail("threads grew %d -> %d" % (first[col("threads")], last[col("threads")]))
            if self.slope_per_hour("fds") > 60:
                self.fail("fds grow %.0f/h" % self.slope_per_hour("fds"))
        print("restart: fovead back %.2f s after kill -9" % (restarted - killed_at))
        return lost


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--minutes", type=float, default=2.0)
    ap.add_argument("--build", default="build/main")
    ap.add_argument("--out", default="build/soak")
    ap.add_argument("--no-abuse", action="store_true", help="no abusive control-socket client")
    a = ap.parse_args()
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))
    s = Soak(a)
    lost = None
    try:
        lost = s.run()
    finally:
        s.stop.set()
        for p in s.procs:
            if p.poll() is None:
                p.kill()
                p.wait()
    if s.failures:
        print("%d checks failed: %s" % (len(s.failures), "; ".join(s.failures)))
    print("lost %d" % lost)
    sys.exit(0 if lost == 0 and not s.failures else 1)


if __name__ == "__main__":
    main()
