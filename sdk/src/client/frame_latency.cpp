// Render-side latency hops (C ABI, fovea/client.h): per-hop histograms of the frame events a
// host reports, the stale-gaze counter, and the `latency.report` request to fovead.
#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include <rapidjson/document.h>
#include <rapidjson/writer.h>

#include "fovea/client.h"
#include "fovea/latency_histogram.hpp"
#include "fovea/runtime_dir.hpp"
#include "last_error.hpp"

using fovea::LatencyHistogram;
using fovea::client_detail::fail;

namespace {

// fovead refuses control requests over 64 KB (ControlServer::kMaxRequestBytes); stay below.
constexpr std::size_t kRequestCapacity = 60 * 1024;

constexpr std::array<const char*, FOVEA_RENDER_HOP_COUNT> kHopNames = {
    "publish_to_read",   "read_to_frame_begin",    "frame_begin_to_submit",
    "submit_to_present", "capture_to_frame_begin", "publish_to_frame_begin",
    "capture_to_present"};

int64_t now_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

enum class Stage { kNone, kBegun, kSubmitted };

}  // namespace

struct fovea_frame_latency {
    std::array<LatencyHistogram, FOVEA_RENDER_HOP_COUNT> hops;

    // The most recently read record, to pair with the frame that uses it.
    bool have_read = false;
    uint64_t read_index = 0;
    int64_t read_publish_ns = 0;
    int64_t read_at_ns = 0;

    // The open frame.
    Stage stage = Stage::kNone;
    int64_t begin_ns = 0;
    int64_t submit_ns = 0;
    bool frame_has_gaze = false;
    int64_t frame_capture_ns = 0;

    // Written by the event thread, read by any: atomics, single writer (relaxed is enough).
    std::atomic<int64_t> stale_threshold_ns{FOVEA_STALE_GAZE_DEFAULT_NS};
    std::atomic<uint64_t> frames{0}, stale_frames{0}, frames_without_gaze{0}, submitted{0},
        presented{0};

    // Scratch space for the report request: no allocation after create.
    mutable char request[kRequestCapacity];
};

