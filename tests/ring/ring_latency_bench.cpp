// Publish -> visible-to-reader latency of the ring, the number a foveated renderer lives by.
// A writer publishes at a fixed rate; N reader threads block in fovea_client_wait (futex) and
// stamp CLOCK_MONOTONIC when each record becomes readable. Prints a table, writes a CSV.
//   ring_latency_bench [--seconds S] [--csv FILE]
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "fovea/client.h"
#include "ring_writer.hpp"

namespace {

int64_t now_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

double percentile(std::vector<int64_t>& v, double p) {
    if (v.empty()) return 0;
    const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k] / 1000.0;
}

struct Row {
    int rate_hz;
    int readers;
    const char* mode;
    std::size_t samples;
    double p50_us, p99_us, p999_us, max_us;
};

Row run(int rate_hz, int n_readers, bool spin, double seconds) {
    const std::string inst = "bench-" + std::to_string(getpid());
    fovea::ring::WriterOptions o;
    o.instance = inst;
    auto w = fovea::ring::RingWriter::create(o);
    if (!w.ok()) {
        std::fprintf(stderr, "%s\n", w.error().message.c_str());
        std::exit(1);
    }
    std::atomic<bool> done{false};
    std::atomic<int> ready{0};
    std::vector<std::vector<int64_t>> lat(n_readers);
    std::vector<std::thread> readers;
    for (int i = 0; i < n_readers; ++i) {
        readers.emplace_back([&, i] {
            fovea_client* c = nullptr;
            fovea_client_open(inst.c_str(), FOVEA_STREAM_GAZE, &c);
            uint64_t cursor = fovea_client_head(c);
            lat[i].reserve(static_cast<std::size_t>(rate_hz * seconds) + 16);
            ready.fetch_add(1);
            fovea_gaze_record rec[16];
            while (!done.load(std::memory_order_relaxed)) {
                if (!spin && fovea_client_wait(c, cursor, 50) != FOVEA_OK) continue;
                uint32_t n = 0;
                fovea_client_read(c, &cursor, rec, 16, &n, nullptr);
                const int64_t t = now_ns();
                for (uint32_t k = 0; k < n; ++k) lat[i].push_back(t - rec[k].t_publish_ns);
            }
            fovea_client_close(&c);
        });
    }
    while (ready.load() < n_readers) std::this_thread::yield();
    const int64_t period = 1'000'000'000 / rate_hz;
    const int64_t start = now_ns();
    const auto total = static_cast<int64_t>(rate_hz * seconds);
    for (int64_t k = 0; k < total; ++k) {
        const int64_t due = start + k * period;
        timespec ts{static_cast<time_t>(due / 1'000'000'000), static_cast<long>(due % 1'000'000'000)};
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
        fovea_gaze_record r{};
        w->publish(r);  // stamps t_publish_ns
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    done = true;
    for (auto& t : readers) t.join();
    std::vector<int64_t> all;
    for (auto& v : lat) all.insert(all.end(), v.begin(), v.end());
    Row row{rate_hz, n_readers, spin ? "spin" : "futex", all.size(), 0, 0, 0, 0};
    row.max_us = all.empty() ? 0 : *std::max_element(all.begin(), all.end()) / 1000.0;
    row.p50_us = percentile(all, 0.50);
    row.p99_us = percentile(all, 0.99);
    row.p999_us = percentile(all, 0.999);
    return row;
}

}  // namespace

int main(int argc, char** argv) {
    double seconds = 3.0;
    std::string csv = "ring_latency.csv";
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--seconds") && i + 1 < argc) seconds = std::atof(argv[++i]);
        else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc) csv = argv[++i];
        else {
            std::fprintf(stderr, "usage: %s [--seconds S] [--csv FILE]\n", argv[0]);
            return 2;
        }
    }
    std::vector<Row> rows;
    for (int rate : {2000, 10000})
        for (int readers : {1, 8}) rows.push_back(run(rate, readers, false, seconds));
    rows.push_back(run(2000, 1, true, seconds));  // a dedicated spinning reader, for contrast
    std::printf("%-8s %-8s %-6s %9s %9s %9s %9s %9s\n", "rate_hz", "readers", "mode", "samples",
                "p50_us", "p99_us", "p99.9_us", "max_us");
    FILE* f = std::fopen(csv.c_str(), "w");
    if (f) std::fprintf(f, "rate_hz,readers,mode,samples,p50_us,p99_us,p999_us,max_us\n");
    for (const Row& r : rows) {
        std::printf("%-8d %-8d %-6s %9zu %9.1f %9.1f %9.1f %9.1f\n", r.rate_hz, r.readers, r.mode,
                    r.samples, r.p50_us, r.p99_us, r.p999_us, r.max_us);
        if (f)
            std::fprintf(f, "%d,%d,%s,%zu,%.2f,%.2f,%.2f,%.2f\n", r.rate_hz, r.readers, r.mode,
                         r.samples, r.p50_us, r.p99_us, r.p999_us, r.max_us);
    }
    if (f) std::fclose(f);
    std::printf("wrote %s\n", csv.c_str());
}
