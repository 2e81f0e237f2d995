// The ring contract: untorn records under concurrency, overrun accounting, writer restarts,
// readers that die mid-read, read-only mappings.
#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "fovea/client.h"
#include "fovea/client.hpp"
#include "ring_writer.hpp"

namespace {

using fovea::ring::RingWriter;
using fovea::ring::WriterOptions;

std::string unique_instance(const char* tag) {
    return std::string("t") + tag + "-" + std::to_string(getpid());
}

RingWriter make_writer(const std::string& instance, uint32_t slots = 1024) {
    WriterOptions o;
    o.instance = instance;
    o.slot_count = slots;
    o.nominal_rate_hz = 1000;
    o.device_name = "test";
    auto w = RingWriter::create(o);
    if (!w.ok()) throw std::runtime_error(w.error().message);
    return std::move(w).value();
}

// A record whose every field derives from its sequence number, so a torn copy is detectable
// twice over: by the checksum and by the fields disagreeing with the index.
fovea_gaze_record make_record(uint64_t n) {
    fovea_gaze_record r{};
    r.t_capture_ns = static_cast<int64_t>(n) * 1000;
    r.t_receive_ns = r.t_capture_ns + 7;
    r.left.norm_x = static_cast<float>(n % 1000) / 1000.0f;
    r.right.norm_x = r.left.norm_x;
    r.combined.pupil_mm = static_cast<float>(n % 97);
    r.event = static_cast<uint32_t>(n % 6);
    r.reserved[0] = n;
    r.reserved[1] = ~n;
    return r;
}

bool consistent(const fovea_gaze_record& r) {
    const uint64_t n = r.reserved[0];
    return r.checksum == fovea_record_checksum(&r) && r.reserved[1] == ~n && r.index == n &&
           r.t_capture_ns == static_cast<int64_t>(n) * 1000 && r.event == n % 6 &&
           r.combined.pupil_mm == static_cast<float>(n % 97);
}

TEST(SeqlockRing, RecordLayoutIsTheAbi) {
    EXPECT_EQ(sizeof(fovea_gaze_record), 192u);
    EXPECT_EQ(sizeof(fovea_ring_header), 256u);
    EXPECT_EQ(fovea_abi_version(), FOVEA_RING_ABI_VERSION);
}

TEST(SeqlockRing, RingNameRejectsBadInstances) {
    char name[64];
    EXPECT_EQ(fovea_ring_name("lab-1_a", FOVEA_STREAM_GAZE, name, sizeof name), FOVEA_OK);
    EXPECT_STREQ(name, "/fovea.lab-1_a.gaze");
    EXPECT_EQ(fovea_ring_name("", FOVEA_STREAM_HEAD, name, sizeof name), FOVEA_OK);
    EXPECT_STREQ(name, "/fovea.default.head");
    EXPECT_EQ(fovea_ring_name("../etc", FOVEA_STREAM_GAZE, name, sizeof name),
              FOVEA_E_INVALID_ARGUMENT);
    EXPECT_NE(std::string(fovea_last_error()).find("[A-Za-z0-9_-]"), std::string::npos);
    EXPECT_EQ(fovea_ring_name("default", FOVEA_STREAM_GAZE, name, 8), FOVEA_E_INVALID_ARGUMENT);
}

TEST(SeqlockRing, OpenWithoutWriterSaysSo) {
    fovea_client* c = nullptr;
    EXPECT_EQ(fovea_client_open(unique_instance("none").c_str(), FOVEA_STREAM_GAZE, &c),
              FOVEA_E_NOT_FOUND);
    EXPECT_EQ(c, nullptr);
    EXPECT_NE(std::string(fovea_last_error()).find("fovead"), std::string::npos);
}

TEST(SeqlockRing, LatestAndReadSeeWhatWasPublished) {
    const auto inst = unique_instance("basic");
    RingWriter w = make_writer(inst, 64);
    fovea::Client c(inst);
    EXPECT_FALSE(c.latest().has_value());
    for (uint64_t n = 0; n < 10; ++n) {
        auto r = make_record(n);
        EXPECT_EQ(w.publish(r), n);
    }
    auto latest = c.latest();
    ASSERT_TRUE(latest.has_value());
    EXPECT_EQ(latest->index, 9u);
    EXPECT_TRUE(consistent(*latest));
    uint64_t cursor = 0;
    auto batch = c.read(cursor, 100);
    ASSERT_EQ(batch.records.size(), 10u);
    EXPECT_EQ(batch.dropped, 0u);
    EXPECT_EQ(cursor, 10u);
    for (uint64_t n = 0; n < 10; ++n) EXPECT_TRUE(consistent(batch.records[n]));
    const auto info = c.info();
    EXPECT_EQ(info.slot_count, 64u);
    EXPECT_STREQ(info.device_name, "test");
    EXPECT_EQ(info.generation, w.generation());
}

TEST(SeqlockRing, OverrunIsCountedAndRecovered) {
    const auto inst = unique_instance("overrun");
    RingWriter w = make_writer(inst, 64);
    fovea::Client c(inst);
    for (uint64_t n = 0; n < 1000; ++n) {
        auto r = make_record(n);
        w.publish(r);
    }
    uint64_t cursor = 5;
    auto batch = c.read(cursor, 1000);
    // Only the last 64 survive; everything from 5 to 935 was overwritten.
    EXPECT_EQ(batch.dropped, 1000u - 64u - 5u);
    ASSERT_EQ(batch.records.size(), 64u);
    EXPECT_EQ(batch.records.front().index, 936u);
    EXPECT_EQ(cursor, 1000u);
    auto r = make_record(1000);
    w.publish(r);
    batch = c.read(cursor, 10);
    EXPECT_EQ(batch.dropped, 0u);
    ASSERT_EQ(batch.records.size(), 1u);
    EXPECT_EQ(batch.records[0].index, 1000u);
}

TEST(SeqlockRing, WaitWakesOnPublishAndTimesOut) {
    const auto inst = unique_instance("wait");
    RingWriter w = make_writer(inst, 64);
    fovea_client* c = nullptr;
    ASSERT_EQ(fovea_client_open(inst.c_str(), FOVEA_STREAM_GAZE, &c), FOVEA_OK);
    EXPECT_EQ(fovea_client_wait(c, 0, 20), FOVEA_E_TIMEOUT);
    std::thread publisher([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
        auto r = make_record(0);
        w.publish(r);
    });
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_EQ(fovea_client_wait(c, 0, 5000), FOVEA_OK);
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(4));
    publisher.join();
    fovea_client_close(&c);
    EXPECT_EQ(c, nullptr);
}

