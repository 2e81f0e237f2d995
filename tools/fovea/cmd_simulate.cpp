// `fovea simulate serial|gazepoint|pupil|osc`: a simulated tracker behind a real kernel object, for
// driving fovead (and its tests) without hardware.
//   serial:    opens a pty, prints the path to connect to, streams protocol frames
//              (drivers/serial/PROTOCOL.md) with optional garbage, drops, stalls and reopens.
//   gazepoint: serves the Open Gaze API on 127.0.0.1 and prints host:port.
//   pupil, osc: simulate_pupil.cpp, simulate_osc.cpp.
#include <poll.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include "command.hpp"
#include "gazepoint/server_sim.hpp"
#include "serial/device_sim.hpp"
#include "sim/sim_tracker.hpp"
#include "simulate_osc.hpp"
#include "simulate_pupil.hpp"

namespace fovea::cli {
namespace {

using Clock = std::chrono::steady_clock;

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

struct SimOptions {
    double rate_hz = 1000.0;
    uint64_t seed = 1;
    bool monocular = false;
    int counter_bits = 32;
    double tick_hz = 1e6;
    double drift_ppm = 0.0;
    double duration_s = 0.0;  // 0: until SIGINT/SIGTERM
};

void add_sim_options(CLI::App& app, SimOptions& o) {
    app.add_option("--rate", o.rate_hz, "Sampling rate, Hz (60..2000)")
        ->check(CLI::Range(60.0, 2000.0));
    app.add_option("--seed", o.seed, "Simulated tracker seed");
    app.add_flag("--monocular", o.monocular, "Only the left eye");
    app.add_option("--counter-bits", o.counter_bits, "Device counter width (16, 32, 64)")
        ->check(CLI::IsMember({16, 32, 64}));
    app.add_option("--tick-hz", o.tick_hz, "Device counter ticks per second");
    app.add_option("--drift-ppm", o.drift_ppm, "Device clock error, ppm");
    app.add_option("--duration", o.duration_s, "Stop after S seconds (0: run until interrupted)");
}

drivers::sim::SimConfig to_sim_config(const SimOptions& o) {
    drivers::sim::SimConfig c;
    c.rate_hz = o.rate_hz;
    c.seed = o.seed;
    c.binocular = !o.monocular;
    c.counter_bits = o.counter_bits;
    c.tick_hz = o.tick_hz;
    c.drift_ppm = o.drift_ppm;
    if (auto v = drivers::sim::validate(c); !v.ok()) throw std::runtime_error(v.error().message);
    return c;
}

void install_signals() {
    struct sigaction sa {};
    sa.sa_handler = on_signal;  // no SA_RESTART: poll() returns on a signal
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    signal(SIGPIPE, SIG_IGN);
}

struct SerialOptions {
    SimOptions sim;
    double garbage = 0.0, drop = 0.0, corrupt = 0.0;
    int stall_ms = 0;
    double stall_every_s = 1.0;
    double reopen_every_s = 0.0;
    int unplugged_ms = 200;
    std::string link;
};

std::unique_ptr<drivers::serial::PtyPort> open_pty(const std::string& link) {
    auto p = drivers::serial::PtyPort::open(link);
    if (!p.ok()) throw std::runtime_error(p.error().message);
    // The path on stdout, alone on its line: scripts read it to configure `port`.
    std::printf("%s\n", (*p)->path().c_str());
    std::fflush(stdout);
    return std::move(*p);
}

void run_serial(const SerialOptions& o) {
    using namespace drivers::serial;
    install_signals();
    FaultOptions faults;
    faults.garbage = o.garbage;
    faults.drop = o.drop;
    faults.corrupt = o.corrupt;
    faults.seed = o.sim.seed;
    DeviceEmulator dev(to_sim_config(o.sim), faults, "Fovea simulated serial tracker");
    auto pty = open_pty(o.link);
    std::fprintf(stderr, "fovea simulate serial: %s (%s), %.0f Hz\n", pty->path().c_str(),
                 pty->slave_path().c_str(), dev.rate_hz());

    std::vector<uint8_t> pending;
    dev.hello(pending);
    uint64_t overflow_bytes = 0, reopens = 0, stalls = 0;
    const auto started = Clock::now();
    auto t0 = started;
    uint64_t n = 0;
    double rate = dev.rate_hz();
    auto next_stall = started + std::chrono::duration<double>(o.stall_every_s);
    auto next_reopen = started + std::chrono::duration<double>(o.reopen_every_s);
    const auto period = [&] { return std::chrono::duration<double>(1.0 / rate); };

    while (!g_stop) {
        auto now = Clock::now();
        if (o.sim.duration_s > 0 &&
            now - started >= std::chrono::duration<double>(o.sim.duration_s))
            break;
        if (o.reopen_every_s > 0 && now >= next_reopen) {
            // Unplug: the port disappears for a while, then a new one comes up.
            pty.reset();
            pending.clear();
            std::this_thread::sleep_for(std::chrono::milliseconds(o.unplugged_ms));
            pty = open_pty(o.link);
            ++reopens;
            dev.hello(pending);
            now = Clock::now();
            next_reopen = now + std::chrono::duration<double>(o.reopen_every_s);
            t0 = now;  // the tracker's own clock keeps running; only the schedule restarts
            n = 0;
        }
        while (t0 +
                   std::chrono::duration_cast<Clock::duration>(period() * static_cast<double>(n)) <=
               now) {
            dev.next_sample(pending);
            ++n;
        }
        if (o.stall_ms > 0 && now >= next_stall && pending.size() > 1) {
            // The device stops mid-frame: half of what is pending, then silence.
            const std::size_t half = pending.size() / 2;
            auto w = pty->write({pending.data(), half});
            if (w.ok()) pending.erase(pending.begin(), pending.begin() + static_cast<long>(*w));
            std::this_thread::sleep_for(std::chrono::milliseconds(o.stall_ms));
            next_stall = Clock::now() + std::chrono::duration<double>(o.stall_every_s);
            ++stalls;
            continue;
        }
        if (!pending.empty()) {
            auto w = pty->write(pending);
            if (!w.ok()) throw std::runtime_error(w.error().message);
            pending.erase(pending.begin(), pending.begin() + static_cast<long>(*w));
            if (pending.size() > (1u << 20)) {
                // Nobody reads: the device's transmit buffer overflows.
                overflow_bytes += pending.size();
                pending.clear();
            }
        }
        uint8_t in[512];
        if (auto r = pty->read(in); r.ok() && *r > 0) dev.on_host_bytes({in, *r}, pending);
        if (dev.rate_hz() != rate) {
            rate = dev.rate_hz();
            t0 = Clock::now();
            n = 0;
            std::fprintf(stderr, "fovea simulate serial: host set the rate to %.0f Hz\n", rate);
        }
        const auto next_due =
            t0 + std::chrono::duration_cast<Clock::duration>(period() * static_cast<double>(n));
        const auto wait_ms =
            std::chrono::duration_cast<std::chrono::milliseconds>(next_due - Clock::now());
        pollfd pfd{pty->master_fd(), static_cast<short>(POLLIN | (pending.empty() ? 0 : POLLOUT)),
                   0};
        ::poll(&pfd, 1, static_cast<int>(std::clamp<int64_t>(wait_ms.count(), 0, 50)));
    }
    const auto& s = dev.stats();
    std::fprintf(
        stderr,
        "fovea simulate serial: sent %llu frames (%llu hello), dropped %llu, corrupted %llu, "
        "garbage bursts %llu, stalls %llu, reopens %llu, overflow bytes %llu\n",
        static_cast<unsigned long long>(s.frames), static_cast<unsigned long long>(s.hellos),
        static_cast<unsigned long long>(s.dropped), static_cast<unsigned long long>(s.corrupted),
        static_cast<unsigned long long>(s.garbage_bursts), static_cast<unsigned long long>(stalls),
        static_cast<unsigned long long>(reopens), static_cast<unsigned long long>(overflow_bytes));
}

struct GazepointOptions {
    SimOptions sim;
    int port = 4242;
    double drop = 0.0, garbage = 0.0;
    double tick_hz = 1e7;
};

void run_gazepoint(const GazepointOptions& o) {
    boost::asio::io_context io;
    drivers::gazepoint::ServerOptions so;
    so.port = static_cast<uint16_t>(o.port);
    so.sim = to_sim_config(o.sim);
    so.drop = o.drop;
    so.garbage = o.garbage;
    so.tick_hz = o.tick_hz;
    drivers::gazepoint::SimServer server(io, so);
    if (auto r = server.start(); !r.ok()) throw std::runtime_error(r.error().message);
    std::printf("127.0.0.1:%u\n", server.port());
    std::fflush(stdout);
    std::fprintf(stderr, "fovea simulate gazepoint: Open Gaze API on 127.0.0.1:%u, %.0f Hz\n",
                 server.port(), so.sim.rate_hz);
    boost::asio::signal_set signals(io, SIGINT, SIGTERM);
    boost::asio::steady_timer deadline(io);
    const auto finish = [&] {
        server.stop();
        signals.cancel();
        deadline.cancel();
    };
    signals.async_wait([&](boost::system::error_code ec, int) {
        if (!ec) finish();
    });
    if (o.sim.duration_s > 0) {
        deadline.expires_after(std::chrono::duration_cast<Clock::duration>(
            std::chrono::duration<double>(o.sim.duration_s)));
        deadline.async_wait([&](boost::system::error_code ec) {
            if (!ec) finish();
        });
    }
    io.run();
    const auto s = server.stats();
    std::fprintf(
        stderr,
        "fovea simulate gazepoint: %llu clients, %llu records sent, %llu dropped, "
        "%llu garbage bursts\n",
        static_cast<unsigned long long>(s.clients), static_cast<unsigned long long>(s.records),
        static_cast<unsigned long long>(s.dropped), static_cast<unsigned long long>(s.garbage));
}

void setup_simulate(CLI::App& app) {
    app.require_subcommand(1);
    static SerialOptions serial;
    CLI::App* s =
        app.add_subcommand("serial", "Simulated serial tracker on a pty (prints its path)");
    add_sim_options(*s, serial.sim);
    s->add_option("--garbage", serial.garbage, "Chance per frame of random bytes before it")
        ->check(CLI::Range(0.0, 1.0));
    s->add_option("--drop", serial.drop, "Chance per frame of not sending it")
        ->check(CLI::Range(0.0, 1.0));
    s->add_option("--corrupt", serial.corrupt, "Chance per frame of a flipped byte")
        ->check(CLI::Range(0.0, 1.0));
    s->add_option("--stall-ms", serial.stall_ms, "Stop mid-frame for N ms every --stall-every s")
        ->check(CLI::Range(0, 60000));
    s->add_option("--stall-every", serial.stall_every_s, "Seconds between stalls")
        ->check(CLI::Range(0.001, 3600.0));
    s->add_option("--reopen-every", serial.reopen_every_s,
                  "Close the pty and open a new one every S seconds (0: never)")
        ->check(CLI::Range(0.0, 3600.0));
    s->add_option("--unplugged-ms", serial.unplugged_ms, "How long the port stays away on reopen")
        ->check(CLI::Range(0, 60000));
    s->add_option("--link", serial.link,
                  "Symlink kept pointing at the current pty (use it as the driver's port)");
    s->callback([] { run_serial(serial); });

    static GazepointOptions gp;
    CLI::App* g =
        app.add_subcommand("gazepoint", "Open Gaze API server on 127.0.0.1 (prints host:port)");
    add_sim_options(*g, gp.sim);
    g->add_option("--port", gp.port, "TCP port (0: any free port)")->check(CLI::Range(0, 65535));
    g->add_option("--drop", gp.drop, "Chance per record of skipping it (CNT still advances)")
        ->check(CLI::Range(0.0, 1.0));
    g->add_option("--garbage", gp.garbage, "Chance per record of stray bytes before it")
        ->check(CLI::Range(0.0, 1.0));
    g->add_option("--tick-frequency", gp.tick_hz, "TIME_TICK_FREQUENCY, Hz");
    g->callback([] { run_gazepoint(gp); });

    add_simulate_pupil(app);
    add_simulate_osc(app);
}

const Command kSimulate{"simulate", "Run a simulated tracker behind a pty or a TCP port",
                        &setup_simulate};

}  // namespace
}  // namespace fovea::cli
