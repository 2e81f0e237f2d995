#include "pldata.hpp"

#include "fovea/import/pldata.hpp"

#include <algorithm>
#include <cstring>

namespace fovea::import::detail {
namespace {

// A record starts with fixarray(2) then a str header (fixstr or str8).
bool record_start(const char* p, std::size_t left) {
    if (left < 2 || static_cast<uint8_t>(p[0]) != 0x92) return false;
    const auto b = static_cast<uint8_t>(p[1]);
    return (b >= 0xa0 && b <= 0xbf) || b == 0xd9;
}

}  // namespace

PldataStream::PldataStream(std::unique_ptr<ByteSource> source) : buf_(std::move(source)) {}

void PldataStream::resync(const std::string& why) {
    ++resyncs_;
    problem_ =
        "byte " + std::to_string(buf_.consumed()) + ": " + why + "; skipped to the next record";
    std::size_t p = buf_.begin() + 1;
    for (;;) {
        const char* d = buf_.data();
        while (p + 1 < buf_.end() && !record_start(d + p, buf_.end() - p)) ++p;
        if (p + 1 < buf_.end()) {
            buf_.consume_to(p);
            return;
        }
        // No record start in the window: keep the last byte (a start may straddle the end).
        buf_.consume_to(std::min(p, buf_.end()));
        if (!buf_.fill()) {
            buf_.consume_to(buf_.end());
            return;
        }
        p = buf_.begin();
    }
}

bool PldataStream::next(std::string_view& topic, std::string_view& payload) {
    for (;;) {
        if (buf_.begin() == buf_.end() && !buf_.fill()) return false;
        std::size_t off = buf_.begin();
        std::string why;
        const auto r = msgpack_read::unpack_at(buf_.data(), buf_.end(), off, record_, &why);
        if (r == msgpack_read::Unpacked::kNeedMore) {
            if (buf_.fill()) continue;
            if (buf_.at_limit()) {
                resync("record larger than " + std::to_string(BlockBuffer::kMaxWindow >> 20) +
                       " MiB");
                continue;
            }
            truncated_ = true;
            problem_ = "byte " + std::to_string(buf_.consumed()) + ": last record cut off (" +
                       std::to_string(buf_.end() - buf_.begin()) + " bytes)";
            buf_.consume_to(buf_.end());
            return false;
        }
        if (r == msgpack_read::Unpacked::kMalformed) {
            resync("malformed msgpack (" + why + ")");
            continue;
        }
        const msgpack::object& o = record_.get();
        const auto is_bytes = [](const msgpack::object& x) {
            return x.type == msgpack::type::BIN || x.type == msgpack::type::STR;
        };
        if (o.type != msgpack::type::ARRAY || o.via.array.size != 2 ||
            o.via.array.ptr[0].type != msgpack::type::STR || !is_bytes(o.via.array.ptr[1])) {
            resync("not a [topic, datum] record");
            continue;
        }
        buf_.consume_to(off);
        const msgpack::object& t = o.via.array.ptr[0];
        const msgpack::object& b = o.via.array.ptr[1];
        topic = std::string_view(t.via.str.ptr, t.via.str.size);
        payload = b.type == msgpack::type::BIN ? std::string_view(b.via.bin.ptr, b.via.bin.size)
                                               : std::string_view(b.via.str.ptr, b.via.str.size);
        ++records_;
        return true;
    }
}

Result<std::unique_ptr<NpyDoubles>> NpyDoubles::open(const std::string& path) {
    auto src = ByteSource::file(path);
    if (!src) return src.error();
    return open(std::move(*src), path);
}

Result<std::unique_ptr<NpyDoubles>> NpyDoubles::open(std::unique_ptr<ByteSource> source,
                                                     const std::string& path) {
    std::unique_ptr<NpyDoubles> n(new NpyDoubles());
    n->source_ = std::move(source);
    char magic[10];
    if (n->source_->read(magic, 10) != 10 || std::memcmp(magic, "\x93NUMPY", 6) != 0)
        return make_error(path + ": not a .npy file");
    // Major versions 1 (2-byte header length), 2 and 3 (4-byte; 3 has a UTF-8 header).
    const auto version = static_cast<uint8_t>(magic[6]);
    if (version < 1 || version > 3)
        return make_error(path + ": unsupported .npy version " + std::to_string(version));
    std::size_t header_len = static_cast<uint8_t>(magic[8]) | static_cast<uint8_t>(magic[9]) << 8;
    if (version >= 2) {
        char more[2];
        if (n->source_->read(more, 2) != 2) return make_error(path + ": cut-off .npy header");
        header_len |= static_cast<std::size_t>(static_cast<uint8_t>(more[0])) << 16 |
                      static_cast<std::size_t>(static_cast<uint8_t>(more[1])) << 24;
    }
    if (header_len > 65536) return make_error(path + ": absurd .npy header length");
    std::string header(header_len, '\0');
    if (n->source_->read(header.data(), header_len) != header_len)
        return make_error(path + ": cut-off .npy header");
    if (header.find("'descr': '<f8'") == std::string::npos ||
        header.find("'fortran_order': False") == std::string::npos)
        return make_error(path + ": expected a little-endian float64 array ('<f8')");
    const auto shape = header.find("'shape': (");
    if (shape == std::string::npos) return make_error(path + ": .npy header has no shape");
    // "(N,)" as NumPy writes it (also "(N, )", "(N)"): digits only, one dimension; reading
    // stops at 2^60 values (no file is that long) so that the length cannot wrap.
    const char* p = header.c_str() + shape + 10;
    const auto digit = [](char c) { return c >= '0' && c <= '9'; };
    uint64_t size = 0;
    const char* first = p;
    for (; digit(*p) && size < (uint64_t{1} << 60); ++p)
        size = size * 10 + static_cast<uint64_t>(*p - '0');
    if (*p == ',') ++p;
    while (*p == ' ') ++p;
    if (!digit(*first) || *p != ')')
        return make_error(path + ": .npy array is not one-dimensional");
    n->size_ = size;
    return n;
}

bool NpyDoubles::next(double& out) {
    if (read_ >= size_) return false;
    char b[8];
    if (source_->read(b, 8) != 8) return false;
    uint64_t bits = 0;
    for (int i = 7; i >= 0; --i) bits = bits << 8 | static_cast<uint8_t>(b[i]);
    std::memcpy(&out, &bits, 8);
    ++read_;
    return true;
}

}  // namespace fovea::import::detail

namespace fovea::import {

Result<std::unique_ptr<PldataFile>> PldataFile::open(const std::string& path) {
    auto src = detail::ByteSource::file(path);
    if (!src) return src.error();
    std::unique_ptr<PldataFile> f(new PldataFile());
    f->stream_ = std::make_unique<detail::PldataStream>(std::move(*src));
    return f;
}

PldataFile::~PldataFile() = default;
bool PldataFile::next(std::string_view& topic, std::string_view& datum) {
    return stream_->next(topic, datum);
}
uint64_t PldataFile::records() const { return stream_->records(); }
uint64_t PldataFile::resyncs() const { return stream_->resyncs(); }
bool PldataFile::truncated() const { return stream_->truncated(); }

}  // namespace fovea::import
