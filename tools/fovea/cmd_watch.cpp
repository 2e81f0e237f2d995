// fovea watch: one line per gaze sample from the ring.
#include <cstdio>

#include "command.hpp"
#include "gaze_format.hpp"
#include "ring_session.hpp"
#include "zmq_gaze.hpp"

namespace fovea::cli {
namespace {

struct WatchOptions {
    uint64_t count = 0;  // 0: until interrupted
    double wait_s = 5.0;
    uint32_t every = 1;
    std::string zmq;  // subscribe to a fovead [zmq] publisher instead of the local ring
};

void run_watch_zmq(const WatchOptions& o);

void run_watch(const WatchOptions& o) {
    if (!o.zmq.empty()) return run_watch_zmq(o);
    auto client = open_ring(global_options().instance, static_cast<int>(o.wait_s * 1000));
    uint64_t cursor = client->head();
    uint64_t generation = client->info().generation;
    uint64_t shown = 0, seen = 0, dropped = 0;
    while (o.count == 0 || shown < o.count) {
        if (!client->wait(cursor, static_cast<int32_t>(o.wait_s * 1000))) {
            // A restarted fovead: wait() re-attached and moved the cursor to the new ring's head.
            if (const uint64_t g = client->info().generation; g != generation) {
                generation = g;
                std::fprintf(stderr, "fovea watch: fovead restarted; following its new ring\n");
                continue;
            }
            if (client->head() <= cursor)
                throw std::runtime_error("no gaze for " + std::to_string(o.wait_s) +
                                         " s: is the tracker delivering?");
            continue;
        }
        auto batch = client->read(cursor, 256);
        dropped += batch.dropped;
        const int64_t now = monotonic_ns();
        for (const auto& r : batch.records) {
            if (seen++ % o.every) continue;
            std::printf("%s\n", watch_line(r, now).c_str());
            if (o.count && ++shown >= o.count) break;
        }
        std::fflush(stdout);
    }
    if (dropped)
        std::fprintf(stderr, "fovea watch: %llu samples overrun (reader too slow)\n",
                     static_cast<unsigned long long>(dropped));
}

// Pupil-style messages from another machine; each line is the topic and the ring-style line.
void run_watch_zmq(const WatchOptions& o) {
    auto sub = daemon::ZmqGazeSubscriber::connect(o.zmq);
    if (!sub) throw std::runtime_error(sub.error().message);
    uint64_t shown = 0, seen = 0;
    while (o.count == 0 || shown < o.count) {
        auto g = (*sub)->receive(static_cast<int>(o.wait_s * 1000));
        if (!g) throw std::runtime_error(g.error().message);
        if (!*g)
            throw std::runtime_error("no gaze from " + o.zmq + " for " + std::to_string(o.wait_s) +
                                     " s");
        if (seen++ % o.every) continue;
        const std::string line = watch_line((*g)->record, monotonic_ns());
        std::printf("%-12s %s\n", (*g)->topic.c_str(), line.c_str());
        std::fflush(stdout);
        ++shown;
    }
    if ((*sub)->malformed())
        std::fprintf(stderr, "fovea watch: %llu malformed messages skipped\n",
                     static_cast<unsigned long long>((*sub)->malformed()));
    if ((*sub)->missed())
        std::fprintf(stderr,
                     "fovea watch: %llu samples missed (gaps in the publisher's index: dropped "
                     "at its send_hwm while this subscriber lagged)\n",
                     static_cast<unsigned long long>((*sub)->missed()));
}

void setup_watch(CLI::App& app) {
    static WatchOptions o;
    app.add_option("--count,-n", o.count, "Stop after N samples (0: run until interrupted)");
    app.add_option("--every", o.every, "Print every Nth sample")->check(CLI::PositiveNumber);
    app.add_option("--wait", o.wait_s, "Seconds to wait for the daemon / for data");
    app.add_option("--zmq", o.zmq, "Subscribe to a fovead ZeroMQ publisher (tcp://HOST:PORT)");
    app.callback([] { run_watch(o); });
}

const Command kWatch{"watch", "Print live gaze samples, one line each", &setup_watch};

}  // namespace
}  // namespace fovea::cli