// The opt-in spin learns a 1 kHz cadence and spins before each record: every record still
// arrives, in order, through wait + read; once the writer stops, wait times out (a spin window is
// used once per record, never a busy wait for the whole timeout).
TEST(SeqlockRing, SpinningWaitSeesEveryRecordAndStillTimesOut) {
    const auto inst = unique_instance("spin");
    RingWriter w = make_writer(inst, 1024);
    fovea_client* c = nullptr;
    ASSERT_EQ(fovea_client_open(inst.c_str(), FOVEA_STREAM_GAZE, &c), FOVEA_OK);
    ASSERT_EQ(fovea_client_set_wait_spin(c, -1), FOVEA_OK);
    constexpr uint64_t kRecords = 300;
    std::thread publisher([&] {
        for (uint64_t i = 0; i < kRecords; ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
            auto r = make_record(i);
            w.publish(r);
        }
    });
    uint64_t cursor = 0, next = 0;
    int timeouts = 0;
    while (next < kRecords && timeouts < 50) {
        const int s = fovea_client_wait(c, cursor, 100);
        if (s == FOVEA_E_TIMEOUT) {
            ++timeouts;
            continue;
        }
        ASSERT_EQ(s, FOVEA_OK);
        fovea_gaze_record rec[8];
        uint32_t n = 0;
        ASSERT_EQ(fovea_client_read(c, &cursor, rec, 8, &n, nullptr), FOVEA_OK);
        for (uint32_t k = 0; k < n; ++k) EXPECT_EQ(rec[k].index, next++);
    }
    publisher.join();
    EXPECT_EQ(next, kRecords);
    EXPECT_EQ(timeouts, 0);
    const int64_t cpu0 = []() {
        timespec ts{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
    }();
    EXPECT_EQ(fovea_client_wait(c, cursor, 200), FOVEA_E_TIMEOUT);
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    const int64_t cpu = int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec - cpu0;
    EXPECT_LT(cpu, 50'000'000) << "a 200 ms wait on a stopped writer must sleep, not spin";
    EXPECT_EQ(fovea_client_set_wait_spin(nullptr, 0), FOVEA_E_INVALID_ARGUMENT);
    fovea_client_close(&c);
}

TEST(SeqlockRing, WrongStreamKindIsRejected) {
    const auto inst = unique_instance("kind");
    RingWriter w = make_writer(inst, 64);
    fovea_client* c = nullptr;
    EXPECT_EQ(fovea_client_open(inst.c_str(), FOVEA_STREAM_HEAD, &c), FOVEA_E_NOT_FOUND);
    ASSERT_EQ(fovea_client_open(inst.c_str(), FOVEA_STREAM_GAZE, &c), FOVEA_OK);
    fovea_head_record h{};
    EXPECT_EQ(fovea_client_latest_head(c, &h), FOVEA_E_WRONG_STREAM);
    fovea_client_close(&c);
}

TEST(SeqlockRing, HeadStreamCarriesHeadRecords) {
    const auto inst = unique_instance("head");
    WriterOptions o;
    o.instance = inst;
    o.kind = FOVEA_STREAM_HEAD;
    auto w = RingWriter::create(o);
    ASSERT_TRUE(w.ok()) << w.error().message;
    fovea_head_record h{};
    h.position_m[2] = 1.5f;
    h.rotation_quat[3] = 1.0f;
    w->publish(h);
    fovea_client* c = nullptr;
    ASSERT_EQ(fovea_client_open(inst.c_str(), FOVEA_STREAM_HEAD, &c), FOVEA_OK);
    fovea_head_record out{};
    ASSERT_EQ(fovea_client_latest_head(c, &out), FOVEA_OK);
    EXPECT_EQ(out.position_m[2], 1.5f);
    EXPECT_EQ(out.checksum, fovea_record_checksum(&out));
    fovea_client_close(&c);
}

TEST(SeqlockRing, RestartedWriterIsDetected) {
    const auto inst = unique_instance("restart");
    auto w = std::make_unique<RingWriter>(make_writer(inst, 64));
    fovea_client* c = nullptr;
    ASSERT_EQ(fovea_client_open(inst.c_str(), FOVEA_STREAM_GAZE, &c), FOVEA_OK);
    for (uint64_t n = 0; n < 5; ++n) {
        auto r = make_record(n);
        w->publish(r);
    }
    const uint64_t old_generation = w->generation();
    // A crashed writer never calls close(): simulate by creating the new one over the old.
    RingWriter w2 = make_writer(inst, 64);
    auto r = make_record(0);
    w2.publish(r);
    EXPECT_EQ(fovea_client_check(c), FOVEA_E_WRITER_RESTARTED);
    fovea_ring_info info{};
    ASSERT_EQ(fovea_client_info(c, &info), FOVEA_OK);
    EXPECT_NE(info.generation, old_generation);
    EXPECT_EQ(info.generation, w2.generation());
    EXPECT_EQ(fovea_client_head(c), 1u);
    EXPECT_EQ(fovea_client_check(c), FOVEA_OK);
    fovea_client_close(&c);
    w.reset();  // the stale writer's close() must not unlink the new generation's object...
    fovea::Client again(inst);  // ...which is still there
    EXPECT_EQ(again.info().generation, w2.generation());
}

TEST(SeqlockRing, EyeGeometryTravelsInTheHeader) {
    const auto inst = unique_instance("eyes");
    {
        RingWriter monitor = make_writer(inst, 64);
        fovea::Client c(inst);
        EXPECT_EQ(c.eye_geometry().ipd_m, 0.0f);  // a writer without an HMD profile
    }
    WriterOptions o;
    o.instance = inst;
    o.slot_count = 64;
    o.eyes.ipd_m = 0.064f;
    for (int e = 0; e < 2; ++e)
        for (int k = 0; k < 4; ++k) o.eyes.fov_deg[e][k] = 40.0f + 3.0f * e + k;
    auto w = RingWriter::create(o);
    ASSERT_TRUE(w.ok()) << w.error().message;
    fovea::Client c(inst);
    const fovea_eye_geometry g = c.eye_geometry();
    EXPECT_EQ(g.ipd_m, 0.064f);
    EXPECT_EQ(g.fov_deg[0][0], 40.0f);
    EXPECT_EQ(g.fov_deg[1][3], 46.0f);
    EXPECT_EQ(fovea_client_eye_geometry(nullptr, nullptr), FOVEA_E_INVALID_ARGUMENT);
}

// Trackers that never state their rate (Gazepoint, Pupil, OSC) have it measured after their
// first samples: an attached reader must see the measured rate, not the 0 of the ring's creation.
TEST(SeqlockRing, AMeasuredRateReachesAttachedReaders) {
    const auto inst = unique_instance("rate");
    WriterOptions o;
    o.instance = inst;
    o.slot_count = 64;  // and no rate: the tracker has not said it
    auto w = RingWriter::create(o);
    ASSERT_TRUE(w.ok()) << w.error().message;
    fovea::Client c(inst);
    EXPECT_EQ(c.info().nominal_rate_hz, 0u);
    w->set_nominal_rate_hz(150);
    EXPECT_EQ(c.info().nominal_rate_hz, 150u);
    EXPECT_EQ(fovea::Client(inst).info().nominal_rate_hz, 150u);  // and later ones
}

// A page first touched while publishing is a page fault in the writer and in every reader (tens
// of microseconds in a VM, the ring latency's tail): a fresh ring has all its pages already.
TEST(SeqlockRing, EveryPageIsAllocatedWhenTheRingIsCreated) {
    const auto inst = unique_instance("pages");
    RingWriter w = make_writer(inst, 4096);
    char name[128];
    ASSERT_EQ(fovea_ring_name(inst.c_str(), FOVEA_STREAM_GAZE, name, sizeof name), FOVEA_OK);
    const int fd = shm_open(name, O_RDONLY, 0);
    ASSERT_GE(fd, 0);
    struct stat st {};
    ASSERT_EQ(fstat(fd, &st), 0);
    const long page = sysconf(_SC_PAGESIZE);
    const size_t pages = (static_cast<size_t>(st.st_size) + page - 1) / page;
    ASSERT_GT(pages, 100u);
    // mincore reports the shm object's pages in memory, whether or not this mapping touched them.
    void* base = mmap(nullptr, static_cast<size_t>(st.st_size), PROT_READ, MAP_SHARED, fd, 0);
    ASSERT_NE(base, MAP_FAILED);
    std::vector<unsigned char> resident(pages);
    ASSERT_EQ(mincore(base, static_cast<size_t>(st.st_size), resident.data()), 0);
    size_t missing = 0;
    for (unsigned char r : resident) missing += (r & 1) ? 0 : 1;
    EXPECT_EQ(missing, 0u) << "of " << pages << " pages";
    munmap(base, static_cast<size_t>(st.st_size));
    close(fd);
}

TEST(SeqlockRing, ReadersAttachedIsSeenByTheWriter) {
    const auto inst = unique_instance("attached");
    RingWriter w = make_writer(inst, 64);
    EXPECT_FALSE(w.readers_attached());
    {
        fovea::Client c(inst);
        EXPECT_TRUE(w.readers_attached());
    }
    EXPECT_FALSE(w.readers_attached());
}

TEST(SeqlockRing, IncompatibleObjectIsRefused) {
    const auto inst = unique_instance("badmagic");
    char name[128];
    ASSERT_EQ(fovea_ring_name(inst.c_str(), FOVEA_STREAM_GAZE, name, sizeof name), FOVEA_OK);
    int fd = shm_open(name, O_RDWR | O_CREAT | O_EXCL, 0600);
    ASSERT_GE(fd, 0);
    fovea_ring_header h{};
    h.magic = 0x1234;
    h.state = FOVEA_RING_LIVE;
    ASSERT_EQ(write(fd, &h, sizeof h), static_cast<ssize_t>(sizeof h));
    close(fd);
    fovea_client* c = nullptr;
    EXPECT_EQ(fovea_client_open(inst.c_str(), FOVEA_STREAM_GAZE, &c), FOVEA_E_INCOMPATIBLE);
    shm_unlink(name);
}

// A client that is not the ring's owner can open it only for reading, cannot make its mapping
// writable, and faults if it writes anyway; the writer carries on.
TEST(SeqlockRing, ClientCannotWriteTheRing) {
    if (geteuid() != 0) GTEST_SKIP() << "needs root to drop to another uid";
    const auto inst = unique_instance("ro");
    RingWriter w = make_writer(inst, 64);
    auto r = make_record(0);
    w.publish(r);
    char name[128];
    ASSERT_EQ(fovea_ring_name(inst.c_str(), FOVEA_STREAM_GAZE, name, sizeof name), FOVEA_OK);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        // Same group as the ring (mode 0640 gives the group read), another user.
        if (setuid(65534) != 0) _exit(10);
        if (shm_open(name, O_RDWR, 0) >= 0 || errno != EACCES) _exit(11);
        fovea_client* c = nullptr;
        if (fovea_client_open(inst.c_str(), FOVEA_STREAM_GAZE, &c) != FOVEA_OK) _exit(12);
        fovea_gaze_record got{};
        if (fovea_client_latest(c, &got) != FOVEA_OK || got.index != 0) _exit(13);
        const int fd = shm_open(name, O_RDONLY, 0);
        void* p = mmap(nullptr, 4096, PROT_READ, MAP_SHARED, fd, 0);
        if (p == MAP_FAILED) _exit(14);
        if (mprotect(p, 4096, PROT_READ | PROT_WRITE) == 0 || errno != EACCES) _exit(15);
        signal(SIGSEGV, SIG_DFL);  // let the kernel's verdict through, not a sanitizer's report
        static_cast<volatile fovea_ring_header*>(p)->head = 0;  // must SIGSEGV
        _exit(16);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << "child exited with code " << WEXITSTATUS(status);
    EXPECT_EQ(WTERMSIG(status), SIGSEGV);
    EXPECT_EQ(w.head(), 1u);
    fovea::Client c(inst);
    EXPECT_EQ(c.latest()->index, 0u);
}

// A writer thread and four reader threads over FOVEA_RING_STRESS_SAMPLES records: no reader ever
// sees a torn record, indices only increase, and every record is either read or counted dropped.
TEST(SeqlockRing, ReaderNeverSeesTornSlot) {
    const auto inst = unique_instance("stress");
    RingWriter w = make_writer(inst, 256);  // small ring: readers get lapped now and then
    const uint64_t total = FOVEA_RING_STRESS_SAMPLES;
    std::atomic<bool> done{false};
    std::atomic<uint64_t> torn{0};
    std::vector<std::thread> readers;
    std::vector<uint64_t> seen(4), dropped(4);
    for (int i = 0; i < 4; ++i) {
        readers.emplace_back([&, i] {
            fovea::Client c(inst);
            uint64_t cursor = 0;
            fovea_gaze_record buf[64];
            uint64_t last = 0;
            bool first = true;
            auto drain = [&] {
                uint32_t n = 0;
                uint64_t d = 0;
                fovea_client_read(c.handle(), &cursor, buf, 64, &n, &d);
                dropped[i] += d;
                for (uint32_t k = 0; k < n; ++k) {
                    if (!consistent(buf[k]) || (!first && buf[k].index <= last)) ++torn;
                    last = buf[k].index;
                    first = false;
                }
                seen[i] += n;
                return n + d;
            };
            while (!done.load(std::memory_order_acquire)) {
                if (i % 2 == 0) fovea_client_wait(c.handle(), cursor, 10);  // sleepers
                drain();                                                    // and spinners
            }
            while (drain() > 0) {}
            // latest() under fire, too
            auto l = c.latest();
            if (!l || !consistent(*l)) ++torn;
        });
    }
    for (uint64_t n = 0; n < total; ++n) {
        auto r = make_record(n);
        w.publish(r);
    }
    done.store(true, std::memory_order_release);
    for (auto& t : readers) t.join();
    EXPECT_EQ(torn.load(), 0u);
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(seen[i] + dropped[i], total) << "reader " << i;
        EXPECT_GT(seen[i], 0u);
    }
}

