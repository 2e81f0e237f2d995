#!/usr/bin/env python3
"""Soak: one fovead with several devices under abuse for --minutes, then a kill -9 mid-recording.

Devices: the simulated tracker at 2 kHz, the serial simulator on a pty (corrupt bytes, reopened
every 20 s), a Gazepoint server restarted every 15 s and, where ../shared/data holds the Pupil
Capture recording, `fovea simulate pupil` replaying it (garbage and truncated messages, a restart
every 8 s, and a new simulator at the end of the recording). Around them: 8 ring readers (`fovea
watch`; 4 run throughout, 4 are kill -9ed and restarted one per second), a ZeroMQ subscriber, a
recording, and an abusive control-socket client (bursts of 1000 connections with oversize requests,
invalid UTF-8 and random JSON: nested structures, wrong types, every command but shutdown and
record.stop with garbage arguments; slow writers sending a request a byte every 200 ms; requests at
and over the size limit; random requests whose answers are checked) while a prober asks for status
every 100 ms.

Checks, per sample (ring index) where they can be: status p99 <= 100 ms; every ring reader's
output steps by exactly one index within a ring generation (a step back is a failure; only fovea
watch's own "fovead restarted" note, on a new ring generation, starts a new run); the ZeroMQ
subscriber and the recording (after `fovea repair`, read back with `fovea export`) hold each
sample once, each device's in order, the subscriber in the recording's exact order; the recording
has every sample published between record.start and the kill less the last flush interval;
every datum the Pupil simulator sent reached fovead (decoded or counted as dropped) and every
decoded one was published; fovead's fds and threads after warm-up equal those at the end, its
anonymous RSS grows less than one burst's request buffers (slopes per hour printed; 2 minutes
show leaks per connection or per burst, slower ones need --minutes 60, where slopes are checked);
after kill -9 every surviving reader and the subscriber follow the restarted fovead. fovead's RSS,
fds and threads go to resources.csv once a second. The last line is `lost N` (samples lost; must
be 0), also when the harness aborts (then after an ERROR line); exit status 0 only if all passed.
"""
import argparse
import bisect
import csv
import json
import multiprocessing
import os
import random
import re
import resource
import shutil
import signal
import socket
import statistics
import struct
import subprocess
import sys
import threading
import time

SIM_RATE_HZ = 2000
FLUSH_MS = 250
# A sample line of `fovea watch` (ring or --zmq): "#<index> t=...".
SAMPLE = re.compile(rb"#(\d+)\s+t=")
READER_STARTED = b"soak: reader started"  # written by the harness before each fovea watch
WATCH_RESTARTED = b"fovead restarted"  # fovea watch: attached to a new ring generation
ZMQ_KILLED = b"soak: fovead killed"  # written into zmq.out once the dead publisher's last line is
RESOURCE_COLUMNS = ("t_s", "pid", "rss_kb", "anon_kb", "file_kb", "shmem_kb", "fds", "threads")
# ControlServer::kMaxRequestBytes (daemon/src/control.hpp): a longer line is refused.
MAX_REQUEST = 64 * 1024
# Sent to fovead with any arguments, these would end the daemon or the recording under test.
NOT_SENT = ("shutdown", "record.stop")
ARG_KEYS = ("path", "flush_ms", "user", "eyes", "x", "y", "deg_x", "deg_y", "samples", "hide",
            "device", "hops", "frames", "stale_frames", "frames_without_gaze",
            "stale_threshold_ns", "publish_to_read", "count", "cmd")
PUPIL_RECORDING = "recordings/pupil/vedb_pupil_recording_interface/test_recording"
# `fovea simulate pupil --restart 8` rebinds twice per pass of the 21 s recording; at its end the
# simulator exits and the harness starts another one: a Capture restart with a new clock. Not
# --loop: its second lap is not paced (/work/coord/soak_request.md), the datums would come at
# 20-40 k/s.
PUPIL_RESTART_S = 8
# Resource figures: the first WARMUP_S of the soak are not compared (the ring's pages are touched
# in its first 8 s at 2.2 kHz, the allocator grows its arenas in the first bursts, ZeroMQ and the
# recorder fill their queues); then medians over WINDOW_S after warm-up and before the end.
WARMUP_S = 30.0
WINDOW_S = 15.0


class Aborted(Exception):
    """The soak could not go on (fovead exited, a request went unanswered, a deadline passed)."""


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def receive_line(s):
    buf = b""
    while not buf.endswith(b"\n"):
        chunk = s.recv(65536)
        if not chunk:
            break
        buf += chunk
    return buf


def request_raw(sock, data, timeout=2.0):
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
        s.settimeout(timeout)
        s.connect(sock)
        s.sendall(data)
        return receive_line(s)


def request(sock, req, timeout=2.0):
    return json.loads(request_raw(sock, (json.dumps(req) + "\n").encode(), timeout))


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
    """Asks for status every 100 ms and writes `t_s,ms,bursting,record_buffer_kb,error` per
    request (record_buffer_kb: the memory the recorder's queue holds, one known source of RSS
    steps). It runs in its own process: among the harness's threads its timing would include
    waits for Python's GIL (the abuser builds a quarter of a GiB of requests per burst), not only
    fovead's answer."""
    dumped = False
    with open(csv_path, "w", buffering=1) as out:
        out.write("t_s,ms,bursting,record_buffer_kb,error\n")
        while not stop.is_set():
            t = time.monotonic()
            error = ""
            buffer_kb = -1
            try:
                reply = request(sock, {"cmd": "status"}, timeout=5.0)
                buffer_kb = int(reply.get("recording", {}).get("buffer_bytes", -1024)) // 1024
            except (OSError, ValueError, AttributeError) as e:
                error = (str(e) or type(e).__name__).replace(",", ";")
            ms = (time.monotonic() - t) * 1000.0
            if not (error and restarting.is_set()):  # no daemon to answer while it restarts
                out.write("%.3f,%.2f,%d,%d,%s\n" % (t - t0, ms, bursting.is_set(), buffer_kb,
                                                     error))
            if error and not restarting.is_set() and not dumped:
                dumped = True
                dump_stacks(daemon_pid.value, os.path.dirname(csv_path) + "/fovead.stacks.txt")
            # The same 100 ms pace after a failure: a refused connect returns at once.
            time.sleep(max(0.0, 0.1 - (time.monotonic() - t)))


