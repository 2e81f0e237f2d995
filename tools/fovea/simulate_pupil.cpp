// `fovea simulate pupil --recording DIR|FILE.pldata [--address tcp://HOST:PORT] [--fast]
// [--garbage P] [--truncate P] [--restart S] [--loop]`: Pupil Capture's network API serving a
// real recording. Pupil Remote (REP) answers SUB_PORT, v (the recording's Pupil Capture
// version), t (Pupil time: the recording's clock, running continuously from its first datum's
// stamp at start-up) and T; the bus (XPUB, so streaming starts when a subscriber arrives)
// publishes each gaze (or, without gaze, pupil) datum as [datum topic, the recorded msgpack
// bytes unchanged], at the recorded pace or as fast as possible; the stamps being fixed, a datum
// arrives as old as the wait for the subscriber. Faults are extra messages — the recorded datums
// all still go out: --garbage sends random bytes before a datum, --truncate a copy cut in half;
// --restart S closes both sockets every S seconds of streaming, is away for a second, binds again
// (as Capture restarting) and goes on where it stopped once a subscriber is back.
#include "simulate_pupil.hpp"

#include <zmq.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "fovea/import/pldata.hpp"
#include "fovea/import/pupil_datum.hpp"

namespace fovea::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

struct Options {
    std::string recording;
    std::string address = "tcp://127.0.0.1:50020";
    bool fast = false;
    double garbage = 0.0, truncate = 0.0;
    double restart_s = 0.0;
    bool loop = false;
};

// The .pldata to serve and the version to report.
struct Source {
    std::string pldata;
    std::string version = "unknown";
};

Source find_source(const std::string& path) {
    Source s;
    const fs::path p(path);
    if (fs::is_regular_file(p)) {
        s.pldata = path;
        return s;
    }
    if (!fs::is_directory(p)) throw std::runtime_error(path + ": no such recording");
    for (const char* name : {"gaze.pldata", "pupil.pldata"})
        if (fs::exists(p / name)) {
            s.pldata = (p / name).string();
            break;
        }
    if (s.pldata.empty())
        for (const auto& e : fs::directory_iterator(p))
            if (e.path().extension() == ".pldata" &&
                e.path().filename().string().find("gaze") != std::string::npos)
                s.pldata = e.path().string();
    if (s.pldata.empty()) throw std::runtime_error(path + ": no gaze or pupil .pldata");
    std::ifstream info(p / "info.player.json");
    if (info) {
        try {
            s.version = nlohmann::json::parse(info).value("recording_software_version", s.version);
        } catch (const std::exception&) {}
    }
    return s;
}

// The first datum's Pupil time, where the simulated clock starts (0 without one).
double first_stamp(const std::string& pldata) {
    auto f = import::PldataFile::open(pldata);
    std::string_view outer, datum;
    while (f && (*f)->next(outer, datum))
        if (auto d = import::decode_pupil_datum(datum); d && std::isfinite(d->timestamp))
            return d->timestamp;
    return 0.0;
}

double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

class Server {
public:
    Server(const Options& o, const Source& src) : o_(o), src_(src), rng_(7) {
        context_ = zmq_ctx_new();
        clock_base_ = first_stamp(src.pldata);
        clock_start_ = Clock::now();
    }
    ~Server() {
        unbind();
        zmq_ctx_term(context_);
    }