// Reader processes killed with SIGKILL at random points of their read loops never disturb the
// writer, and the next reader attaches normally.
TEST(SeqlockRing, ReaderKilledMidReadNeverDisturbsWriter) {
    const auto inst = unique_instance("kill9");
    RingWriter w = make_writer(inst, 256);
    std::mt19937 rng(42);
    uint64_t n = 0;
    for (int round = 0; round < 40; ++round) {
        const pid_t child = fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            fovea_client* c = nullptr;
            while (fovea_client_open(inst.c_str(), FOVEA_STREAM_GAZE, &c) != FOVEA_OK) {}
            uint64_t cursor = 0;
            fovea_gaze_record buf[32];
            for (;;) {
                uint32_t got = 0;
                fovea_client_read(c, &cursor, buf, 32, &got, nullptr);
                for (uint32_t k = 0; k < got; ++k)
                    if (!consistent(buf[k])) _exit(3);
            }
        }
        const auto until =
            std::chrono::steady_clock::now() + std::chrono::microseconds(500 + rng() % 5000);
        while (std::chrono::steady_clock::now() < until) {
            auto r = make_record(n++);
            w.publish(r);
        }
        kill(child, SIGKILL);
        int status = 0;
        ASSERT_EQ(waitpid(child, &status, 0), child);
        ASSERT_TRUE(WIFSIGNALED(status)) << "reader exited with " << WEXITSTATUS(status);
        EXPECT_EQ(WTERMSIG(status), SIGKILL);
    }
    EXPECT_EQ(w.head(), n);
    EXPECT_FALSE(w.readers_attached());  // dead readers' locks went with them
    fovea::Client c(inst);
    auto latest = c.latest();
    ASSERT_TRUE(latest.has_value());
    EXPECT_EQ(latest->index, n - 1);
}

}  // namespace
