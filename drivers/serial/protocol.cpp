#include "serial/protocol.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>

namespace fovea::drivers::serial {
namespace {

constexpr std::size_t kHelloFixed = 17;  // up to and including name_len
constexpr std::size_t kSampleSize = 29;
constexpr std::size_t kConfigureSize = 8;
constexpr std::size_t kMaxName = 48;

constexpr std::array<uint32_t, 256> make_crc_table() {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
        uint32_t c = i;
        for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        t[i] = c;
    }
    return t;
}
constexpr auto kCrcTable = make_crc_table();

void put_u16(std::vector<uint8_t>& v, uint16_t x) {
    v.push_back(static_cast<uint8_t>(x));
    v.push_back(static_cast<uint8_t>(x >> 8));
}
void put_u32(std::vector<uint8_t>& v, uint32_t x) {
    for (int i = 0; i < 4; ++i) v.push_back(static_cast<uint8_t>(x >> (8 * i)));
}
void put_u64(std::vector<uint8_t>& v, uint64_t x) {
    for (int i = 0; i < 8; ++i) v.push_back(static_cast<uint8_t>(x >> (8 * i)));
}
void put_f32(std::vector<uint8_t>& v, float f) { put_u32(v, std::bit_cast<uint32_t>(f)); }

uint16_t get_u16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t get_u32(const uint8_t* p) {
    return uint32_t{p[0]} | (uint32_t{p[1]} << 8) | (uint32_t{p[2]} << 16) | (uint32_t{p[3]} << 24);
}
uint64_t get_u64(const uint8_t* p) {
    return uint64_t{get_u32(p)} | (uint64_t{get_u32(p + 4)} << 32);
}
float get_f32(const uint8_t* p) { return std::bit_cast<float>(get_u32(p)); }

// Appends COBS(in) (no delimiter). Frames are <= 255 bytes, so at most 2 overhead bytes.
void cobs_encode(std::span<const uint8_t> in, std::vector<uint8_t>& out) {
    std::size_t code_pos = out.size();
    out.push_back(0);
    uint8_t code = 1;
    for (const uint8_t b : in) {
        if (b == 0) {
            out[code_pos] = code;
            code_pos = out.size();
            out.push_back(0);
            code = 1;
            continue;
        }
        out.push_back(b);
        if (++code == 0xFF) {
            out[code_pos] = code;
            code_pos = out.size();
            out.push_back(0);
            code = 1;
        }
    }
    out[code_pos] = code;
}

// Decodes COBS; returns the decoded length or -1 on a malformed block.
long cobs_decode(std::span<const uint8_t> in, uint8_t* out, std::size_t out_cap) {
    std::size_t i = 0, n = 0;
    while (i < in.size()) {
        const uint8_t code = in[i++];
        if (code == 0 || i + code - 1 > in.size()) return -1;
        for (int k = 1; k < code; ++k) {
            if (n >= out_cap) return -1;
            out[n++] = in[i++];
        }
        if (code != 0xFF && i < in.size()) {
            if (n >= out_cap) return -1;
            out[n++] = 0;
        }
    }
    return static_cast<long>(n);
}

bool plausible_eye(double x, double y, double pupil_mm) {
    // Normalized coordinates may leave the display a little; beyond that the value is broken.
    return std::isfinite(x) && std::isfinite(y) && x > -1.0 && x < 2.0 && y > -1.0 && y < 2.0 &&
           (pupil_mm == 0.0 || (pupil_mm >= 0.5 && pupil_mm <= 12.0));
}

}  // namespace

uint32_t crc32(std::span<const uint8_t> data, uint32_t crc) {
    crc = ~crc;
    for (const uint8_t b : data) crc = kCrcTable[(crc ^ b) & 0xFF] ^ (crc >> 8);
    return ~crc;
}

