// fovea record --out FILE.csv --duration S: everything the ring publishes, as CSV.
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "control_client.hpp"
#include "gaze_format.hpp"
#include "paths.hpp"
#include "ring_session.hpp"

namespace fovea::cli {
namespace {

struct RecordOptions {
    std::string out;
    double duration_s = 10.0;
};

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void record_csv(const RecordOptions& o) {
    auto client = open_ring(global_options().instance, 5000);
    std::FILE* f = std::fopen(o.out.c_str(), "w");
    if (!f) throw std::runtime_error("cannot write " + o.out + ": " + std::strerror(errno));
    const auto info = client->info();
    write_csv_header(f, "instance=" + global_options().instance + " device=" + info.device_name +
                            " rate_hz=" + std::to_string(info.nominal_rate_hz));
    uint64_t cursor = client->head();
    uint64_t rows = 0, dropped = 0;
    const int64_t end = monotonic_ns() + static_cast<int64_t>(o.duration_s * 1e9);
    while (monotonic_ns() < end) {
        const auto left_ms = static_cast<int32_t>((end - monotonic_ns()) / 1'000'000);
        if (!client->wait(cursor, std::max<int32_t>(1, std::min<int32_t>(left_ms, 200)))) continue;
        auto batch = client->read(cursor, 1024);
        dropped += batch.dropped;
        for (const auto& r : batch.records) write_csv_row(f, r);
        rows += batch.records.size();
    }
    if (std::fclose(f) != 0)
        throw std::runtime_error("writing " + o.out + ": " + std::strerror(errno));
    std::fprintf(stderr, "fovea record: %llu samples to %s (%llu overrun)\n",
                 static_cast<unsigned long long>(rows), o.out.c_str(),
                 static_cast<unsigned long long>(dropped));
    if (dropped) throw CLI::RuntimeError(3);
}

// .xdf: the daemon itself records (raw, processed and latency streams; see
// daemon/src/record_commands.hpp), so the file can be replayed through the gaze chain.
void record_xdf(const RecordOptions& o) {
    const std::string sock = daemon::control_socket_path(global_options().instance);
    const std::string path = std::filesystem::absolute(o.out).string();
    auto call = [&](const nlohmann::json& req) {
        auto r = daemon::control_request(sock, req, 10000);
        if (!r) throw std::runtime_error(r.error().message);
        if (!r->value("ok", false))
            throw std::runtime_error(r->value("error", std::string("failed")));
        return *r;
    };
    call({{"cmd", "record.start"}, {"path", path}});
    std::this_thread::sleep_for(std::chrono::duration<double>(o.duration_s));
    const auto st = call({{"cmd", "record.stop"}});
    std::fprintf(stderr, "fovea record: %llu raw / %llu processed samples to %s (%llu dropped)\n",
                 st.value("raw_samples", 0ull), st.value("gaze_samples", 0ull), path.c_str(),
                 st.value("dropped_samples", 0ull));
    if (st.contains("error")) throw std::runtime_error(st["error"].get<std::string>());
}

void setup_record(CLI::App& app) {
    static RecordOptions o;
    app.add_option("--out,-o", o.out, "Output file (.csv, or .xdf recorded by the daemon)")
        ->required();
    app.add_option("--duration", o.duration_s, "Seconds to record")->check(CLI::PositiveNumber);
    app.callback([] {
        if (ends_with(o.out, ".xdf")) return record_xdf(o);
        if (!ends_with(o.out, ".csv"))
            throw std::runtime_error("unsupported output format for " + o.out +
                                     " (use .csv or .xdf)");
        record_csv(o);
    });
}

const Command kRecord{"record", "Record the gaze stream to a file", &setup_record};

}  // namespace
}  // namespace fovea::cli
