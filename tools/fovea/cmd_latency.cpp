// fovea latency: per-hop latency table (p50/p90/p99/p99.9/max, counts), refreshing.
// Device-side hops come from the daemon's `status` ("latency"), render-side hops from what SDK
// clients reported to the daemon ("latency_clients"); publish -> read is measured here, on
// every record this command reads from the ring. The SDK rows also show the gaze's age at frame
// begin and at present, and the count of frames rendered with stale gaze.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "control_client.hpp"
#include "fovea/record/latency_stats.hpp"
#include "gaze_format.hpp"
#include "paths.hpp"
#include "ring_session.hpp"

namespace fovea::cli {
namespace {

using nlohmann::json;
using record::Hop;
using record::LatencyStats;

struct Options {
    bool once = false;
    int count = 0;  // refreshes; 0 = until interrupted
    double interval_s = 1.0;
    bool json = false;
};

struct Row {
    std::string hop, source;
    nlohmann::json summary;  // histogram_to_json(..., false) form; null when nothing measured
};

void print_table(const std::vector<Row>& rows, bool clear, double uptime_s) {
    if (clear) std::printf("\033[H\033[2J");
    std::printf("%-24s %-7s %10s %10s %10s %10s %10s %10s %6s\n", "hop", "source", "count",
                "p50_us", "p90_us", "p99_us", "p99.9_us", "max_us", "neg");
    for (const auto& r : rows) {
        const auto& j = r.summary;
        if (!j.is_object() || j.value("count", uint64_t{0}) == 0) {
            std::printf("%-24s %-7s %10s\n", r.hop.c_str(), r.source.c_str(), "-");
            continue;
        }
        std::printf("%-24s %-7s %10llu %10.1f %10.1f %10.1f %10.1f %10.1f %6llu\n", r.hop.c_str(),
                    r.source.c_str(),
                    static_cast<unsigned long long>(j.value("count", uint64_t{0})),
                    j.value("p50_us", 0.0), j.value("p90_us", 0.0), j.value("p99_us", 0.0),
                    j.value("p999_us", 0.0), j.value("max_us", 0.0),
                    static_cast<unsigned long long>(j.value("negative", uint64_t{0})));
    }
    if (uptime_s > 0)
        std::printf("(daemon and sdk hops since daemon start, %.0f s ago)\n", uptime_s);
    std::fflush(stdout);
}

// One line on the SDK clients' frames: how many were rendered with stale gaze.
void print_frames(const nlohmann::json& clients) {
    const auto f = clients.value("frames", nlohmann::json::object());
    const uint64_t frames = f.value("frames", uint64_t{0});
    if (frames == 0) {
        std::printf("sdk frames: none reported (%llu clients)\n",
                    static_cast<unsigned long long>(clients.value("clients", uint64_t{0})));
    } else {
        const uint64_t stale = f.value("stale", uint64_t{0});
        std::printf(
            "sdk frames: %llu from %llu clients, %llu (%.1f%%) with stale gaze (older than "
            "%.1f ms at frame begin, or none), %llu without gaze\n",
            static_cast<unsigned long long>(frames),
            static_cast<unsigned long long>(clients.value("clients", uint64_t{0})),
            static_cast<unsigned long long>(stale),
            100.0 * static_cast<double>(stale) / static_cast<double>(frames),
            f.value("stale_threshold_ms_min", 0.0),
            static_cast<unsigned long long>(f.value("without_gaze", uint64_t{0})));
    }
    std::fflush(stdout);
}

nlohmann::json section(const nlohmann::json& reply, const char* key, Hop h) {
    const std::string name(record::hop_name(h));
    if (!reply.contains(key) || !reply[key].contains(name)) return nullptr;
    return reply[key][name];
}

void run(const Options& o) {
    const std::string sock = daemon::control_socket_path(global_options().instance);
    auto client = open_ring(global_options().instance, 3000);
    uint64_t cursor = client->head();
    LatencyStats mine;
    const bool tty = isatty(STDOUT_FILENO) && !o.once && !o.json;
    const int refreshes = o.once ? 1 : o.count;
    for (int n = 0; refreshes == 0 || n < refreshes; ++n) {
        // read the ring until the next refresh, stamping each batch the moment it arrives
        const int64_t until = monotonic_ns() + static_cast<int64_t>(o.interval_s * 1e9);
        while (monotonic_ns() < until) {
            const auto left_ms = static_cast<int32_t>((until - monotonic_ns()) / 1'000'000);
            if (!client->wait(cursor, std::max<int32_t>(1, std::min<int32_t>(left_ms, 100))))
                continue;
            auto batch = client->read(cursor, 256);
            const int64_t now = monotonic_ns();
            for (const auto& r : batch.records)
                mine.hop(Hop::kPublishToRead).record(now - r.t_publish_ns);
        }
        auto reply = daemon::control_request(sock, {{"cmd", "status"}});
        if (!reply) throw std::runtime_error(reply.error().message);
        if (!reply->value("ok", false))
            throw std::runtime_error(reply->value("error", std::string("status failed")));
        const json mine_json = record::histogram_to_json(mine.hop(Hop::kPublishToRead), false);
        if (o.json) {
            json j = {{"daemon", reply->value("latency", json::object())},
                      {"reader", {{"publish_to_read", mine_json}}},
                      {"clients", reply->value("latency_clients", json::object())}};
            std::printf("%s\n", j.dump().c_str());
            std::fflush(stdout);
            continue;
        }
        std::vector<Row> rows;
        for (Hop h : {Hop::kCaptureToReceive, Hop::kReceiveToProcessed, Hop::kProcessedToPublish}) {
            rows.push_back(
                {std::string(record::hop_name(h)), "daemon", section(*reply, "latency", h)});
        }
        rows.push_back({std::string(record::hop_name(Hop::kPublishToRead)), "reader", mine_json});
        for (Hop h : {Hop::kPublishToRead, Hop::kReadToFrameBegin, Hop::kFrameBeginToSubmit,
                      Hop::kSubmitToPresent}) {
            auto j = section(*reply, "latency_clients", h);
            if (h == Hop::kPublishToRead && j.is_null()) continue;
            rows.push_back({std::string(record::hop_name(h)), "sdk", j});
        }
        // the gaze's age as the SDK clients' frames saw it (fovea_frame_begin/_presented)
        const json clients = reply->value("latency_clients", json::object());
        const json ages = clients.value("gaze_age", json::object());
        for (const char* name :
             {"capture_to_frame_begin", "publish_to_frame_begin", "capture_to_present"}) {
            rows.push_back({name, "sdk", ages.contains(name) ? ages[name] : json(nullptr)});
        }
        if (!reply->contains("latency")) {
            std::fprintf(stderr,
                         "fovea latency: the daemon's status has no \"latency\" section "
                         "(an older fovead?)\n");
        }
        print_table(rows, tty, reply->value("uptime_s", 0.0));
        print_frames(clients);
    }
}

void setup_latency(CLI::App& app) {
    static Options o;
    app.add_flag("--once", o.once, "Measure for --interval seconds, print one table and exit");
    app.add_option("--count,-n", o.count, "Number of refreshes, then exit (0: until Ctrl-C)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--interval", o.interval_s, "Seconds between refreshes")
        ->check(CLI::PositiveNumber);
    app.add_flag("--json", o.json, "One JSON object per refresh instead of the table");
    app.callback([] { run(o); });
}

const Command kLatency{"latency", "Live per-hop latency table (device, ring, render hops)",
                       &setup_latency};

}  // namespace
}  // namespace fovea::cli