# ---- what the abuser sends -----------------------------------------------------------------
def random_string(rng):
    pick = rng.randrange(7)
    if pick == 0:
        return "".join(chr(rng.randrange(0x20)) for _ in range(rng.randrange(1, 8)))  # controls
    if pick == 1:
        return "".join(chr(rng.choice((0xe9, 0x4e2d, 0x1f600, 0xfffd, 0x202e)))
                       for _ in range(rng.randrange(1, 8)))
    if pick == 2:
        return rng.choice(("../../../../etc/passwd", "relative.xdf", "", "\\", "%s%n", "null"))
    if pick == 3:
        return "y" * rng.choice((255, 256, 4096))
    if pick == 4:
        return rng.choice(ARG_KEYS)
    return "".join(rng.choice("abc/._-0") for _ in range(rng.randrange(0, 12)))


def random_json(rng, depth=0):
    """A random JSON value: scalars of every type and edge, nested arrays and objects."""
    kind = rng.randrange(9 if depth < 5 else 6)
    if kind == 0:
        return rng.choice((0, -1, 1, 7, 2 ** 31, 2 ** 53 + 1, 2 ** 63, -2 ** 63, 2 ** 64, 10 ** 40))
    if kind == 1:
        return rng.choice((0.5, -0.0, 1e-320, -1e300, 1e308, 3.0, float("inf"), float("nan")))
    if kind == 2:
        return random_string(rng)
    if kind == 3:
        return rng.choice((True, False))
    if kind == 4:
        return None
    if kind == 5:
        return rng.choice(([], {}, [[]], {"": {}}))
    if kind in (6, 7):
        return [random_json(rng, depth + 1) for _ in range(rng.randrange(0, 6))]
    return {rng.choice(ARG_KEYS + ("", "\u0000", random_string(rng))): random_json(rng, depth + 1)
            for _ in range(rng.randrange(0, 6))}


def random_request(rng, commands):
    """One request line: usually an existing command with garbage arguments, sometimes a "cmd"
    of a wrong type, no "cmd" at all, a non-object or NaN/Infinity (not JSON)."""
    pick = rng.randrange(10)
    if pick < 6:
        req = {"cmd": rng.choice(commands)}
        for _ in range(rng.randrange(0, 5)):
            req[rng.choice(ARG_KEYS[:-1])] = random_json(rng, 1)
    elif pick == 6:
        req = {"cmd": random_json(rng, 3)}
    elif pick == 7:
        req = random_json(rng)
    elif pick == 8:
        req = {"cmd": rng.choice(commands) + rng.choice((" ", ".", "\u0000", "X"))}
    else:
        req = [rng.choice(commands), random_json(rng, 2)]
    return json.dumps(req).encode() + b"\n"