void encode_frame(FrameType type, uint16_t seq, std::span<const uint8_t> payload,
                  std::vector<uint8_t>& out) {
    uint8_t buf[kMaxFrameSize];
    const std::size_t n = kHeaderSize + payload.size();
    assert(n + kCrcSize <= kMaxFrameSize);
    if (n + kCrcSize > kMaxFrameSize) return;
    buf[0] = kProtocolVersion;
    buf[1] = static_cast<uint8_t>(type);
    buf[2] = static_cast<uint8_t>(seq);
    buf[3] = static_cast<uint8_t>(seq >> 8);
    if (!payload.empty()) std::memcpy(buf + kHeaderSize, payload.data(), payload.size());
    const uint32_t crc = crc32({buf, n});
    for (int i = 0; i < 4; ++i) buf[n + i] = static_cast<uint8_t>(crc >> (8 * i));
    // A leading delimiter too: line noise before a frame then costs only the noise.
    out.push_back(0);
    cobs_encode({buf, n + kCrcSize}, out);
    out.push_back(0);
}

void encode_hello(const Hello& h, uint16_t seq, std::vector<uint8_t>& out) {
    std::vector<uint8_t> p;
    p.push_back(h.protocol_version);
    p.push_back(static_cast<uint8_t>((h.binocular ? 1 : 0) | (h.has_pupil ? 2 : 0)));
    p.push_back(h.counter_bits);
    p.push_back(0);
    put_u32(p, h.tick_hz);
    put_u32(p, h.rate_mhz);
    put_u32(p, h.baud);
    const std::size_t len = std::min(h.name.size(), kMaxName);
    p.push_back(static_cast<uint8_t>(len));
    p.insert(p.end(), h.name.begin(), h.name.begin() + static_cast<long>(len));
    encode_frame(FrameType::kHello, seq, p, out);
}

void encode_sample(const gaze::RawSample& raw, uint16_t seq, std::vector<uint8_t>& out) {
    std::vector<uint8_t> p;
    p.reserve(kSampleSize);
    put_u64(p, raw.device_ticks);
    p.push_back(static_cast<uint8_t>((raw.left.valid ? 1 : 0) | (raw.right.valid ? 2 : 0)));
    for (const gaze::EyeSample* e : {&raw.left, &raw.right}) {
        put_f32(p, e->valid ? static_cast<float>(e->x) : NAN);
        put_f32(p, e->valid ? static_cast<float>(e->y) : NAN);
        const double um = std::clamp(e->pupil_mm * 1000.0, 0.0, 65535.0);
        put_u16(p, e->valid ? static_cast<uint16_t>(std::lround(um)) : 0);
    }
    encode_frame(FrameType::kSample, seq, p, out);
}

void encode_configure(const Configure& c, uint16_t seq, std::vector<uint8_t>& out) {
    std::vector<uint8_t> p;
    put_u32(p, c.rate_mhz);
    put_u32(p, c.baud);
    encode_frame(FrameType::kConfigure, seq, p, out);
}

void encode_hello_request(uint16_t seq, std::vector<uint8_t>& out) {
    encode_frame(FrameType::kHelloRequest, seq, {}, out);
}

std::optional<Hello> decode_hello(std::span<const uint8_t> p, std::string* why) {
    if (p.size() < kHelloFixed || p.size() < kHelloFixed + p[16]) {
        if (why) *why = "hello frame too short";
        return std::nullopt;
    }
    Hello h;
    h.protocol_version = p[0];
    h.binocular = p[1] & 1;
    h.has_pupil = p[1] & 2;
    h.counter_bits = p[2];
    h.tick_hz = get_u32(&p[4]);
    h.rate_mhz = get_u32(&p[8]);
    h.baud = get_u32(&p[12]);
    h.name.assign(reinterpret_cast<const char*>(&p[kHelloFixed]),
                  std::min<std::size_t>(p[16], kMaxName));
    if (h.counter_bits != 16 && h.counter_bits != 32 && h.counter_bits != 64) {
        if (why) *why = "hello: counter_bits must be 16, 32 or 64";
        return std::nullopt;
    }
    if (h.tick_hz == 0 || h.rate_mhz < 1'000 || h.rate_mhz > 10'000'000) {
        if (why) *why = "hello: tick_hz must be > 0 and rate within 1..10000 Hz";
        return std::nullopt;
    }
    return h;
}

