// Publish -> visible-to-reader latency of the ring, the number a foveated renderer lives by, judged
// against this machine's own floor measured in the same run: a bare futex wake between two threads
// and a bare spin hand-off (no ring). A writer thread publishes at a fixed rate; reader threads
// block in fovea_client_wait and stamp CLOCK_MONOTONIC when each record becomes readable. Rows are
// interleaved round by round (floors, futex-only wait, adaptive wait), the table shows medians over
// rounds, and the CSV has every round. Reader CPU is the readers' summed thread CPU time over the
// wall time (100 = one core). --hog N forks N busy processes for the "hog" load.
//   ring_latency_bench [--seconds S] [--rounds R] [--rates 2000,10000] [--readers 1,8]
//                      [--load idle,hog] [--hog N] [--csv FILE]
#include <linux/futex.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "fovea/client.h"
#include "ring_writer.hpp"

namespace {

int64_t now_ns(clockid_t clock = CLOCK_MONOTONIC) {
    timespec ts{};
    clock_gettime(clock, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

double percentile(std::vector<int64_t>& v, double p) {
    if (v.empty()) return 0;
    const std::size_t k =
        std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k] / 1000.0;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double load_average() {
    double l = 0;
    if (FILE* f = std::fopen("/proc/loadavg", "r")) {
        if (std::fscanf(f, "%lf", &l) != 1) l = 0;
        std::fclose(f);
    }
    return l;
}

// What the readers of one row do. kBareFutex/kBareSpin use no ring: the writer bumps a word in a
// shared page and (futex) wakes it, the reader stamps when it sees the new value.
enum class Mode { kBareFutex, kBareSpin, kRingFutex, kRingAdaptive, kRingSpin };

const char* mode_name(Mode m) {
    switch (m) {
        case Mode::kBareFutex: return "bare-futex";
        case Mode::kBareSpin: return "bare-spin";
        case Mode::kRingFutex: return "ring-futex";
        case Mode::kRingAdaptive: return "ring-adaptive";
        case Mode::kRingSpin: return "ring-spin";
    }
    return "?";
}

struct Result {
    std::size_t samples = 0;
    double p50_us = 0, p99_us = 0, p999_us = 0, max_us = 0;
    double reader_cpu_pct = 0;  // summed over readers, 100 = one core
    double load = 0;
};

long futex(uint32_t* word, int op, uint32_t val, const timespec* ts) {
    return syscall(SYS_futex, word, op, val, ts, nullptr, 0);
}

// Pace `total` publishes at `rate_hz` with absolute sleeps; publish(k) does the hand-off.
template <class F>
void paced(int rate_hz, int64_t total, F&& publish) {
    const int64_t period = 1'000'000'000 / rate_hz;
    const int64_t start = now_ns() + 5'000'000;
    for (int64_t k = 0; k < total; ++k) {
        const int64_t due = start + k * period;
        timespec ts{static_cast<time_t>(due / 1'000'000'000),
                    static_cast<long>(due % 1'000'000'000)};
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
        publish(k);
    }
}

Result summarize(std::vector<std::vector<int64_t>>& lat, const std::vector<int64_t>& cpu_ns,
                 int64_t wall_ns) {
    std::vector<int64_t> all;
    for (auto& v : lat) all.insert(all.end(), v.begin(), v.end());
    Result r;
    r.samples = all.size();
    r.max_us = all.empty() ? 0 : *std::max_element(all.begin(), all.end()) / 1000.0;
    r.p50_us = percentile(all, 0.50);
    r.p99_us = percentile(all, 0.99);
    r.p999_us = percentile(all, 0.999);
    int64_t cpu = 0;
    for (int64_t c : cpu_ns) cpu += c;
    r.reader_cpu_pct = wall_ns > 0 ? 100.0 * static_cast<double>(cpu) / wall_ns : 0;
    return r;
}

Result run_bare(Mode mode, int rate_hz, int n_readers, double seconds) {
    // A shared page, as the ring's header is, so the futex takes the same (inode-keyed) path.
    // Publish stamps by count, so a reader that wakes late scores every publish it missed, as
    // the ring readers do with every record.
    constexpr std::size_t kStamps = 4096;
    const std::size_t bytes = 64 + kStamps * sizeof(int64_t);
    void* page = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (page == MAP_FAILED) {
        std::perror("mmap");
        std::exit(1);
    }
    auto* word = static_cast<uint32_t*>(page);
    auto* stamp = reinterpret_cast<int64_t*>(static_cast<char*>(page) + 64);
    std::atomic<bool> done{false};
    std::atomic<int> ready{0};
    std::vector<std::vector<int64_t>> lat(n_readers);
    std::vector<int64_t> cpu(n_readers, 0);
    std::vector<std::thread> readers;
    const auto total = static_cast<int64_t>(rate_hz * seconds);
    for (int i = 0; i < n_readers; ++i) {
        readers.emplace_back([&, i] {
            lat[i].reserve(static_cast<std::size_t>(total) + 16);
            uint32_t seen = __atomic_load_n(word, __ATOMIC_ACQUIRE);
            ready.fetch_add(1);
            const int64_t cpu0 = now_ns(CLOCK_THREAD_CPUTIME_ID);
            const timespec ts{0, 50'000'000};
            while (!done.load(std::memory_order_relaxed)) {
                const uint32_t w = __atomic_load_n(word, __ATOMIC_ACQUIRE);
                if (w == seen) {
                    if (mode == Mode::kBareFutex)
                        futex(word, FUTEX_WAIT, w, &ts);
                    else
                        __builtin_ia32_pause();
                    continue;
                }
                const int64_t t = now_ns();
                for (uint32_t k = seen + 1; k != w + 1; ++k)
                    lat[i].push_back(t - __atomic_load_n(stamp + k % kStamps, __ATOMIC_RELAXED));
                seen = w;
            }
            cpu[i] = now_ns(CLOCK_THREAD_CPUTIME_ID) - cpu0;
        });
    }
    while (ready.load() < n_readers) std::this_thread::yield();
    const int64_t t0 = now_ns();
    paced(rate_hz, total, [&](int64_t) {
        const uint32_t next = __atomic_load_n(word, __ATOMIC_RELAXED) + 1;
        __atomic_store_n(stamp + next % kStamps, now_ns(), __ATOMIC_RELAXED);
        __atomic_store_n(word, next, __ATOMIC_RELEASE);
        if (mode == Mode::kBareFutex) futex(word, FUTEX_WAKE, INT32_MAX, nullptr);
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const int64_t wall = now_ns() - t0;
    done = true;
    futex(word, FUTEX_WAKE, INT32_MAX, nullptr);
    for (auto& t : readers) t.join();
    munmap(page, bytes);
    return summarize(lat, cpu, wall);
}

Result run_ring(Mode mode, int rate_hz, int n_readers, double seconds) {
    const std::string inst = "bench-" + std::to_string(getpid());
    fovea::ring::WriterOptions o;
    o.instance = inst;
    o.nominal_rate_hz = static_cast<uint32_t>(rate_hz);
    auto w = fovea::ring::RingWriter::create(o);
    if (!w.ok()) {
        std::fprintf(stderr, "%s\n", w.error().message.c_str());
        std::exit(1);
    }
    std::atomic<bool> done{false};
    std::atomic<int> ready{0};
    std::vector<std::vector<int64_t>> lat(n_readers);
    std::vector<int64_t> cpu(n_readers, 0);
    std::vector<std::thread> readers;
    const auto total = static_cast<int64_t>(rate_hz * seconds);
    for (int i = 0; i < n_readers; ++i) {
        readers.emplace_back([&, i] {
            fovea_client* c = nullptr;
            fovea_client_open(inst.c_str(), FOVEA_STREAM_GAZE, &c);
            fovea_client_set_wait_spin(c, mode == Mode::kRingAdaptive ? -1 : 0);
            uint64_t cursor = fovea_client_head(c);
            lat[i].reserve(static_cast<std::size_t>(total) + 16);
            ready.fetch_add(1);
            const int64_t cpu0 = now_ns(CLOCK_THREAD_CPUTIME_ID);
            fovea_gaze_record rec[16];
            while (!done.load(std::memory_order_relaxed)) {
                if (mode != Mode::kRingSpin && fovea_client_wait(c, cursor, 50) != FOVEA_OK)
                    continue;
                uint32_t n = 0;
                fovea_client_read(c, &cursor, rec, 16, &n, nullptr);
                const int64_t t = now_ns();
                for (uint32_t k = 0; k < n; ++k) lat[i].push_back(t - rec[k].t_publish_ns);
                if (n == 0 && mode == Mode::kRingSpin) __builtin_ia32_pause();
            }
            cpu[i] = now_ns(CLOCK_THREAD_CPUTIME_ID) - cpu0;
            fovea_client_close(&c);
        });
    }
    while (ready.load() < n_readers) std::this_thread::yield();
    const int64_t t0 = now_ns();
    paced(rate_hz, total, [&](int64_t) {
        fovea_gaze_record r{};
        w->publish(r);  // stamps t_publish_ns
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const int64_t wall = now_ns() - t0;
    done = true;
    for (auto& t : readers) t.join();
    return summarize(lat, cpu, wall);
}

// N processes that only burn CPU, like `stress --cpu N`; killed by the destructor.
struct Hog {
    std::vector<pid_t> pids;
    explicit Hog(int n) {
        for (int i = 0; i < n; ++i) {
            const pid_t p = fork();
            if (p == 0) {
                volatile uint64_t x = 0;
                for (;;) x = x + 1;
            }
            if (p > 0) pids.push_back(p);
        }
    }
    ~Hog() {
        for (pid_t p : pids) kill(p, SIGKILL);
        for (pid_t p : pids) waitpid(p, nullptr, 0);
    }
};

std::vector<int> parse_ints(const char* s) {
    std::vector<int> v;
    for (const char* p = s; *p;) {
        char* end = nullptr;
        v.push_back(static_cast<int>(std::strtol(p, &end, 10)));
        p = *end == ',' ? end + 1 : end;
        if (end == p && *p) break;
    }
    return v;
}

std::vector<std::string> parse_words(const std::string& s) {
    std::vector<std::string> v;
    std::size_t a = 0;
    while (a <= s.size()) {
        const std::size_t b = std::min(s.find(',', a), s.size());
        if (b > a) v.push_back(s.substr(a, b - a));
        a = b + 1;
    }
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    double seconds = 2.0;
    int rounds = 3;
    int hog_procs = 2;
    std::vector<int> rates{2000, 10000};
    std::vector<int> reader_counts{1, 8};
    std::vector<std::string> loads{"idle", "hog"};
    std::string csv = "ring_latency.csv";
    for (int i = 1; i < argc; ++i) {
        const bool more = i + 1 < argc;
        if (!std::strcmp(argv[i], "--seconds") && more)
            seconds = std::atof(argv[++i]);
        else if (!std::strcmp(argv[i], "--rounds") && more)
            rounds = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--hog") && more)
            hog_procs = std::max(1, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--rates") && more)
            rates = parse_ints(argv[++i]);
        else if (!std::strcmp(argv[i], "--readers") && more)
            reader_counts = parse_ints(argv[++i]);
        else if (!std::strcmp(argv[i], "--load") && more)
            loads = parse_words(argv[++i]);
        else if (!std::strcmp(argv[i], "--csv") && more)
            csv = argv[++i];
        else {
            std::fprintf(stderr,
                         "usage: %s [--seconds S] [--rounds R] [--rates 2000,10000] "
                         "[--readers 1,8] [--load idle,hog] [--hog N] [--csv FILE]\n",
                         argv[0]);
            return 2;
        }
    }
    for (const auto& l : loads)
        if (l != "idle" && l != "hog") {
            std::fprintf(stderr, "--load takes idle and/or hog, not '%s'\n", l.c_str());
            return 2;
        }

    FILE* f = std::fopen(csv.c_str(), "w");
    if (!f) {
        std::fprintf(stderr, "cannot write %s: %s\n", csv.c_str(), std::strerror(errno));
        return 1;
    }
    std::fprintf(f,
                 "round,load,rate_hz,readers,mode,samples,p50_us,p99_us,p999_us,max_us,"
                 "reader_cpu_pct,loadavg\n");
    using Key = std::tuple<std::string, int, int, int>;  // load, rate, readers, mode
    std::map<Key, std::vector<Result>> results;
    for (int round = 0; round < rounds; ++round) {
        for (const auto& load : loads) {
            Hog hog(load == "hog" ? hog_procs : 0);
            for (int rate : rates) {
                // The floor with one waiter, then every reader count; alternate the ring modes'
                // order each round so neither always runs first.
                std::vector<std::pair<Mode, int>> plan{{Mode::kBareFutex, 1}, {Mode::kBareSpin, 1}};
                for (int n : reader_counts) {
                    if (n > 1) plan.push_back({Mode::kBareFutex, n});
                    if (round % 2 == 0) {
                        plan.push_back({Mode::kRingFutex, n});
                        plan.push_back({Mode::kRingAdaptive, n});
                    } else {
                        plan.push_back({Mode::kRingAdaptive, n});
                        plan.push_back({Mode::kRingFutex, n});
                    }
                }
                plan.push_back({Mode::kRingSpin, 1});
                for (const auto& [mode, n] : plan) {
                    const bool bare = mode == Mode::kBareFutex || mode == Mode::kBareSpin;
                    Result r =
                        bare ? run_bare(mode, rate, n, seconds) : run_ring(mode, rate, n, seconds);
                    r.load = load_average();
                    results[{load, rate, n, static_cast<int>(mode)}].push_back(r);
                    std::fprintf(f, "%d,%s,%d,%d,%s,%zu,%.2f,%.2f,%.2f,%.2f,%.1f,%.2f\n", round,
                                 load.c_str(), rate, n, mode_name(mode), r.samples, r.p50_us,
                                 r.p99_us, r.p999_us, r.max_us, r.reader_cpu_pct, r.load);
                    std::fflush(f);
                }
            }
        }
    }
    std::fclose(f);

    auto med = [&](const Key& k, double Result::*field) {
        std::vector<double> v;
        for (const Result& r : results[k]) v.push_back(r.*field);
        return median(v);
    };
    std::printf(
        "medians of %d interleaved rounds, %.1f s per row; x_fx1 = ring / bare futex with one "
        "waiter, x_fxN = / bare futex with as many waiters\n",
        rounds, seconds);
    std::printf("%-5s %-6s %-3s %-13s %7s %8s %8s %8s %8s %6s %6s %6s %5s\n", "load", "rate", "rd",
                "mode", "samples", "p50_us", "p99_us", "p999_us", "max_us", "cpu%", "x_fx1",
                "x_fxN", "ldavg");
    for (const auto& [k, v] : results) {
        const auto& [load, rate, n, mode_i] = k;
        const Mode mode = static_cast<Mode>(mode_i);
        const double p99 = med(k, &Result::p99_us);
        const double fx1 =
            med({load, rate, 1, static_cast<int>(Mode::kBareFutex)}, &Result::p99_us);
        const double fxn =
            med({load, rate, n, static_cast<int>(Mode::kBareFutex)}, &Result::p99_us);
        std::vector<double> samples;
        for (const Result& r : v) samples.push_back(static_cast<double>(r.samples));
        std::printf("%-5s %-6d %-3d %-13s %7.0f %8.1f %8.1f %8.1f %8.1f %6.1f %6.2f %6.2f %5.1f\n",
                    load.c_str(), rate, n, mode_name(mode), median(samples),
                    med(k, &Result::p50_us), p99, med(k, &Result::p999_us), med(k, &Result::max_us),
                    med(k, &Result::reader_cpu_pct), fx1 > 0 ? p99 / fx1 : 0,
                    fxn > 0 ? p99 / fxn : 0, med(k, &Result::load));
    }
    std::printf("wrote %s\n", csv.c_str());
}
