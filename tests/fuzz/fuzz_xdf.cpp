// XDF reader and repair over arbitrary bytes (what `fovea repair`, export, replay and report
// read). The reader must never crash and what it delivers must be consistent: the valid prefix
// reads back alone to the same streams, untruncated. Repair, run on a file in /dev/shm, must
// leave a file that reads back whole, with every stream closed and every sample kept, and that
// a second repair finds already closed.
#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <string>

#include "fovea/record/xdf.hpp"

namespace xdf = fovea::record::xdf;

namespace {

void check(bool ok) {
    if (!ok) std::abort();
}

uint64_t sample_total(const xdf::File& f) {
    uint64_t n = 0;
    for (const auto& s : f.streams) n += s.sample_count();
    return n;
}

void check_consistent(const xdf::File& f) {
    check(f.valid_bytes <= f.file_size);
    check(f.truncated == (f.valid_bytes < f.file_size));
    for (const auto& s : f.streams) {
        check(s.channel_count > 0);
        const std::size_t cells = s.sample_count() * static_cast<std::size_t>(s.channel_count);
        if (s.format == xdf::Format::kString) {
            check(s.string_values.size() == cells && s.values.empty());
        } else {
            check(s.values.size() == cells && s.string_values.empty());
        }
    }
    // Chunks tile the valid bytes in order (a chunk is >= 2 bytes of prefix + its length).
    uint64_t next = 4;
    for (const auto& c : f.chunks) {
        check(c.offset >= next && c.length >= 2);
        next = c.offset + 2 + c.length;
        check(next <= f.valid_bytes);
    }
}

bool write_all(const std::string& path, const uint8_t* data, std::size_t size) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0) return false;
    std::size_t done = 0;
    while (done < size) {
        const ssize_t w = ::write(fd, data + done, size - done);
        if (w <= 0) break;
        done += static_cast<std::size_t>(w);
    }
    ::close(fd);
    return done == size;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    auto parsed = xdf::parse(data, size);
    if (!parsed) return 0;
    const xdf::File& f = *parsed;
    check_consistent(f);

    // The valid prefix is a file of its own: same streams and samples, nothing cut.
    auto prefix = xdf::parse(data, f.valid_bytes);
    check(prefix.ok());
    check(!prefix->truncated && prefix->streams.size() == f.streams.size());
    check(sample_total(*prefix) == sample_total(f));

    bool open_stream = false;
    for (const auto& s : f.streams) open_stream |= s.footer_xml.empty();
    if (!f.truncated && !open_stream) return 0;

    // tmpfs: repair's fsync costs nothing there.
    static const std::string path = "/dev/shm/fovea-fuzz-xdf-" + std::to_string(getpid()) + ".xdf";
    if (!write_all(path, data, size)) return 0;
    auto rep = xdf::repair(path);
    check(rep.ok());
    check(!rep->already_closed && rep->samples_kept == sample_total(f));
    check(rep->bytes_dropped == f.file_size - f.valid_bytes);
    auto after = xdf::read_file(path);
    check(after.ok());
    check(!after->truncated && after->streams.size() == f.streams.size());
    check(sample_total(*after) == sample_total(f));
    for (const auto& s : after->streams) check(!s.footer_xml.empty());
    auto again = xdf::repair(path);
    check(again.ok() && again->already_closed);
    ::unlink(path.c_str());
    return 0;
}