namespace {

void bump(std::atomic<uint64_t>& a) {
    a.store(a.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
}

LatencyHistogram& hop(fovea_frame_latency* fl, fovea_render_hop h) {
    return fl->hops[static_cast<std::size_t>(h)];
}

bool resolve_time(int64_t& t) {
    if (t < 0) return false;
    if (t == 0) t = now_ns();
    return true;
}

// RapidJSON output stream over a fixed buffer: remembers overflow instead of truncating
// silently. RapidJSON (not nlohmann) because its writer and in-situ parser run on caller-supplied
// memory, and this C ABI promises no allocation after create.
struct FixedBuffer {
    using Ch = char;
    char* buf;
    std::size_t cap;
    std::size_t len = 0;
    bool overflow = false;

    void Put(char c) {
        if (len + 1 >= cap) {  // keep one byte for the NUL
            overflow = true;
            return;
        }
        buf[len++] = c;
    }
    void Flush() {}
};

// Pools over stack memory for RapidJSON's bookkeeping; sized well past what one request or one
// reply line needs, so the heap fallback (a larger document) never happens in practice.
template <std::size_t N>
struct Pool {
    alignas(std::max_align_t) char bytes[N];
    rapidjson::MemoryPoolAllocator<> allocator{bytes, sizeof bytes};
};

using JsonWriter = rapidjson::Writer<FixedBuffer, rapidjson::UTF8<>, rapidjson::UTF8<>,
                                     rapidjson::MemoryPoolAllocator<>>;

// One histogram in the form fovead's histogram_from_json() reads. With coarsen_bits > 0 the
// counts of each group of 2^bits neighbouring sub-buckets go to the group's first bucket (an
// octave holds 64 sub-buckets, so groups never cross octaves): the percentile error grows to
// 2^bits / 64 of the value while count, sum, min and max stay exact.
void write_histogram(JsonWriter& w, const LatencyHistogram& h, int coarsen_bits) {
    const uint64_t count = h.count();
    w.StartObject();
    w.Key("count");
    w.Uint64(count);
    w.Key("negative");
    w.Uint64(h.negative());
    w.Key("sum_ns");
    w.Uint64(h.sum_ns());
    w.Key("min_ns");
    w.Uint64(h.min_ns());
    w.Key("max_ns");
    w.Uint64(h.max_ns());
    w.Key("buckets");
    w.StartArray();
    auto bucket = [&](int index, uint64_t c) {
        w.StartArray();
        w.Int(index);
        w.Uint64(c);
        w.EndArray();
    };
    const int group = 1 << coarsen_bits;
    // A snapshot taken while the event thread records may hold a few more bucket counts than
    // `count`; the daemon rejects a mismatch, so stop adding once `count` is reached.
    uint64_t written = 0;
    for (int i = 0; i < LatencyHistogram::kBucketCount && written < count; i += group) {
        uint64_t c = 0;
        for (int j = i; j < i + group && j < LatencyHistogram::kBucketCount; ++j)
            c += h.bucket_count(j);
        c = std::min(c, count - written);
        if (c == 0) continue;
        bucket(i, c);
        written += c;
    }
    // ...and fewer if it raced the other way: put the rest in the max's bucket.
    if (written < count) bucket(LatencyHistogram::bucket_of(h.max_ns()), count - written);
    w.EndArray();
    w.EndObject();
}

// The request line into out; false if it does not fit.
bool write_request(const fovea_frame_latency* fl, FixedBuffer& out, int coarsen_bits) {
    Pool<2048> stack;
    JsonWriter w(out, &stack.allocator);
    w.StartObject();
    w.Key("cmd");
    w.String("latency.report");
    w.Key("hops");
    w.StartObject();
    for (std::size_t i = 0; i < fl->hops.size(); ++i) {
        if (fl->hops[i].count() == 0) continue;
        w.Key(kHopNames[i]);
        write_histogram(w, fl->hops[i], coarsen_bits);
    }
    w.EndObject();
    const auto counter = [&](const char* key, uint64_t v) {
        w.Key(key);
        w.Uint64(v);
    };
    counter("frames", fl->frames.load(std::memory_order_relaxed));
    counter("stale_frames", fl->stale_frames.load(std::memory_order_relaxed));
    counter("frames_without_gaze", fl->frames_without_gaze.load(std::memory_order_relaxed));
    w.Key("stale_threshold_ns");
    w.Int64(fl->stale_threshold_ns.load(std::memory_order_relaxed));
    w.EndObject();
    out.Put('\n');
    if (out.overflow) return false;
    out.buf[out.len] = '\0';
    return true;
}

bool valid_instance(const char* s) {
    if (std::strlen(s) > 64) return false;
    for (; *s; ++s) {
        const char c = *s;
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
              c == '_' || c == '-'))
            return false;
    }
    return true;
}

struct Fd {
    int fd;
    ~Fd() {
        if (fd >= 0) close(fd);
    }
};

// Wait for `fd` to become ready for `events` until deadline; false on timeout.
int wait_fd(int fd, short events, int64_t deadline_ns) {
    for (;;) {
        const int64_t left_ms = (deadline_ns - now_ns()) / 1'000'000;
        if (left_ms <= 0) return 0;
        pollfd p{fd, events, 0};
        const int r = poll(&p, 1, static_cast<int>(std::min<int64_t>(left_ms, 1 << 30)));
        if (r < 0 && errno == EINTR) continue;
        return r;
    }
}

using ReplyDocument =
    rapidjson::GenericDocument<rapidjson::UTF8<>, rapidjson::MemoryPoolAllocator<>,
                               rapidjson::MemoryPoolAllocator<>>;

// prefix + text into out, cut to fit.
void put_text(char* out, std::size_t cap, const char* prefix, const char* text) {
    std::size_t n = 0;
    for (const char* p : {prefix, text})
        for (; *p && n + 1 < cap; ++p) out[n++] = *p;
    out[n] = '\0';
}