def garbage_lines():
    return [b"\xff\xfe\xc3\x28 not utf-8\n", b'{"cmd": "status", "x": "\xed\xa0\x80"}\n',
            b'{"cmd": "\xc0\xaf"}\n', b"{" * 5000 + b"\n", b"[1,2,3]\n", b'{"cmd": 7}\n',
            b'{"cmd":"nope"}\n', b"\n", b"\x00" * 100 + b"\n",
            b'{"cmd":"status"}{"cmd":"status"}\n', b'{"cmd":"status"\n',
            b'{"cmd":"latency.report","hops":{"publish_to_read":{"count":1e300}}}\n']


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
        data = a.data or os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                      "../../../shared/data")
        self.pupil_recording = os.path.join(data, PUPIL_RECORDING)
        if not os.path.isdir(self.pupil_recording):
            self.pupil_recording = None
        self.procs = []
        self.failures = []
        self.lost = 0
        self.stop = threading.Event()
        self.quiet = threading.Event()
        self.mp = multiprocessing.get_context("spawn")  # no fork of a threaded harness
        self.restarting, self.bursting = self.mp.Event(), self.mp.Event()
        self.status_stop = self.mp.Event()
        self.status_csv = self.out + "/status.csv"
        self.resources_csv = self.out + "/resources.csv"
        self.resources = []  # RESOURCE_COLUMNS, one row a second
        self.abuse = {"bursts": 0, "connections": 0, "refused": 0, "random": 0, "answered": 0,
                      "unanswered": 0, "slow": 0, "slow_answered": 0, "stallers": 0}
        self.limit = {}  # what fovead answered to requests at and over the size limit
        self.commands = ["status"]
        self.steady = []  # (reader number, its one fovea watch)
        self.checked = set()  # per-sample checks done (an abort runs those that are not)
        self.daemon = None
        self.before = None  # the last status of the first fovead
        self.pupil_sims = []  # every `fovea simulate pupil` run, in order
        self.t0 = time.monotonic()

    # ---- processes -------------------------------------------------------------------------
    def spawn(self, args, name=None, **kw):
        """`name`: its output goes to <out>/<name>.log; without one, the caller passes stdout and
        stderr."""
        if name is not None:
            with open("%s/%s.log" % (self.out, name), "ab") as log:  # the child keeps its copy
                p = subprocess.Popen(args, env=self.env, stdout=log, stderr=log, **kw)
        else:
            p = subprocess.Popen(args, env=self.env, **kw)
        self.procs.append(p)
        return p

    def fail(self, what):
        self.failures.append(what)
        print("FAIL: " + what, flush=True)

    def request(self, req, timeout=2.0):
        try:
            return request(self.sock, req, timeout)
        except (OSError, ValueError) as e:
            raise Aborted("no answer from fovead to %s within %.0f s: %s"
                          % (req.get("cmd"), timeout, e or type(e).__name__)) from e

    def start_daemon(self):
        self.daemon = self.spawn([self.fovead, "--instance", self.instance, "--config",
                                  self.out + "/fovead.toml"], "fovead")
        deadline = time.time() + 20
        while time.time() < deadline:
            if self.daemon.poll() is not None:
                raise Aborted("fovead exited (%s) at start (see %s/fovead.log)"
                              % (self.daemon.returncode, self.out))
            try:
                request(self.sock, {"cmd": "status"})
                return
            except (OSError, ValueError):
                time.sleep(0.1)
        raise Aborted("fovead did not answer within 20 s (see %s/fovead.log)" % self.out)

    # ---- background activity ---------------------------------------------------------------
    def sampler(self):
        with open(self.resources_csv, "w") as out:
            out.write(",".join(RESOURCE_COLUMNS) + "\n")
            while not self.stop.is_set() and not self.quiet.is_set():
                pid = self.daemon.pid
                try:
                    st = open("/proc/%d/status" % pid).read()
                    kb = {k: int(re.search(r"%s:\s+(\d+)" % k, st).group(1))
                          for k in ("VmRSS", "RssAnon", "RssFile", "RssShmem")}
                    thr = int(re.search(r"Threads:\s+(\d+)", st).group(1))
                    fds = len(os.listdir("/proc/%d/fd" % pid))
                    # Bursts and slow writers hold connections; a restart has a new pid.
                    if not self.restarting.is_set() and not self.bursting.is_set():
                        row = (time.monotonic() - self.t0, pid, kb["VmRSS"], kb["RssAnon"],
                               kb["RssFile"], kb["RssShmem"], fds, thr)
                        self.resources.append(row)
                        out.write("%.1f,%d,%d,%d,%d,%d,%d,%d\n" % row)
                        out.flush()
                except (OSError, AttributeError):
                    pass
                time.sleep(1.0)

    def slow_writer(self, data, byte_s, expect):
        """Sends `data` a byte every `byte_s` seconds on one connection it holds throughout, then
        reads the answer; `expect` is what it must say ("ok": a status answer; None: nothing
        expected, the connection is only held)."""
        try:
            with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
                s.connect(self.sock)
                for i in range(len(data)):
                    s.send(data[i:i + 1])
                    if self.stop.wait(byte_s):
                        return
                if expect is None:
                    return
                s.settimeout(5.0)
                reply = json.loads(receive_line(s))
                if reply.get("ok") and "devices" in reply:
                    self.abuse["slow_answered"] += 1
        except (OSError, ValueError):
            pass

    def checked_requests(self, rng, n):
        """Random requests one at a time, each answer read: fovead must answer every complete
        line (an error is an answer) and never hang up without one."""
        for _ in range(n):
            if self.stop.is_set():
                return
            data = random_request(rng, self.commands)
            self.abuse["random"] += 1
            try:
                reply = json.loads(request_raw(self.sock, data, timeout=5.0))
                if isinstance(reply, dict) and "ok" in reply:
                    self.abuse["answered"] += 1
                    continue
            except (OSError, ValueError):
                pass
            self.abuse["unanswered"] += 1
            with open(self.out + "/unanswered.txt", "ab") as f:
                f.write(data[:2000] + b"\n")

    def size_limit(self):
        """A request line of exactly MAX_REQUEST bytes (newline included) must be served, one of
        a byte more refused with "request too large"."""
        for size in (MAX_REQUEST, MAX_REQUEST + 1):
            head = b'{"cmd":"status","pad":"'
            line = head + b"p" * (size - len(head) - 3) + b'"}\n'
            try:
                reply = json.loads(request_raw(self.sock, line, timeout=5.0))
                self.limit[size] = "ok" if reply.get("ok") else reply.get("error", "?")
            except (OSError, ValueError) as e:
                self.limit[size] = "no answer (%s)" % (e or type(e).__name__)

    def abuser(self):
        rng = random.Random(20)
        garbage = garbage_lines()
        try:
            helped = request(self.sock, {"cmd": "help"})
            self.commands = sorted(c for c in helped["commands"] if c not in NOT_SENT)
        except (OSError, ValueError, KeyError):
            pass
        print("abuse: sends %d commands with garbage arguments: %s (not %s)"
              % (len(self.commands), " ".join(self.commands), ", ".join(NOT_SENT)), flush=True)
        self.size_limit()
        while not self.stop.wait(8.0):
            if self.restarting.is_set() or self.quiet.is_set():
                continue
            self.bursting.set()
            # Slow writers: 10 send a status request a byte every 0.2 s (3.4 s) and must get
            # their answer; 10 trickle a request that never ends for 3 s.
            slow = [threading.Thread(target=self.slow_writer, daemon=True,
                                     args=(b'{"cmd":"status"}\n', 0.2, "ok")) for _ in range(10)]
            slow += [threading.Thread(target=self.slow_writer, daemon=True,
                                      args=(b'{"cmd":"status","x', 0.2, None))
                     for _ in range(10)]
            for t in slow:
                t.start()
            self.abuse["slow"] += 10
            self.abuse["stallers"] += 10
            conns = []
            for _ in range(1000):
                s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
                try:
                    s.setblocking(False)
                    s.connect(self.sock)
                    conns.append(s)
                except OSError:
                    self.abuse["refused"] += 1
                    s.close()
            self.abuse["bursts"] += 1
            self.abuse["connections"] += len(conns)
            # The payloads go out in 5 slices 0.2 s apart: 1000 connections are open at once,
            # but their 16 MiB of oversize lines do not all land on fovead's loop in one instant.
            for i, s in enumerate(conns):
                if i % 200 == 199:
                    time.sleep(0.2)
                try:
                    if i == 1:  # deep nesting, at most 64 KiB: parsed on fovead's loop
                        s.send(b"[" * 30000 + b"]" * 30000 + b"\n")
                    elif i % 4 == 0:
                        s.send(b"x" * (1 << 20))  # oversize, no newline
                    elif i % 4 == 1:
                        s.send(rng.choice(garbage))
                    elif i % 4 == 2:
                        s.send(random_request(rng, self.commands))
                except OSError:
                    pass
            self.checked_requests(rng, 40)
            time.sleep(0.5)
            for s in conns:
                s.close()
            for t in slow:
                t.join(10.0)
            time.sleep(0.5)  # the daemon closes its ends
            self.bursting.clear()

    def reader(self, i, churn):
        name = "reader%d" % i
        out = open("%s/%s.out" % (self.out, name), "ab")
        while not self.stop.is_set():
            # Our marker, then fovea watch's lines and notes (stderr too, in order).
            out.write(b"\n" + READER_STARTED + b"\n")
            out.flush()
            p = self.spawn([self.fovea, "--instance", self.instance, "watch", "--wait", "30"],
                           stdout=out, stderr=out)
            if not churn:
                self.steady.append((i, p))
                return
            self.stop.wait(1.0 + (i % 4) * 0.25)
            p.send_signal(signal.SIGKILL)
            p.wait()

    def pupil_feeder(self, port):
        """One simulator at a time, a new one when the last reaches the recording's end."""
        n = 0
        while not self.stop.is_set() and not self.quiet.is_set():
            p = self.spawn([self.fovea, "simulate", "pupil", "--recording", self.pupil_recording,
                            "--address", "tcp://127.0.0.1:%d" % port, "--garbage", "0.01",
                            "--truncate", "0.01", "--restart", str(PUPIL_RESTART_S)],
                           "pupil.%d" % n)
            self.pupil_sims.append(p)
            n += 1
            while p.poll() is None and not self.stop.is_set() and not self.quiet.is_set():
                time.sleep(0.1)

    def stop_pupil(self):
        """Stopped before the last status, so its counts and fovead's cover the same datums
        (what it had queued leaves within its 0.5 s linger)."""
        for p in self.pupil_sims:
            if p.poll() is None:
                p.terminate()
                p.wait(10.0)

    def periodic(self, args, name, every):
        while not self.stop.is_set():
            p = self.spawn(args, "%s.%d" % (name, int(time.time())))
            if self.stop.wait(every):
                break
            p.terminate()
            p.wait()

    # ---- the run ---------------------------------------------------------------------------
    def write_config(self, pty, gp_port, zmq_port, pupil_port):
        with open(self.out + "/fovead.toml", "w") as f:
            f.write('[ring]\nslots = 16384\n'
                    '[[device]]\ndriver = "sim"\nrate_hz = %d\nseed = 11\n'
                    '[[device]]\ndriver = "serial"\nport = "%s"\n'
                    '[[device]]\ndriver = "gazepoint"\naddress = "127.0.0.1:%d"\n'
                    % (SIM_RATE_HZ, pty, gp_port))
            if self.pupil_recording:
                # The recording holds pupil datums (no gaze.pldata): subscribe to them.
                f.write('[[device]]\ndriver = "pupil"\naddress = "tcp://127.0.0.1:%d"\n'
                        'topics = ["pupil."]\n' % pupil_port)
            f.write('[zmq]\npublish = "tcp://127.0.0.1:%d"\nsend_hwm = 1000000\n' % zmq_port)

    def run(self):
        pty = self.out + "/serial.pty"
        gp_port, zmq_port, pupil_port = free_port(), free_port(), free_port()
        self.write_config(pty, gp_port, zmq_port, pupil_port)
        threading.Thread(target=self.periodic, daemon=True, args=(
            [self.fovea, "simulate", "serial", "--link", pty, "--corrupt", "0.01",
             "--reopen-every", "20"], "serial", 1e9)).start()
        threading.Thread(target=self.periodic, daemon=True, args=(
            [self.fovea, "simulate", "gazepoint", "--port", str(gp_port), "--garbage", "0.01"],
            "gazepoint", 15.0)).start()
        if self.pupil_recording:
            threading.Thread(target=self.pupil_feeder, args=(pupil_port,), daemon=True).start()
        else:
            print("pupil: no recording at %s; the soak runs without the Pupil simulator"
                  % os.path.join(self.a.data or "../shared/data", PUPIL_RECORDING))
        self.start_daemon()
        self.zmq_out = self.out + "/zmq.out"
        zmq_out = open(self.zmq_out, "ab")
        self.zmq = self.spawn([self.fovea, "watch", "--zmq", "tcp://127.0.0.1:%d" % zmq_port,
                               "--wait", "30"], stdout=zmq_out, stderr=zmq_out)
        for i in range(8):
            threading.Thread(target=self.reader, args=(i, i >= 4), daemon=True).start()
        time.sleep(2.0)
        self.rec = self.out + "/soak.xdf"
        r = self.request({"cmd": "record.start", "path": self.rec, "flush_ms": FLUSH_MS})
        if not r.get("ok"):
            raise Aborted("record.start: %s" % r)
        self.record_started_ns = time.monotonic_ns()
        self.daemon_pid = self.mp.Value("i", self.daemon.pid)
        self.prober = self.mp.Process(target=probe_status, daemon=True, args=(
            self.sock, self.status_csv, self.t0, self.status_stop, self.restarting,
            self.bursting, self.daemon_pid))
        self.prober.start()
        for fn in (self.sampler,) + (() if self.a.no_abuse else (self.abuser,)):
            threading.Thread(target=fn, daemon=True).start()
        self.t_started = time.monotonic()
        end = self.t_started + self.a.minutes * 60
        while time.monotonic() < end:
            time.sleep(1.0)
            if self.daemon.poll() is not None:
                raise Aborted("fovead exited (%s) during the soak, %.0f s in (see %s/fovead.log)"
                              % (self.daemon.returncode, time.monotonic() - self.t0, self.out))

        self.t_soaked = time.monotonic()
        self.quiet.set()  # the abuser stops; the last figures come from a calm daemon
        calm = time.monotonic() + 20.0  # a burst lasts ~5 s
        while self.bursting.is_set() and time.monotonic() < calm:
            time.sleep(0.1)
        self.stop_pupil()
        time.sleep(2.0)
        first = self.request({"cmd": "status"}, timeout=10.0)
        time.sleep(1.0)
        self.before = self.request({"cmd": "status"}, timeout=10.0)
        self.recorded_rate = (self.recorded(self.before) - self.recorded(first)) / 1.0
        self.restarting.set()
        self.log_at_kill = os.path.getsize(self.out + "/fovead.log")
        self.killed_ns = time.monotonic_ns()
        self.daemon.send_signal(signal.SIGKILL)
        self.daemon.wait()
        killed_at = time.monotonic()
        self.mark_zmq_generation()
        self.start_daemon()
        self.daemon_pid.value = self.daemon.pid
        self.restart_s = time.monotonic() - killed_at
        self.restarting.clear()
        # Readers look for a new ring every 100 ms, the ZeroMQ subscriber reconnects within
        # 100 ms (ZeroMQ's default interval): 3 s to show they follow, even on a loaded machine.
        time.sleep(3.0)
        self.stop.set()
        self.status_stop.set()
        self.prober.join(10.0)
        self.t_checks = time.monotonic()

    def mark_zmq_generation(self):
        """Once the subscriber has printed what the killed publisher sent (its output stops
        growing for 0.5 s; at most 5 s), our marker goes after it: what follows comes from the
        restarted fovead."""
        size, still, deadline = -1, 0, time.monotonic() + 5.0
        while time.monotonic() < deadline and still < 5:
            now = os.path.getsize(self.zmq_out)
            still = still + 1 if now == size else 0
            size = now
            time.sleep(0.1)
        with open(self.zmq_out, "ab") as f:
            f.write(b"\n" + ZMQ_KILLED + b"\n")

    # ---- reading the outputs ---------------------------------------------------------------
    @staticmethod
    def segments(path, markers):
        """Sample indices of a watch output cut at marker lines: [(marker or None, [index])]."""
        segs = [(None, [])]
        with open(path, "rb") as f:
            for line in f:
                m = SAMPLE.search(line)
                if m:
                    segs[-1][1].append(int(m.group(1)))
                    continue
                for key in markers:
                    if key in line:
                        segs.append((key, []))
                        break
        return segs

    @staticmethod
    def steps(idx):
        """(missing, backwards) of a run whose indices must step by exactly one."""
        missing = back = 0
        for a, b in zip(idx, idx[1:]):
            if b > a:
                missing += b - a - 1
            else:
                back += 1
        return missing, back

    def start_export(self):
        """`fovea repair`, then `fovea export` in the background (the other core's work while
        this one reads the watch outputs)."""
        r = subprocess.run([self.fovea, "repair", self.rec], env=self.env, check=False,
                           capture_output=True, text=True)
        print("fovea repair: rc %d %s" % (r.returncode, (r.stdout + r.stderr).strip()[:300]))
        shutil.rmtree(self.out + "/export", ignore_errors=True)
        self.export = subprocess.Popen([self.fovea, "export", self.rec, "--csv",
                                        self.out + "/export"], env=self.env,
                                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)

    def read_recording(self):
        """The FoveaGaze rows `fovea export` wrote, as (ring index, device, t_publish ns) in
        file order. The CSVs are deleted once read (a 60-minute run's are gigabytes)."""
        out = self.out + "/export"
        _, err = self.export.communicate()
        if self.export.returncode != 0:
            self.fail("fovea export: rc %d %s" % (self.export.returncode, err.strip()[:300]))
            return []
        rows = []
        with open(out + "/FoveaGaze.csv", newline="") as f:
            it = csv.reader(f)
            head = next(it)
            ci, cd, ct = (head.index(c) for c in ("ring_index", "device_id", "t_publish_ns"))
            for row in it:
                rows.append((int(float(row[ci])), int(float(row[cd])), int(row[ct])))
        shutil.rmtree(out, ignore_errors=True)
        return rows

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

    # ---- checks ----------------------------------------------------------------------------
    def check_status_latency(self):
        rows = [r.split(",", 4) for r in open(self.status_csv).read().splitlines()[1:]]
        for t, _, _, _, error in rows:
            if error:
                self.fail("status request failed at %s s: %s" % (t, error))

        def percentiles(ms):
            ms = sorted(ms)
            if not ms:
                return float("inf"), "none"
            p99 = ms[min(len(ms) - 1, int(0.99 * len(ms)))]
            return p99, "%d requests, p50 %.1f ms, p99 %.1f ms, max %.1f ms" % (
                len(ms), ms[len(ms) // 2], p99, ms[-1])
        answered = [(float(ms), b == "1") for _, ms, b, _, error in rows if not error]
        buffer_kb = [int(kb) for _, _, _, kb, error in rows if not error and int(kb) >= 0]
        if buffer_kb:
            print("recorder queue: max %d kB, %d kB at the end (status.csv record_buffer_kb)"
                  % (max(buffer_kb), buffer_kb[-1]))
        p99, line = percentiles([ms for ms, _ in answered])
        print("status: %s (timeline: %s)" % (line, self.status_csv))
        print("status during abuse bursts: %s" % percentiles([m for m, b in answered if b])[1])
        print("status between bursts: %s" % percentiles([m for m, b in answered if not b])[1])
        if p99 > 100.0:  # the budget
            self.fail("status p99 %.1f ms > 100 ms" % p99)

    def check_abuse(self):
        a = self.abuse
        print("abuse: %(bursts)d bursts, %(connections)d connections, %(refused)d refused; "
              "%(random)d random requests read back, %(answered)d answered, %(unanswered)d not; "
              "slow writers: %(slow_answered)d of %(slow)d answered, %(stallers)d held open"
              % a)
        print("abuse: a request of %d bytes: %s; of %d bytes: %s"
              % (MAX_REQUEST, self.limit.get(MAX_REQUEST), MAX_REQUEST + 1,
                 self.limit.get(MAX_REQUEST + 1)))
        if a["unanswered"]:
            self.fail("%d random requests got no answer (%s/unanswered.txt)"
                      % (a["unanswered"], self.out))
        if a["slow_answered"] < a["slow"]:
            self.fail("%d slow writers got no status answer" % (a["slow"] - a["slow_answered"]))
        if self.limit.get(MAX_REQUEST) != "ok":
            self.fail("a request of exactly %d bytes was not served: %s"
                      % (MAX_REQUEST, self.limit.get(MAX_REQUEST)))
        if self.limit.get(MAX_REQUEST + 1) != "request too large":
            self.fail("a request of %d bytes was not refused as too large: %s"
                      % (MAX_REQUEST + 1, self.limit.get(MAX_REQUEST + 1)))

    def check_devices(self):
        devices = self.before["devices"]
        for dev in devices:
            print("device %s %s: samples %d published %d frames_dropped %d frames_lost %d "
                  "resyncs %d reconnects %d" % (dev["id"], dev["driver"], dev["samples"],
                                                dev["published"], dev["frames_dropped"],
                                                dev["frames_lost"], dev["resyncs"],
                                                dev["reconnects"]))
            if dev["driver"] == "sim" and dev["samples"] - dev["published"] > 1:
                # Live publishing: every sim sample is published as it arrives (the one the loop
                # is handling when status runs may be counted and not yet published).
                self.lost += dev["samples"] - dev["published"] - 1
                self.fail("sim: %d samples not published" % (dev["samples"] - dev["published"]))

        # A stalled loop makes the simulated tracker skip the samples it could not deliver.
        skipped = 0
        with open(self.out + "/fovead.log", "rb") as f:
            for line in f.read(self.log_at_kill).decode(errors="replace").splitlines():
                m = re.search(r"\[drv\.sim\] loop stalled: skipped (\d+) samples", line)
                if m:
                    skipped += int(m.group(1))
                    print("fovead: " + line.strip())
        sim = [d for d in devices if d["driver"] == "sim"]
        counted = sim[0]["frames_lost"] if sim else 0
        # Counted drops, not losses: the status counts them (frames_lost) and the log says why.
        print("sim drops: %d samples skipped while fovead's loop stalled; status counts %d"
              % (skipped, counted))
        if skipped > counted:
            self.lost += skipped - counted
            self.fail("%d sim samples skipped but not counted" % (skipped - counted))
        self.check_pupil([d for d in devices if d["driver"] == "pupil"])

    def check_pupil(self, devices):
        if not self.pupil_recording:
            return
        totals = [0, 0, 0, 0]
        for n in range(len(self.pupil_sims)):
            log = open("%s/pupil.%d.log" % (self.out, n), errors="replace").read()
            m = re.search(r"(\d+) datums sent, (\d+) garbage, (\d+) truncated, (\d+) restarts",
                          log)
            if not m:
                self.fail("pupil: no summary from simulator %d (%s/pupil.%d.log)"
                          % (n, self.out, n))
                continue
            totals = [a + int(b) for a, b in zip(totals, m.groups())]
        if not devices:
            self.fail("pupil: no pupil device in fovead's status")
            return
        d = devices[0]
        sent, garbage, truncated, rebinds = totals
        # Each simulator after the first is a restart too.
        restarts = rebinds + len(self.pupil_sims) - 1
        print("pupil simulators: %d runs, %d datums sent, %d garbage and %d truncated messages, "
              "%d restarts; fovead: %d decoded, %d dropped, %d published, %d reconnects"
              % (len(self.pupil_sims), sent, garbage, truncated, restarts, d["samples"],
                 d["frames_dropped"], d["published"], d["reconnects"]))
        # The simulators stopped 3 s before this status, and each waits for a subscriber before
        # it streams after a (re)bind: every message sent had time to arrive and be counted.
        if d["samples"] != sent:
            self.lost += max(0, sent - d["samples"])
            self.fail("pupil: the simulator sent %d datums, fovead decoded %d"
                      % (sent, d["samples"]))
        if d["frames_dropped"] != garbage + truncated:
            self.fail("pupil: %d garbage + %d truncated messages sent, %d counted as dropped"
                      % (garbage, truncated, d["frames_dropped"]))
        if d["samples"] != d["published"]:
            self.lost += max(0, d["samples"] - d["published"])
            self.fail("pupil: %d datums decoded, %d published" % (d["samples"], d["published"]))
        # The last restart may come within the driver's silence_s (2 s) plus its reconnect
        # backoff before the simulators were stopped: fovead need not have reconnected yet.
        if restarts < 1 or d["reconnects"] < restarts - 1:
            self.fail("pupil: %d simulator restarts, %d reconnects counted"
                      % (restarts, d["reconnects"]))

    def check_readers(self, complete):
        """Every reader's runs step by one; the steady ones read all the first fovead published
        (up to its ring head at the last status) and follow the restarted one."""
        self.checked.add("readers")
        head = self.before["ring"]["head"] if self.before else None
        steady_readers = dict(self.steady)
        for i in range(8):
            p = steady_readers.get(i)
            path = "%s/reader%d.out" % (self.out, i)
            if not os.path.exists(path):
                continue
            segs = self.segments(path, (READER_STARTED, WATCH_RESTARTED))
            n = sum(len(idx) for _, idx in segs)
            missing = back = 0
            for _, idx in segs:
                m, b = self.steps(idx)
                missing += m
                back += b
            runs = sum(1 for k, _ in segs if k == READER_STARTED)
            restarts = sum(1 for k, _ in segs if k == WATCH_RESTARTED)
            steady = p is not None
            print("reader%d (%s): %d runs, %d samples, %d missing, %d steps back, %d fovead "
                  "restarts seen" % (i, "throughout" if steady else "kill -9 each 1-2 s", runs,
                                     n, missing, back, restarts))
            self.lost += missing
            if missing:
                self.fail("reader%d: %d samples missing from its runs" % (i, missing))
            if back:
                self.fail("reader%d: %d steps back within a ring generation" % (i, back))
            if not steady or not complete:
                continue
            gen1 = [idx for k, idx in segs if k != WATCH_RESTARTED]
            last = max((idx[-1] for idx in gen1 if idx), default=-1)
            after = [idx for k, idx in segs if k == WATCH_RESTARTED]
            if head is not None and last < head - 1:
                self.lost += head - 1 - last
                self.fail("reader%d read up to #%d of the first fovead, which published up to "
                          "#%d" % (i, last, head - 1))
            if restarts != 1 or not any(after) or p.poll() is not None:
                self.fail("reader%d did not follow the restarted fovead" % i)

    def check_recording(self):
        """The recording's gaze rows: each ring index once, each device's in order, and every
        index published from record.start to the kill less the last flush interval."""
        rows = self.read_recording()
        counts = self.xdf_samples(self.rec)
        in_file = sum(counts.values())
        # What the recorder had been handed at the last status, less one flush interval's worth
        # at the rate it was being handed samples, must all be in the repaired file.
        allowance = int(self.recorded_rate * FLUSH_MS / 1000.0) + 1
        missing_total = max(0, self.recorded(self.before) - in_file)
        print("recording after kill -9 + repair: %d samples in the file (%s); the recorder had "
              "%d; allowed to miss %d (%d ms at %.0f/s)"
              % (in_file, counts, self.recorded(self.before), allowance, FLUSH_MS,
                 self.recorded_rate))
        if missing_total > allowance:
            self.lost += missing_total - allowance
            self.fail("recording lost %d samples (> one flush interval, %d)"
                      % (missing_total, allowance))
        if not rows:
            self.fail("recording: no gaze rows read back")
            return []
        seen, dupes, back, last = set(), 0, 0, {}
        for idx, dev, _ in rows:
            if idx in seen:
                dupes += 1
            seen.add(idx)
            if dev in last and idx <= last[dev]:
                back += 1
            last[dev] = idx
        # Window: published after record.start answered, and handed to the recorder (published
        # + the longest look-ahead) a flush interval before the kill, plus 250 ms: the recorder
        # thread's write of the previous interval may still be in progress when it is killed.
        lookahead_ms = max(d.get("lookahead_ms", 0.0) for d in self.before["devices"])
        end_ns = self.killed_ns - int((FLUSH_MS + lookahead_ms + 250) * 1e6)
        self.window_end = end_ns
        inside = [idx for idx, _, t in rows if self.record_started_ns <= t <= end_ns]
        lo, hi = (min(inside), max(inside)) if inside else (0, -1)
        missing = sum(1 for i in range(lo, hi + 1) if i not in seen)
        dropped = int(self.before.get("recording", {}).get("dropped_samples", 0))
        tail = sum(1 for idx, _, t in rows if t > end_ns)
        print("recording, per sample: %d gaze rows, %d devices, %d twice, %d out of order in "
              "their device; ring indices #%d..#%d (published from record.start to %.0f ms "
              "before the kill): %d missing, recorder counted %d dropped; %d rows after that"
              % (len(rows), len(last), dupes, back, lo, hi,
                 (self.killed_ns - end_ns) / 1e6, missing, dropped, tail))
        if dupes:
            self.fail("recording holds %d samples twice" % dupes)
        if back:
            self.fail("recording: %d samples out of order within their device" % back)
        if missing > dropped:
            self.lost += missing - dropped
            self.fail("recording lacks %d samples published while it ran (%d counted dropped)"
                      % (missing, dropped))
        return rows

    def check_zmq(self, rows, complete):
        """The subscriber's first-generation stream holds each index once and the recording's
        rows in the recording's order (both are fed by one observer in one order); it follows
        the restarted fovead (the lines after our marker)."""
        self.checked.add("zmq")
        publisher = self.before.get("zmq", {}) if self.before else {}
        segs = self.segments(self.zmq_out, (ZMQ_KILLED,))
        gen1 = segs[0][1]
        gen2 = [i for k, idx in segs[1:] for i in idx]
        dupes1, dupes2 = len(gen1) - len(set(gen1)), len(gen2) - len(set(gen2))
        failed = int(publisher.get("failed", 0) or 0)
        line = ("zmq subscriber: %d samples from the first fovead (%d twice), %d from the "
                "restarted one (%d twice); publisher sent %s, failed to send %s"
                % (len(gen1), dupes1, len(gen2), dupes2, publisher.get("sent", "?"),
                   publisher.get("failed", "?")))
        if not gen1:
            print(line)
            self.fail("zmq subscriber received nothing")
            return
        if dupes1 or dupes2:
            self.fail("zmq delivered %d samples twice" % (dupes1 + dupes2))
        if rows:
            # Order: the positions in the recording of what the subscriber got must increase.
            pos = {idx: k for k, (idx, _, _) in enumerate(rows)}
            got = [pos[i] for i in gen1 if i in pos]
            back = sum(1 for a, b in zip(got, got[1:]) if b <= a)
            # Missing: the rows of the recording's checked window (published after record.start
            # and handed to the recorder >= 0.5 s before the kill, long sent by then).
            have = set(gen1)
            window = [idx for idx, _, t in rows if self.record_started_ns <= t <= self.window_end]
            missing = sum(1 for idx in window if idx not in have)
            line += ("; in the recording's order: %d of its rows, %d out of order; of the %d "
                     "in its checked window %d missing" % (len(got), back, len(window), missing))
            if back:
                self.fail("zmq: %d samples out of the recording's order" % back)
            if missing > failed:
                self.lost += missing - failed
                self.fail("zmq: %d of the recording's samples missing (%d failed to send)"
                          % (missing, failed))
        print(line)
        if complete and not gen2:
            self.fail("zmq subscriber did not follow the restarted fovead")

    def check_resources(self):
        pts = [r for r in self.resources if r[1] == self.resources[0][1]] if self.resources else []
        col = RESOURCE_COLUMNS.index
        t_start = pts[0][0] if pts else 0.0
        warm = [p for p in pts if t_start + WARMUP_S <= p[0] < t_start + WARMUP_S + WINDOW_S]
        late = [p for p in pts if p[0] >= pts[-1][0] - WINDOW_S] if pts else []
        after = [p for p in pts if p[0] >= t_start + WARMUP_S]
        if len(warm) < 3 or len(late) < 3 or warm[-1][0] >= late[0][0]:
            print("fovead resources: too short a run to compare after %.0f s of warm-up (%d "
                  "samples)" % (WARMUP_S, len(pts)))
            return

        def median(rows, name):
            return statistics.median(r[col(name)] for r in rows)

        def slope(name):  # per hour, least squares over everything after warm-up
            xs = [(p[0] - after[0][0]) / 3600.0 for p in after]
            ys = [p[col(name)] for p in after]
            mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
            var = sum((x - mx) ** 2 for x in xs)
            return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / var if var else 0.0
        fig = {n: (median(warm, n), median(late, n), slope(n))
               for n in ("rss_kb", "anon_kb", "shmem_kb", "fds", "threads")}
        print("fovead resources (%s), medians at %.0f-%.0f s and over the last %.0f s, slope "
              "after warm-up: RSS %d -> %d kB (%+.0f kB/h), anon %d -> %d kB (%+.0f kB/h), "
              "shmem %d -> %d kB, fds %d -> %d (%+.1f/h), threads %d -> %d (%+.1f/h)"
              % (self.resources_csv, warm[0][0], warm[-1][0], WINDOW_S,
                 *fig["rss_kb"], *fig["anon_kb"], *fig["shmem_kb"][:2], *fig["fds"],
                 *fig["threads"]))
        # fovead's threads are one per role (loop, drivers' workers, recorder, ZeroMQ I/O):
        # none is per connection or per reconnect, so any growth is a leak.
        if fig["threads"][1] > fig["threads"][0]:
            self.fail("threads grew %d -> %d" % fig["threads"][:2])
        # fds: between bursts fovead holds its own files and sockets plus, at the moment of a
        # sample, at most the prober's connection and one socket or pty of a device in the middle
        # of reconnecting (serial, Gazepoint, Pupil): 4. A leak of one per abusive connection
        # would add ~1000 a burst, one per reconnect ~10 in 2 minutes.
        if fig["fds"][1] - fig["fds"][0] > 4:
            self.fail("fds grew %d -> %d after warm-up" % fig["fds"][:2])
        # Anonymous memory: a burst's oversize requests fill 250 request buffers of 64 KiB
        # (16 MiB) that glibc may keep after they are freed; more than that after warm-up means
        # buffers kept per connection (a 2-minute run has ~8 bursts: 128 MiB if each leaked).
        if fig["anon_kb"][1] - fig["anon_kb"][0] > 16 * 1024:
            self.fail("anonymous RSS grew %d -> %d kB after warm-up" % fig["anon_kb"][:2])
        if self.a.minutes >= 10:
            # Long runs: slopes over > 9 minutes average out the bursts' steps (64 MB/h: a
            # kept burst's buffers every few minutes at most; 60 fds/h: one a minute).
            if fig["rss_kb"][2] > 64 * 1024:
                self.fail("RSS grows %.0f kB/h" % fig["rss_kb"][2])
            if fig["fds"][2] > 60:
                self.fail("fds grow %.0f/h" % fig["fds"][2])
        else:
            print("fovead resources: %.0f minutes show leaks per connection, per burst or per "
                  "reconnect; slow growth needs --minutes 60 (slopes checked from 10 minutes)"
                  % self.a.minutes)

    def report(self):
        self.start_export()
        self.check_status_latency()
        self.check_abuse()
        self.check_devices()
        self.check_readers(complete=True)
        rows = self.check_recording()
        self.check_zmq(rows, complete=True)
        self.check_resources()
        print("restart: fovead back %.2f s after kill -9" % self.restart_s)
        now = time.monotonic()
        print("wall: %.0f s: %.0f s start, %.0f s soak, %.0f s kill -9 and restart, %.0f s checks"
              % (now - self.t0, self.t_started - self.t0, self.t_soaked - self.t_started,
                 self.t_checks - self.t_soaked, now - self.t_checks))

    def partial_report(self):
        """After an abort: the per-sample checks that need no answer from fovead."""
        for name, check in (("readers", lambda: self.check_readers(complete=False)),
                            ("zmq", lambda: self.check_zmq([], complete=False))):
            if name in self.checked:
                continue
            try:
                check()
            except Exception as e:  # noqa: BLE001 - whatever is left to read may be cut short
                print("(partial check: %s: %s)" % (type(e).__name__, e))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--minutes", type=float, default=2.0)
    ap.add_argument("--build", default="build/main")
    ap.add_argument("--out", default="build/soak")
    ap.add_argument("--data", help="the shared data directory (default ../shared/data)")
    ap.add_argument("--no-abuse", action="store_true", help="no abusive control-socket client")
    a = ap.parse_args()
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))

    def deadline(signo, frame):
        raise Aborted("the soak did not finish in time (a hung step: see the logs in %s)" % a.out)
    signal.signal(signal.SIGALRM, deadline)
    def terminated(signo, frame):
        raise Aborted("terminated (SIGTERM)")
    signal.signal(signal.SIGTERM, terminated)
    # The run takes --minutes plus ~15 s; 90 s more and the harness gives up on its own, before
    # ctest's 300 s timeout of the 2-minute run would kill it without a summary.
    signal.alarm(int(a.minutes * 60 + 90))
    s = Soak(a)
    error = None
    try:
        s.run()
        # The checks read every reader's output: ~30 s a minute of soak would be very slow.
        signal.alarm(int(60 + a.minutes * 30))
        s.report()
    except (Exception, KeyboardInterrupt) as e:  # noqa: BLE001 - any failure ends in a summary
        error = "%s: %s" % (type(e).__name__, e)
    finally:
        signal.alarm(0)
        s.stop.set()
        s.status_stop.set()
        for p in s.procs:
            if p.poll() is None:
                p.kill()
                p.wait()
    if error:
        s.partial_report()
        print("ERROR: the soak aborted: %s" % error)
    if s.failures:
        print("%d checks failed: %s" % (len(s.failures), "; ".join(s.failures)))
    print("lost %d%s" % (s.lost, " (incomplete: the soak aborted, see ERROR above)"
                         if error else ""), flush=True)
    sys.exit(2 if error else 0 if s.lost == 0 and not s.failures else 1)


if __name__ == "__main__":
    main()
