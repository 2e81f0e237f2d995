#include "ring_writer.hpp"

#include <fcntl.h>
#include <linux/futex.h>
#include <sys/file.h>
#include <sys/mman.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstring>
#include <utility>

#include "fovea/client.h"

namespace fovea::ring {
namespace {

int64_t now_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

uint64_t random_generation() {
    uint64_t g = 0;
    if (getrandom(&g, sizeof g, 0) != sizeof g) g = static_cast<uint64_t>(now_ns()) ^ getpid();
    return g | 1;  // never 0, so 0 can mean "no ring"
}

Error sys_error(const std::string& what) {
    return make_error(what + ": " + std::strerror(errno), errno);
}

void copy_name(char* dst, std::size_t capacity, const std::string& src) {
    std::strncpy(dst, src.c_str(), capacity - 1);
    dst[capacity - 1] = '\0';
}

}  // namespace

Result<RingWriter> RingWriter::create(const WriterOptions& options) {
    char name[128];
    if (fovea_ring_name(options.instance.c_str(), options.kind, name, sizeof name) != FOVEA_OK)
        return make_error("invalid instance name '" + options.instance + "' (use [A-Za-z0-9_-])");
    const uint32_t slots = std::bit_ceil(std::max<uint32_t>(options.slot_count, 16));

    RingWriter w;
    w.name_ = name;
    // A crashed writer's object is replaced, never reused: readers still mapping it keep a
    // valid (if stale) view and detect the new generation by its unlinked inode.
    shm_unlink(name);
    w.fd_ = shm_open(name, O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, options.mode);
    if (w.fd_ < 0) return sys_error(std::string("shm_open ") + name);
    fchmod(w.fd_, options.mode);  // not subject to the umask
    w.bytes_ = ring_bytes(slots);
    if (ftruncate(w.fd_, static_cast<off_t>(w.bytes_)) != 0) {
        auto e = sys_error(std::string("ftruncate ") + name);
        shm_unlink(name);
        return e;
    }
    // Every page now, not at its first publish: a first touch is a page fault (tens of us in a
    // VM, in the writer and in every reader), and a full /dev/shm fails here, not as SIGBUS.
    if (const int e = posix_fallocate(w.fd_, 0, static_cast<off_t>(w.bytes_)); e != 0) {
        errno = e;
        auto err = sys_error(std::string("allocating ") + name);
        shm_unlink(name);
        return err;
    }
    void* base =
        mmap(nullptr, w.bytes_, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_POPULATE, w.fd_, 0);
    if (base == MAP_FAILED) {
        auto e = sys_error(std::string("mmap ") + name);
        shm_unlink(name);
        return e;
    }
    auto* h = static_cast<fovea_ring_header*>(base);  // fresh pages are zero
    h->magic = FOVEA_RING_MAGIC;
    h->abi_version = FOVEA_RING_ABI_VERSION;
    h->header_size = sizeof(fovea_ring_header);
    h->slot_size = FOVEA_RING_SLOT_SIZE;
    h->record_size = FOVEA_RING_RECORD_BYTES;
    h->slot_count = slots;
    h->stream_kind = options.kind;
    h->generation = random_generation();
    h->created_ns = now_ns();
    h->writer_pid = static_cast<uint32_t>(getpid());
    h->nominal_rate_hz = options.nominal_rate_hz;
    copy_name(h->stream_name, sizeof h->stream_name,
              options.kind == FOVEA_STREAM_HEAD ? "head" : "gaze");
    copy_name(h->device_name, sizeof h->device_name, options.device_name);
    h->eyes = options.eyes;
    w.view_ = make_view(base);
    __atomic_store_n(&h->state, uint32_t{FOVEA_RING_LIVE}, __ATOMIC_RELEASE);
    return w;
}

RingWriter::RingWriter(RingWriter&& other) noexcept
    : view_(std::exchange(other.view_, RingView{})),
      bytes_(std::exchange(other.bytes_, 0)),
      fd_(std::exchange(other.fd_, -1)),
      name_(std::move(other.name_)) {}

RingWriter& RingWriter::operator=(RingWriter&& other) noexcept {
    if (this != &other) {
        close();
        view_ = std::exchange(other.view_, RingView{});
        bytes_ = std::exchange(other.bytes_, 0);
        fd_ = std::exchange(other.fd_, -1);
        name_ = std::move(other.name_);
    }
    return *this;
}

RingWriter::~RingWriter() { close(); }

void RingWriter::close() {
    if (view_.header) {
        __atomic_store_n(&view_.header->state, uint32_t{FOVEA_RING_CLOSED}, __ATOMIC_RELEASE);
        __atomic_add_fetch(&view_.header->futex_word, 1, __ATOMIC_RELEASE);
        syscall(SYS_futex, &view_.header->futex_word, FUTEX_WAKE, INT32_MAX, nullptr, nullptr, 0);
        munmap(view_.header, bytes_);
        view_ = RingView{};
        // A newer writer may already have replaced our object; never unlink its ring.
        struct stat st {};
        if (fstat(fd_, &st) == 0 && st.st_nlink > 0) shm_unlink(name_.c_str());
    }
    if (fd_ >= 0) ::close(std::exchange(fd_, -1));
}

void RingWriter::set_nominal_rate_hz(uint32_t hz) {
    if (view_.header) __atomic_store_n(&view_.header->nominal_rate_hz, hz, __ATOMIC_RELAXED);
}

uint64_t RingWriter::publish_words(void* record, uint64_t* index_field, int64_t* publish_field,
                                   uint64_t* checksum_field) {
    fovea_ring_header* h = view_.header;
    const uint64_t index = __atomic_load_n(&h->head, __ATOMIC_RELAXED);
    *index_field = index;
    if (*publish_field == 0) *publish_field = now_ns();
    *checksum_field = fovea_record_checksum(record);

    uint64_t* seq = view_.seq_of(index);
    __atomic_store_n(seq, seq_writing(index), __ATOMIC_RELAXED);
    __atomic_thread_fence(__ATOMIC_RELEASE);  // odd seq is visible before any data word
    store_words(view_.words_of(index), record);
    __atomic_store_n(seq, seq_done(index), __ATOMIC_RELEASE);
    __atomic_store_n(&h->head, index + 1, __ATOMIC_RELEASE);
    __atomic_add_fetch(&h->futex_word, 1, __ATOMIC_RELEASE);
    syscall(SYS_futex, &h->futex_word, FUTEX_WAKE, INT32_MAX, nullptr, nullptr, 0);
    return index;
}

uint64_t RingWriter::publish(fovea_gaze_record& record) {
    return publish_words(&record, &record.index, &record.t_publish_ns, &record.checksum);
}

uint64_t RingWriter::publish(fovea_head_record& record) {
    return publish_words(&record, &record.index, &record.t_publish_ns, &record.checksum);
}

bool RingWriter::readers_attached() const {
    if (fd_ < 0) return false;
    // Readers hold LOCK_SH on their own descriptor; an exclusive probe fails while any does.
    if (flock(fd_, LOCK_EX | LOCK_NB) == 0) {
        flock(fd_, LOCK_UN);
        return false;
    }
    return errno == EWOULDBLOCK;
}

}  // namespace fovea::ring
