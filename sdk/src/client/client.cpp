// The C ABI reader of fovea rings. Nothing here throws; errors are codes plus thread-local text.
#include "fovea/client.h"

#include <fcntl.h>
#include <linux/futex.h>
#include <sys/file.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <new>

#include "../ring/seqlock.hpp"
#include "last_error.hpp"

using fovea::ring::RingView;
using fovea::ring::SlotRead;

struct fovea_client {
    char name[128] = {};
    fovea_stream_kind kind = FOVEA_STREAM_GAZE;
    int fd = -1;
    void* base = nullptr;
    std::size_t bytes = 0;
    RingView view;
    int64_t next_check_ns = 0;
    // fovea_client_wait's spin (fovea_client_set_wait_spin): -1 adaptive, 0 never, > 0 cap in us.
    int32_t spin_cap_us = 0;
    uint64_t seen_head = 0;          // head when the writer's cadence was last learned
    int64_t seen_publish_ns = 0;     // t_publish_ns of record seen_head - 1
    int64_t interval_ns = 0;         // moving average of the writer's inter-publish interval
    int64_t lateness_ns = 20'000;    // how late a timed futex sleep returns (learned, high side)
    uint64_t spun_for = UINT64_MAX;  // the cursor whose spin window has been used up
};

namespace fovea::client_detail {

namespace {
thread_local char g_last_error[256] = "";
}

int fail(int status, const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    std::vsnprintf(g_last_error, sizeof g_last_error, fmt, ap);
    va_end(ap);
    return status;
}

const char* last_error() { return g_last_error; }

}  // namespace fovea::client_detail