    void run() {
        bool printed = false;
        for (;;) {
            bind();
            if (!printed) {
                std::printf("%s\n", remote_endpoint_.c_str());
                std::fflush(stdout);
                printed = true;
            }
            std::fprintf(stderr, "fovea simulate pupil: Pupil Remote %s, bus %s, serving %s\n",
                         remote_endpoint_.c_str(), bus_endpoint_.c_str(), src_.pldata.c_str());
            const bool more = stream();
            if (!more || g_stop) break;
            unbind();
            ++restarts_;
            std::fprintf(stderr, "fovea simulate pupil: restarting (away for 1 s)\n");
            for (int i = 0; i < 20 && !g_stop; ++i)
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        std::fprintf(
            stderr,
            "fovea simulate pupil: %llu datums sent, %llu garbage, %llu truncated, "
            "%llu restarts, %llu Remote requests\n",
            static_cast<unsigned long long>(sent_), static_cast<unsigned long long>(garbage_sent_),
            static_cast<unsigned long long>(truncated_sent_),
            static_cast<unsigned long long>(restarts_), static_cast<unsigned long long>(requests_));
    }

private:
    void bind() {
        std::string address = o_.address;
        if (address.size() > 2 && address.compare(address.size() - 2, 2, ":0") == 0)
            address.replace(address.size() - 1, 1, "*");  // ZeroMQ's "any free port"
        remote_ = socket(ZMQ_REP, address);
        remote_endpoint_ = last_endpoint(remote_);
        if (o_.address.find(":0") != std::string::npos ||
            o_.address.find(":*") != std::string::npos)
            o_.address = remote_endpoint_;  // a restart binds the same port again
        const std::string host = remote_endpoint_.substr(0, remote_endpoint_.rfind(':'));
        bus_ = socket(ZMQ_XPUB, host + ":*");
        bus_endpoint_ = last_endpoint(bus_);
        subscribed_ = false;
    }

    void unbind() {
        if (remote_) zmq_close(remote_);
        if (bus_) zmq_close(bus_);
        remote_ = bus_ = nullptr;
    }

    void* socket(int type, const std::string& endpoint) {
        void* s = zmq_socket(context_, type);
        const int linger = 500, hwm = 1'000'000;
        zmq_setsockopt(s, ZMQ_LINGER, &linger, sizeof linger);
        zmq_setsockopt(s, ZMQ_SNDHWM, &hwm, sizeof hwm);
        for (int attempt = 0; zmq_bind(s, endpoint.c_str()) != 0; ++attempt) {
            if (attempt > 50)  // a restart may find the old port in TIME_WAIT for a moment
                throw std::runtime_error("cannot bind " + endpoint + ": " +
                                         zmq_strerror(zmq_errno()));
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        return s;
    }

    static std::string last_endpoint(void* s) {
        char ep[256] = {};
        std::size_t len = sizeof ep;
        zmq_getsockopt(s, ZMQ_LAST_ENDPOINT, ep, &len);
        return ep;
    }

    double pupil_now() const { return clock_base_ + seconds_since(clock_start_); }

    // Answers Pupil Remote and notes subscriptions, waiting up to `ms`.
    void serve(int ms) {
        zmq_pollitem_t items[2] = {{remote_, 0, ZMQ_POLLIN, 0}, {bus_, 0, ZMQ_POLLIN, 0}};
        if (zmq_poll(items, 2, ms) <= 0) return;
        char buf[512];
        if (items[1].revents & ZMQ_POLLIN) {
            const int n = zmq_recv(bus_, buf, sizeof buf, ZMQ_DONTWAIT);
            if (n > 0 && buf[0] == 1) subscribed_ = true;
        }
        if (!(items[0].revents & ZMQ_POLLIN)) return;
        const int n = zmq_recv(remote_, buf, sizeof buf - 1, ZMQ_DONTWAIT);
        if (n < 0) return;
        ++requests_;
        const std::string cmd(buf, static_cast<std::size_t>(std::min<int>(n, sizeof buf - 1)));
        std::string reply = "Unknown command.";
        if (cmd == "SUB_PORT") {
            reply = bus_endpoint_.substr(bus_endpoint_.rfind(':') + 1);
        } else if (cmd == "v") {
            reply = src_.version;
        } else if (cmd == "t") {
            char t[64];
            std::snprintf(t, sizeof t, "%.9f", pupil_now());
            reply = t;
        } else if (cmd.rfind("T ", 0) == 0) {
            char* end = nullptr;
            const double t = std::strtod(cmd.c_str() + 2, &end);
            if (end != cmd.c_str() + 2) {
                // Capture's T moves its clock; our datums keep their recorded stamps.
                lag_ += t - pupil_now();
                clock_base_ = t;
                clock_start_ = Clock::now();
                reply = "Timesync successful.";
            }
        }
        zmq_send(remote_, reply.data(), reply.size(), 0);
    }

    void publish(const std::string& topic, std::string_view datum) {
        zmq_send(bus_, topic.data(), topic.size(), ZMQ_SNDMORE);
        zmq_send(bus_, datum.data(), datum.size(), 0);
    }

    // Streams from where it stopped; true when --restart cut it (call again), false at the end.
    bool stream() {
        while (!subscribed_ && !g_stop) serve(20);
        std::uniform_real_distribution<double> chance(0.0, 1.0);
        const auto started = Clock::now();
        bool paced = false;
        for (;;) {
            if (!file_) {
                auto f = import::PldataFile::open(src_.pldata);
                if (!f) throw std::runtime_error(f.error().message);
                file_ = std::move(*f);
            }
            std::string_view outer, datum;
            while (!g_stop && file_->next(outer, datum)) {
                auto d = import::decode_pupil_datum(datum);
                const std::string topic = d && !d->topic.empty() ? d->topic : std::string(outer);
                const bool stamped = d && std::isfinite(d->timestamp);
                if (stamped && !paced) {  // (re)starting: the recorded pace from here on
                    lag_ = std::max(0.0, pupil_now() - d->timestamp);
                    paced = true;
                }
                if (!o_.fast && stamped) {
                    while (!g_stop && pupil_now() - lag_ < d->timestamp)
                        serve(std::clamp(
                            static_cast<int>((d->timestamp - pupil_now() + lag_) * 1e3), 0, 20));
                }
                serve(0);
                if (chance(rng_) < o_.garbage) {
                    std::string junk(1 + rng_() % 64, '\0');
                    for (char& c : junk) c = static_cast<char>(0xc1);  // never valid msgpack
                    publish(topic, junk);
                    ++garbage_sent_;
                }
                if (chance(rng_) < o_.truncate) {
                    publish(topic, datum.substr(0, datum.size() / 2));
                    ++truncated_sent_;
                }
                publish(topic, datum);
                ++sent_;
                if (o_.restart_s > 0 && seconds_since(started) >= o_.restart_s) return true;
            }
            if (g_stop) return false;
            file_.reset();
            if (!o_.loop) break;
        }
        // Stay up a moment so the last datums leave and a late Remote request is answered.
        const auto end = Clock::now() + std::chrono::milliseconds(500);
        while (Clock::now() < end && !g_stop) serve(20);
        return false;
    }

    Options o_;
    Source src_;
    std::mt19937 rng_;
    void* context_ = nullptr;
    void* remote_ = nullptr;
    void* bus_ = nullptr;
    std::string remote_endpoint_, bus_endpoint_;
    bool subscribed_ = false;
    std::unique_ptr<import::PldataFile> file_;
    double clock_base_ = 0.0;
    double lag_ = 0.0;  // how far the datums' recorded stamps trail Pupil time
    Clock::time_point clock_start_ = Clock::now();
    uint64_t sent_ = 0, garbage_sent_ = 0, truncated_sent_ = 0, restarts_ = 0, requests_ = 0;
};

}  // namespace

void add_simulate_pupil(CLI::App& simulate) {
    static Options o;
    CLI::App* p = simulate.add_subcommand(
        "pupil", "Pupil Capture's network API serving a recording (prints the Remote address)");
    p->add_option("--recording", o.recording, "Pupil recording folder or .pldata file")->required();
    p->add_option("--address", o.address, "Pupil Remote endpoint (port 0: any free port)");
    p->add_flag("--fast", o.fast, "As fast as possible instead of the recorded pace");
    p->add_option("--garbage", o.garbage, "Chance per datum of random bytes sent before it")
        ->check(CLI::Range(0.0, 1.0));
    p->add_option("--truncate", o.truncate, "Chance per datum of a half copy sent before it")
        ->check(CLI::Range(0.0, 1.0));
    p->add_option("--restart", o.restart_s, "Restart (rebind) every S seconds of streaming")
        ->check(CLI::Range(0.0, 3600.0));
    p->add_flag("--loop", o.loop, "Start over at the end");
    p->callback([] {
        std::signal(SIGINT, on_signal);
        std::signal(SIGTERM, on_signal);
        Server server(o, find_source(o.recording));
        server.run();
    });
}

}  // namespace fovea::cli