// What fovead said to a report: ok, or its reason. The reply is one line,
// {"accepted":true,"ok":true} or {"error":"...","ok":false}; parsed in place (reply changes).
bool reply_ok(char* reply, char* why, std::size_t cap) {
    Pool<4096> values;
    Pool<2048> stack;
    ReplyDocument d(&values.allocator, 1024, &stack.allocator);
    if (char* nl = std::strchr(reply, '\n')) *nl = '\0';
    char copy[512];  // for the message: in-situ parsing rewrites the buffer
    std::snprintf(copy, sizeof copy, "%s", reply);
    d.ParseInsitu(reply);
    if (d.HasParseError() || !d.IsObject()) {
        put_text(why, cap, "not a JSON object: ", copy);
        return false;
    }
    // HasMember + operator[], not FindMember != MemberEnd: RapidJSON 1.1's member iterators
    // compare ambiguously under C++20 (clang's -Wambiguous-reversed-operator).
    if (d.HasMember("ok") && d["ok"].IsBool() && d["ok"].GetBool()) return true;
    if (d.HasMember("error") && d["error"].IsString()) {
        put_text(why, cap, "", d["error"].GetString());
    } else {
        put_text(why, cap, "", copy);
    }
    return false;
}

}  // namespace

extern "C" {

const char* fovea_render_hop_name(int hop) {
    if (hop < 0 || hop >= FOVEA_RENDER_HOP_COUNT) return nullptr;
    return kHopNames[static_cast<std::size_t>(hop)];
}

int fovea_frame_latency_create(fovea_frame_latency** out) {
    if (!out) return fail(FOVEA_E_INVALID_ARGUMENT, "null out");
    *out = new (std::nothrow) fovea_frame_latency;
    if (!*out) return fail(FOVEA_E_SYSTEM, "out of memory");
    return FOVEA_OK;
}

void fovea_frame_latency_destroy(fovea_frame_latency** fl) {
    if (!fl) return;
    delete *fl;
    *fl = nullptr;
}

int fovea_frame_latency_set_stale_threshold(fovea_frame_latency* fl, int64_t threshold_ns) {
    if (!fl) return fail(FOVEA_E_INVALID_ARGUMENT, "null frame latency");
    if (threshold_ns <= 0)
        return fail(FOVEA_E_INVALID_ARGUMENT, "stale threshold must be > 0 ns, got %" PRId64,
                    threshold_ns);
    fl->stale_threshold_ns.store(threshold_ns, std::memory_order_relaxed);
    return FOVEA_OK;
}

void fovea_frame_latency_reset(fovea_frame_latency* fl) {
    if (!fl) return;
    for (auto& h : fl->hops) h.reset();
    fl->have_read = false;
    fl->stage = Stage::kNone;
    for (auto* c :
         {&fl->frames, &fl->stale_frames, &fl->frames_without_gaze, &fl->submitted, &fl->presented})
        c->store(0, std::memory_order_relaxed);
}

int fovea_frame_gaze_read(fovea_frame_latency* fl, const fovea_gaze_record* record,
                          int64_t t_read_ns) {
    if (!fl || !record) return fail(FOVEA_E_INVALID_ARGUMENT, "null argument");
    if (!resolve_time(t_read_ns)) return fail(FOVEA_E_INVALID_ARGUMENT, "negative time");
    hop(fl, FOVEA_HOP_PUBLISH_TO_READ).record(t_read_ns - record->t_publish_ns);
    fl->have_read = true;
    fl->read_index = record->index;
    fl->read_publish_ns = record->t_publish_ns;
    fl->read_at_ns = t_read_ns;
    return FOVEA_OK;
}

int fovea_frame_begin(fovea_frame_latency* fl, const fovea_gaze_record* record, int64_t t_begin_ns,
                      int64_t* out_gaze_age_ns) {
    if (!fl) return fail(FOVEA_E_INVALID_ARGUMENT, "null frame latency");
    if (!resolve_time(t_begin_ns)) return fail(FOVEA_E_INVALID_ARGUMENT, "negative time");
    bump(fl->frames);
    fl->stage = Stage::kBegun;
    fl->begin_ns = t_begin_ns;
    fl->frame_has_gaze = record != nullptr;
    if (!record) {
        bump(fl->frames_without_gaze);
        bump(fl->stale_frames);
        if (out_gaze_age_ns) *out_gaze_age_ns = -1;
        return FOVEA_OK;
    }
    // Records are identified by (index, publish time): an index alone repeats across writer
    // generations.
    if (fl->have_read && fl->read_index == record->index &&
        fl->read_publish_ns == record->t_publish_ns) {
        hop(fl, FOVEA_HOP_READ_TO_FRAME_BEGIN).record(t_begin_ns - fl->read_at_ns);
    }
    const int64_t age = t_begin_ns - record->t_capture_ns;
    hop(fl, FOVEA_HOP_CAPTURE_TO_FRAME_BEGIN).record(age);
    hop(fl, FOVEA_HOP_PUBLISH_TO_FRAME_BEGIN).record(t_begin_ns - record->t_publish_ns);
    if (age > fl->stale_threshold_ns.load(std::memory_order_relaxed)) bump(fl->stale_frames);
    fl->frame_capture_ns = record->t_capture_ns;
    if (out_gaze_age_ns) *out_gaze_age_ns = age < 0 ? 0 : age;
    return FOVEA_OK;
}

int fovea_frame_submitted(fovea_frame_latency* fl, int64_t t_submit_ns) {
    if (!fl) return fail(FOVEA_E_INVALID_ARGUMENT, "null frame latency");
    if (!resolve_time(t_submit_ns)) return fail(FOVEA_E_INVALID_ARGUMENT, "negative time");
    if (fl->stage != Stage::kBegun)
        return fail(FOVEA_E_NO_DATA, "fovea_frame_submitted without fovea_frame_begin");
    hop(fl, FOVEA_HOP_FRAME_BEGIN_TO_SUBMIT).record(t_submit_ns - fl->begin_ns);
    fl->submit_ns = t_submit_ns;
    fl->stage = Stage::kSubmitted;
    bump(fl->submitted);
    return FOVEA_OK;
}

int fovea_frame_presented(fovea_frame_latency* fl, int64_t t_present_ns) {
    if (!fl) return fail(FOVEA_E_INVALID_ARGUMENT, "null frame latency");
    if (!resolve_time(t_present_ns)) return fail(FOVEA_E_INVALID_ARGUMENT, "negative time");
    if (fl->stage != Stage::kSubmitted)
        return fail(FOVEA_E_NO_DATA, "fovea_frame_presented without fovea_frame_submitted");
    hop(fl, FOVEA_HOP_SUBMIT_TO_PRESENT).record(t_present_ns - fl->submit_ns);
    if (fl->frame_has_gaze)
        hop(fl, FOVEA_HOP_CAPTURE_TO_PRESENT).record(t_present_ns - fl->frame_capture_ns);
    fl->stage = Stage::kNone;
    bump(fl->presented);
    return FOVEA_OK;
}

int fovea_frame_latency_hop(const fovea_frame_latency* fl, fovea_render_hop h,
                            fovea_hop_stats* out) {
    if (!fl || !out) return fail(FOVEA_E_INVALID_ARGUMENT, "null argument");
    if (h < 0 || h >= FOVEA_RENDER_HOP_COUNT)
        return fail(FOVEA_E_INVALID_ARGUMENT, "unknown render hop %d", static_cast<int>(h));
    const LatencyHistogram& s = fl->hops[static_cast<std::size_t>(h)];
    auto ns = [](uint64_t v) { return static_cast<int64_t>(v); };
    *out = fovea_hop_stats{};
    out->count = s.count();
    out->negative = s.negative();
    out->p50_ns = ns(s.percentile(0.50));
    out->p90_ns = ns(s.percentile(0.90));
    out->p99_ns = ns(s.percentile(0.99));
    out->p999_ns = ns(s.percentile(0.999));
    out->min_ns = ns(s.min_ns());
    out->max_ns = ns(s.max_ns());
    out->mean_ns = s.mean_ns();
    return FOVEA_OK;
}

int fovea_frame_latency_counters(const fovea_frame_latency* fl, fovea_frame_counters* out) {
    if (!fl || !out) return fail(FOVEA_E_INVALID_ARGUMENT, "null argument");
    *out = fovea_frame_counters{};
    out->frames = fl->frames.load(std::memory_order_relaxed);
    out->stale_frames = fl->stale_frames.load(std::memory_order_relaxed);
    out->frames_without_gaze = fl->frames_without_gaze.load(std::memory_order_relaxed);
    out->submitted = fl->submitted.load(std::memory_order_relaxed);
    out->presented = fl->presented.load(std::memory_order_relaxed);
    out->stale_threshold_ns = fl->stale_threshold_ns.load(std::memory_order_relaxed);
    return FOVEA_OK;
}

int fovea_frame_latency_report(const fovea_frame_latency* fl, const char* instance,
                               int32_t timeout_ms) {
    if (!fl) return fail(FOVEA_E_INVALID_ARGUMENT, "null frame latency");
    if (!instance || !*instance) instance = "default";
    if (!valid_instance(instance))
        return fail(FOVEA_E_INVALID_ARGUMENT,
                    "instance name '%.64s' may hold only [A-Za-z0-9_-], at most 64", instance);
    if (timeout_ms <= 0) return fail(FOVEA_E_INVALID_ARGUMENT, "timeout must be > 0 ms");
    const int64_t deadline = now_ns() + int64_t{timeout_ms} * 1'000'000;

    // Coarsen the buckets until the request fits the daemon's limit (wide distributions only).
    FixedBuffer w{fl->request, sizeof fl->request};
    for (int bits = 0; bits <= LatencyHistogram::kSubBucketBits; ++bits) {
        w = FixedBuffer{fl->request, sizeof fl->request};
        if (write_request(fl, w, bits)) break;
    }
    if (w.overflow) return fail(FOVEA_E_SYSTEM, "latency report does not fit in %zu bytes", w.cap);

    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    char dir[sizeof addr.sun_path];
    fovea::runtime_dir(dir, sizeof dir);
    const int n = std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s/%s.sock", dir, instance);
    if (n < 0 || static_cast<std::size_t>(n) >= sizeof addr.sun_path)
        return fail(FOVEA_E_INVALID_ARGUMENT, "control socket path too long: %s/%s.sock", dir,
                    instance);
    Fd s{socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0)};
    if (s.fd < 0) return fail(FOVEA_E_SYSTEM, "socket: %s", std::strerror(errno));
    // A Unix-socket connect completes at once (or fails); only the I/O after it may block.
    if (connect(s.fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
        const int e = errno;
        if (e == ENOENT || e == ECONNREFUSED)
            return fail(FOVEA_E_NOT_FOUND, "no fovead at %s (%s): is it running for instance '%s'?",
                        addr.sun_path, std::strerror(e), instance);
        return fail(FOVEA_E_SYSTEM, "connect %s: %s", addr.sun_path, std::strerror(e));
    }
    if (fcntl(s.fd, F_SETFL, fcntl(s.fd, F_GETFL) | O_NONBLOCK) != 0)
        return fail(FOVEA_E_SYSTEM, "fcntl: %s", std::strerror(errno));
    for (std::size_t sent = 0; sent < w.len;) {
        const ssize_t k = send(s.fd, w.buf + sent, w.len - sent, MSG_NOSIGNAL);
        if (k > 0) {
            sent += static_cast<std::size_t>(k);
            continue;
        }
        if (k < 0 && errno == EINTR) continue;
        if (k < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            if (wait_fd(s.fd, POLLOUT, deadline) == 0)
                return fail(FOVEA_E_TIMEOUT, "fovead did not take the report within %d ms",
                            timeout_ms);
            continue;
        }
        return fail(FOVEA_E_SYSTEM, "send to %s: %s", addr.sun_path, std::strerror(errno));
    }
    // The reply is one short line: {"accepted":true,"ok":true} or {"error":"...","ok":false}.
    char reply[512];
    std::size_t got = 0;
    while (got == 0 || !std::memchr(reply, '\n', got)) {
        if (got + 1 >= sizeof reply) break;
        const ssize_t k = recv(s.fd, reply + got, sizeof reply - 1 - got, 0);
        if (k > 0) {
            got += static_cast<std::size_t>(k);
            continue;
        }
        if (k == 0) break;
        if (errno == EINTR) continue;
        if (errno == EAGAIN || errno == EWOULDBLOCK) {
            if (wait_fd(s.fd, POLLIN, deadline) == 0)
                return fail(FOVEA_E_TIMEOUT, "no reply from fovead within %d ms", timeout_ms);
            continue;
        }
        return fail(FOVEA_E_SYSTEM, "recv from %s: %s", addr.sun_path, std::strerror(errno));
    }
    reply[got] = '\0';
    if (got == 0) return fail(FOVEA_E_SYSTEM, "fovead closed the connection without a reply");
    char why[200];
    if (reply_ok(reply, why, sizeof why)) return FOVEA_OK;
    return fail(FOVEA_E_REJECTED, "fovead refused the latency report: %s", why);
}

}  // extern "C"