namespace {

using fovea::client_detail::fail;

int64_t now_ns(clockid_t clock = CLOCK_MONOTONIC) {
    timespec ts{};
    clock_gettime(clock, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

bool valid_instance_char(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
}

void unmap(fovea_client* c) {
    if (c->base) munmap(c->base, c->bytes);
    if (c->fd >= 0) close(c->fd);  // also drops our shared flock
    c->base = nullptr;
    c->fd = -1;
    c->view = RingView{};
}

// Map c->name read-only and validate it against this library's ABI.
int attach(fovea_client* c) {
    int fd = shm_open(c->name, O_RDONLY | O_CLOEXEC, 0);
    if (fd < 0) {
        if (errno == ENOENT)
            return fail(FOVEA_E_NOT_FOUND, "no ring %s: is fovead running for this instance?",
                        c->name);
        return fail(FOVEA_E_SYSTEM, "shm_open %s: %s", c->name, std::strerror(errno));
    }
    struct stat st {};
    if (fstat(fd, &st) != 0 || static_cast<std::size_t>(st.st_size) < sizeof(fovea_ring_header)) {
        close(fd);
        return fail(FOVEA_E_NOT_FOUND, "ring %s is not initialised yet", c->name);
    }
    const auto bytes = static_cast<std::size_t>(st.st_size);
    // Page tables filled now, not by a fault on each page's first read while waiting for gaze.
    void* base = mmap(nullptr, bytes, PROT_READ, MAP_SHARED | MAP_POPULATE, fd, 0);
    if (base == MAP_FAILED) {
        int e = errno;
        close(fd);
        return fail(FOVEA_E_SYSTEM, "mmap %s: %s", c->name, std::strerror(e));
    }
    const auto* h = static_cast<const fovea_ring_header*>(base);
    auto reject = [&](int status, const char* why) {
        munmap(base, bytes);
        close(fd);
        return fail(status, "ring %s: %s", c->name, why);
    };
    if (__atomic_load_n(&h->state, __ATOMIC_ACQUIRE) == FOVEA_RING_INITIALIZING)
        return reject(FOVEA_E_NOT_FOUND, "writer is still initialising it");
    if (h->magic != FOVEA_RING_MAGIC) return reject(FOVEA_E_INCOMPATIBLE, "bad magic");
    if (h->abi_version != FOVEA_RING_ABI_VERSION)
        return reject(FOVEA_E_INCOMPATIBLE, "ring ABI version differs from this libfovea");
    if (h->header_size != sizeof(fovea_ring_header) || h->slot_size != FOVEA_RING_SLOT_SIZE ||
        h->record_size != FOVEA_RING_RECORD_BYTES)
        return reject(FOVEA_E_INCOMPATIBLE, "struct sizes differ from this libfovea");
    if (h->slot_count == 0 || (h->slot_count & (h->slot_count - 1)) != 0 ||
        bytes < fovea::ring::ring_bytes(h->slot_count))
        return reject(FOVEA_E_INCOMPATIBLE, "slot count does not match the object's size");
    if (h->stream_kind != static_cast<uint32_t>(c->kind))
        return reject(FOVEA_E_WRONG_STREAM, "stream kind differs from the one requested");
    // Our shared lock tells the writer a reader is attached (fovead skips work nobody reads).
    while (flock(fd, LOCK_SH) != 0 && errno == EINTR) {}
    c->fd = fd;
    c->base = base;
    c->bytes = bytes;
    c->view = fovea::ring::make_view(base);
    return FOVEA_OK;
}

// Has the writer restarted (our object unlinked) or closed? Re-attach if a new one exists.
int check_restart(fovea_client* c) {
    struct stat st {};
    const bool unlinked = fstat(c->fd, &st) == 0 && st.st_nlink == 0;
    const bool closed =
        __atomic_load_n(&c->view.header->state, __ATOMIC_ACQUIRE) == FOVEA_RING_CLOSED;
    if (!unlinked && !closed) return FOVEA_OK;
    fovea_client fresh;
    std::memcpy(fresh.name, c->name, sizeof fresh.name);
    fresh.kind = c->kind;
    if (attach(&fresh) != FOVEA_OK) return FOVEA_OK;  // no new writer yet: keep the old view
    if (fresh.view.header->generation == c->view.header->generation) {
        unmap(&fresh);
        return FOVEA_OK;
    }
    unmap(c);
    c->fd = fresh.fd;
    c->base = fresh.base;
    c->bytes = fresh.bytes;
    c->view = fresh.view;
    return fail(FOVEA_E_WRITER_RESTARTED, "writer of %s restarted (generation %llx)", c->name,
                static_cast<unsigned long long>(c->view.header->generation));
}

int maybe_check_restart(fovea_client* c) {
    const int64_t t = now_ns(CLOCK_MONOTONIC_COARSE);
    if (t < c->next_check_ns) return FOVEA_OK;
    c->next_check_ns = t + 100'000'000;
    return check_restart(c);
}

uint64_t head_of(const fovea_client* c) {
    return __atomic_load_n(&c->view.header->head, __ATOMIC_ACQUIRE);
}

int latest_record(fovea_client* c, fovea_stream_kind kind, void* out) {
    if (!c || !out) return fail(FOVEA_E_INVALID_ARGUMENT, "null argument");
    if (c->kind != kind) return fail(FOVEA_E_WRONG_STREAM, "wrong stream kind for this call");
    for (int attempt = 0; attempt < 64; ++attempt) {
        const uint64_t head = head_of(c);
        if (head == 0) {
            int r = maybe_check_restart(c);
            return r != FOVEA_OK ? r : fail(FOVEA_E_NO_DATA, "nothing published yet");
        }
        // Only a writer a whole lap ahead could overwrite head-1 mid-copy; then simply retry.
        if (fovea::ring::read_slot(c->view, head - 1, out) == SlotRead::kOk) return FOVEA_OK;
    }
    return fail(FOVEA_E_SYSTEM, "could not read an untorn record in 64 attempts");
}

int read_records(fovea_client* c, fovea_stream_kind kind, uint64_t* cursor, void* out,
                 uint32_t capacity, uint32_t* out_count, uint64_t* out_dropped) {
    if (!c || !cursor || (!out && capacity) || !out_count)
        return fail(FOVEA_E_INVALID_ARGUMENT, "null argument");
    if (c->kind != kind) return fail(FOVEA_E_WRONG_STREAM, "wrong stream kind for this call");
    *out_count = 0;
    uint64_t dropped = 0;
    auto* dst = static_cast<unsigned char*>(out);
    const uint64_t slots = c->view.header->slot_count;
    uint64_t head = head_of(c);
    if (*cursor > head) *cursor = head;  // a cursor from a previous generation
    while (*out_count < capacity && *cursor < head) {
        if (head - *cursor > slots) {  // lapped: everything older than one ring is gone
            dropped += head - slots - *cursor;
            *cursor = head - slots;
        }
        const SlotRead r = fovea::ring::read_slot(c->view, *cursor, dst);
        if (r == SlotRead::kOk) {
            dst += FOVEA_RING_RECORD_BYTES;
            ++*out_count;
            ++*cursor;
        } else if (r == SlotRead::kOverwritten) {
            ++dropped;
            ++*cursor;
            head = head_of(c);
        } else {
            break;  // not yet complete (cannot happen below head, but never spin on it)
        }
    }
    if (out_dropped) *out_dropped = dropped;
    if (*out_count == 0 && dropped == 0) return maybe_check_restart(c);
    return FOVEA_OK;
}

// One spin-wait step that lets a sibling hyperthread (or the hypervisor) run.
inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#elif defined(__aarch64__)
    asm volatile("yield");
#endif
}

// Learn the writer's cadence from the publish stamps of the records it wrote since last time
// (word 4 of either record type is t_publish_ns; a racing overwrite only feeds the average one
// odd value, which the bounds below reject or the average absorbs).
void learn_cadence(fovea_client* c, uint64_t head) {
    if (head == 0 || head == c->seen_head) return;
    const int64_t t =
        static_cast<int64_t>(__atomic_load_n(c->view.words_of(head - 1) + 4, __ATOMIC_RELAXED));
    if (c->seen_head != 0 && head > c->seen_head && t > c->seen_publish_ns) {
        const int64_t d = (t - c->seen_publish_ns) / static_cast<int64_t>(head - c->seen_head);
        if (d > 0 && d < 1'000'000'000)
            c->interval_ns = c->interval_ns == 0 ? d : c->interval_ns + (d - c->interval_ns) / 8;
    }
    c->seen_head = head;
    c->seen_publish_ns = t;
}

// The spin window for the next record: [from, until) around when the writer's cadence says it is
// due, at most an eighth of the interval (and the caller's cap) long, starting early by what a
// timed sleep is late. from == until: no spin.
struct SpinWindow {
    int64_t from = 0, until = 0;
};

SpinWindow spin_window(const fovea_client* c) {
    if (c->spin_cap_us == 0 || c->interval_ns == 0) return {};
    int64_t width = c->interval_ns / 8;
    if (c->spin_cap_us > 0) width = std::min<int64_t>(width, int64_t{c->spin_cap_us} * 1000);
    const int64_t due = c->seen_publish_ns + c->interval_ns;
    const int64_t lead = std::min(c->lateness_ns + 5'000, width * 3 / 4);
    return {due - lead, due - lead + width};
}

}  // namespace

extern "C" {

const char* fovea_last_error(void) { return fovea::client_detail::last_error(); }

const char* fovea_status_string(int status) {
    switch (status) {
        case FOVEA_OK: return "FOVEA_OK";
        case FOVEA_E_INVALID_ARGUMENT: return "FOVEA_E_INVALID_ARGUMENT";
        case FOVEA_E_NOT_FOUND: return "FOVEA_E_NOT_FOUND";
        case FOVEA_E_INCOMPATIBLE: return "FOVEA_E_INCOMPATIBLE";
        case FOVEA_E_TIMEOUT: return "FOVEA_E_TIMEOUT";
        case FOVEA_E_NO_DATA: return "FOVEA_E_NO_DATA";
        case FOVEA_E_WRITER_RESTARTED: return "FOVEA_E_WRITER_RESTARTED";
        case FOVEA_E_SYSTEM: return "FOVEA_E_SYSTEM";
        case FOVEA_E_WRONG_STREAM: return "FOVEA_E_WRONG_STREAM";
        case FOVEA_E_REJECTED: return "FOVEA_E_REJECTED";
        default: return "FOVEA_E_UNKNOWN";
    }
}

uint32_t fovea_abi_version(void) { return FOVEA_RING_ABI_VERSION; }

int fovea_ring_name(const char* instance, fovea_stream_kind kind, char* out_name, size_t capacity) {
    if (!out_name) return fail(FOVEA_E_INVALID_ARGUMENT, "null out_name");
    if (!instance || !*instance) instance = "default";
    const std::size_t len = std::strlen(instance);
    if (len > 64) return fail(FOVEA_E_INVALID_ARGUMENT, "instance name longer than 64 characters");
    for (std::size_t i = 0; i < len; ++i)
        if (!valid_instance_char(instance[i]))
            return fail(FOVEA_E_INVALID_ARGUMENT, "instance name '%s' may hold only [A-Za-z0-9_-]",
                        instance);
    const char* stream = kind == FOVEA_STREAM_HEAD ? "head" : "gaze";
    if (kind != FOVEA_STREAM_HEAD && kind != FOVEA_STREAM_GAZE)
        return fail(FOVEA_E_INVALID_ARGUMENT, "unknown stream kind %d", static_cast<int>(kind));
    const int n = std::snprintf(out_name, capacity, "/fovea.%s.%s", instance, stream);
    if (n < 0 || static_cast<std::size_t>(n) >= capacity)
        return fail(FOVEA_E_INVALID_ARGUMENT, "ring name does not fit in %zu bytes", capacity);
    return FOVEA_OK;
}

int fovea_client_open(const char* instance, fovea_stream_kind kind, fovea_client** out_client) {
    if (!out_client) return fail(FOVEA_E_INVALID_ARGUMENT, "null out_client");
    *out_client = nullptr;
    auto* c = new (std::nothrow) fovea_client;
    if (!c) return fail(FOVEA_E_SYSTEM, "out of memory");
    c->kind = kind;
    int r = fovea_ring_name(instance, kind, c->name, sizeof c->name);
    if (r == FOVEA_OK) r = attach(c);
    if (r != FOVEA_OK) {
        delete c;
        return r;
    }
    *out_client = c;
    return FOVEA_OK;
}

void fovea_client_close(fovea_client** client) {
    if (!client || !*client) return;
    unmap(*client);
    delete *client;
    *client = nullptr;
}

int fovea_client_info(const fovea_client* c, fovea_ring_info* out) {
    if (!c || !out) return fail(FOVEA_E_INVALID_ARGUMENT, "null argument");
    const fovea_ring_header* h = c->view.header;
    *out = fovea_ring_info{};
    out->generation = h->generation;
    out->slot_count = h->slot_count;
    out->stream_kind = h->stream_kind;
    out->nominal_rate_hz = __atomic_load_n(&h->nominal_rate_hz, __ATOMIC_RELAXED);
    out->writer_pid = h->writer_pid;
    std::memcpy(out->stream_name, h->stream_name, sizeof out->stream_name);
    std::memcpy(out->device_name, h->device_name, sizeof out->device_name);
    out->stream_name[sizeof out->stream_name - 1] = '\0';
    out->device_name[sizeof out->device_name - 1] = '\0';
    return FOVEA_OK;
}

int fovea_client_eye_geometry(const fovea_client* c, fovea_eye_geometry* out) {
    if (!c || !out) return fail(FOVEA_E_INVALID_ARGUMENT, "null argument");
    std::memcpy(out, &c->view.header->eyes, sizeof *out);
    return FOVEA_OK;
}

uint64_t fovea_client_head(const fovea_client* c) { return c ? head_of(c) : 0; }

int fovea_client_latest(fovea_client* c, fovea_gaze_record* out) {
    return latest_record(c, FOVEA_STREAM_GAZE, out);
}

int fovea_client_latest_head(fovea_client* c, fovea_head_record* out) {
    return latest_record(c, FOVEA_STREAM_HEAD, out);
}

int fovea_client_read(fovea_client* c, uint64_t* cursor, fovea_gaze_record* out, uint32_t capacity,
                      uint32_t* out_count, uint64_t* out_dropped) {
    return read_records(c, FOVEA_STREAM_GAZE, cursor, out, capacity, out_count, out_dropped);
}

int fovea_client_read_head(fovea_client* c, uint64_t* cursor, fovea_head_record* out,
                           uint32_t capacity, uint32_t* out_count, uint64_t* out_dropped) {
    return read_records(c, FOVEA_STREAM_HEAD, cursor, out, capacity, out_count, out_dropped);
}

int fovea_client_check(fovea_client* c) {
    if (!c) return fail(FOVEA_E_INVALID_ARGUMENT, "null client");
    return check_restart(c);
}

int fovea_client_set_wait_spin(fovea_client* c, int32_t max_spin_us) {
    if (!c) return fail(FOVEA_E_INVALID_ARGUMENT, "null client");
    c->spin_cap_us = max_spin_us < 0 ? -1 : max_spin_us;
    return FOVEA_OK;
}

int fovea_client_wait(fovea_client* c, uint64_t cursor, int32_t timeout_ms) {
    if (!c) return fail(FOVEA_E_INVALID_ARGUMENT, "null client");
    const int64_t deadline =
        timeout_ms < 0 ? INT64_MAX : now_ns() + int64_t{timeout_ms} * 1'000'000;
    fovea_ring_header* h = c->view.header;
    for (;;) {
        // Read the futex word before the head: a publish in between changes the word, so the
        // FUTEX_WAIT below returns at once instead of sleeping through it.
        const uint32_t word = __atomic_load_n(&h->futex_word, __ATOMIC_ACQUIRE);
        const uint64_t head = head_of(c);
        learn_cadence(c, head);
        if (head > cursor) return FOVEA_OK;
        int64_t now = now_ns();
        if (now >= deadline) {
            const int r = check_restart(c);
            return r != FOVEA_OK ? r
                                 : fail(FOVEA_E_TIMEOUT, "no new sample within %d ms", timeout_ms);
        }
        if (__atomic_load_n(&h->state, __ATOMIC_ACQUIRE) == FOVEA_RING_CLOSED) {
            const int r = check_restart(c);
            if (r != FOVEA_OK) return r;
        }
        // Wake at least every 100 ms to notice a restarted writer, which wakes no one here.
        int64_t sleep_ns = std::min<int64_t>(deadline - now, 100'000'000);
        // Waiting for the very next record of a periodic writer: sleep until its spin window,
        // then spin through the window (once per record) instead of paying the wake-up latency.
        const SpinWindow win =
            cursor == head && c->spun_for != cursor ? spin_window(c) : SpinWindow{};
        bool timed_to_window = false;
        if (win.until > now) {
            if (now >= win.from) {
                const int64_t until = std::min(win.until, deadline);
                while (now < until) {
                    for (int i = 0; i < 4; ++i) cpu_relax();
                    if (head_of(c) > cursor) return FOVEA_OK;
                    now = now_ns();
                }
                c->spun_for = cursor;  // missed: sleep on the futex until the record comes
                continue;
            }
            timed_to_window = win.from - now <= sleep_ns;
            sleep_ns = std::min(sleep_ns, win.from - now);
        }
        timespec ts{static_cast<time_t>(sleep_ns / 1'000'000'000),
                    static_cast<long>(sleep_ns % 1'000'000'000)};
        const long slept = syscall(SYS_futex, &h->futex_word, FUTEX_WAIT, word, &ts, nullptr, 0);
        const int64_t woke = now_ns();
        if (timed_to_window && slept != 0 && errno == ETIMEDOUT) {
            // Learn how late a timed sleep returns, rising fast and falling slowly.
            const int64_t late = woke - win.from;
            c->lateness_ns +=
                late > c->lateness_ns ? (late - c->lateness_ns) / 4 : (late - c->lateness_ns) / 32;
        }
        if (woke - now >= 99'000'000) {
            const int r = maybe_check_restart(c);
            if (r != FOVEA_OK) return r;
        }
    }
}

}  // extern "C"