std::optional<gaze::RawSample> decode_sample(std::span<const uint8_t> p, std::string* why) {
    if (p.size() < kSampleSize) {
        if (why) *why = "sample frame too short";
        return std::nullopt;
    }
    gaze::RawSample s;
    s.device_ticks = get_u64(&p[0]);
    const uint8_t flags = p[8];
    gaze::EyeSample* eyes[2] = {&s.left, &s.right};
    for (int e = 0; e < 2; ++e) {
        const uint8_t* q = &p[9 + 10 * e];
        if (!(flags & (1 << e))) continue;  // invalid eye: default NaN, not valid
        const double x = get_f32(q), y = get_f32(q + 4), pupil = get_u16(q + 8) / 1000.0;
        if (!plausible_eye(x, y, pupil)) {
            if (why) *why = "sample: absurd gaze or pupil value";
            return std::nullopt;
        }
        *eyes[e] = {x, y, pupil, true};
    }
    return s;
}

std::optional<Configure> decode_configure(std::span<const uint8_t> p) {
    if (p.size() < kConfigureSize) return std::nullopt;
    return Configure{get_u32(&p[0]), get_u32(&p[4])};
}

void FrameDecoder::reset() {
    if (!encoded_.empty() || overflow_ != 0) {
        ++stats_.dropped;
        stats_.garbage_bytes += encoded_.size() + overflow_;
    }
    encoded_.clear();
    overflow_ = 0;
}

FrameDecoder::Reject FrameDecoder::finish_chunk(Frame& frame) {
    const std::size_t chunk = encoded_.size() + overflow_;
    Reject r = Reject::kNone;
    long n = 0;
    if (chunk == 0) {
        frame.type = 0;  // idle delimiter
        return Reject::kNone;
    }
    if (overflow_ != 0) {
        r = Reject::kOversize;
    } else if ((n = cobs_decode(encoded_, decoded_.data(), decoded_.size())) < 0) {
        r = Reject::kCobs;
    } else if (static_cast<std::size_t>(n) < kHeaderSize + kCrcSize ||
               static_cast<std::size_t>(n) > kMaxFrameSize) {
        r = Reject::kShort;
    } else {
        const auto len = static_cast<std::size_t>(n);
        const uint32_t want = get_u32(&decoded_[len - kCrcSize]);
        if (crc32({decoded_.data(), len - kCrcSize}) != want) {
            r = Reject::kCrc;
        } else if (decoded_[0] != kProtocolVersion) {
            r = Reject::kVersion;
        } else if (decoded_[1] == 0) {
            r = Reject::kVersion;  // type 0 is reserved (it marks an idle delimiter)
        } else {
            frame.type = decoded_[1];
            frame.seq = get_u16(&decoded_[2]);
            frame.payload = {decoded_.data() + kHeaderSize, len - kHeaderSize - kCrcSize};
        }
    }
    encoded_.clear();
    overflow_ = 0;
    if (r == Reject::kNone) {
        ++stats_.frames;
        in_sync_ = true;
        return r;
    }
    ++stats_.dropped;
    stats_.garbage_bytes += chunk;
    if (in_sync_) ++stats_.resyncs;
    in_sync_ = false;
    return r;
}

uint32_t SequenceTracker::on_seq(uint16_t seq) {
    uint32_t missing = 0;
    if (have_) {
        const auto gap = static_cast<uint16_t>(seq - expected_);
        // A jump backwards or by more than half the range is a device restart, not a loss.
        if (gap < 0x8000) missing = gap;
    }
    have_ = true;
    expected_ = static_cast<uint16_t>(seq + 1);
    return missing;
}

const char* to_string(FrameDecoder::Reject r) {
    switch (r) {
        case FrameDecoder::Reject::kNone: return "none";
        case FrameDecoder::Reject::kOversize: return "oversized frame";
        case FrameDecoder::Reject::kCobs: return "bad COBS encoding";
        case FrameDecoder::Reject::kShort: return "frame too short";
        case FrameDecoder::Reject::kCrc: return "CRC mismatch";
        case FrameDecoder::Reject::kVersion: return "unsupported frame version";
    }
    return "?";
}

}  // namespace fovea::drivers::serial
