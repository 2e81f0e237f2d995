#include <bit>
#include <cstdio>
#include <cstring>
#include <string>

#include "fovea/record/xdf.hpp"

namespace fovea::record::xdf {

static_assert(std::endian::native == std::endian::little, "XDF is little-endian; so is this code");

std::string_view format_name(Format f) {
    switch (f) {
        case Format::kFloat32: return "float32";
        case Format::kDouble64: return "double64";
        case Format::kString: return "string";
        case Format::kInt32: return "int32";
        case Format::kInt16: return "int16";
        case Format::kInt8: return "int8";
        case Format::kInt64: return "int64";
    }
    return "double64";
}

int format_bytes(Format f) {
    switch (f) {
        case Format::kFloat32: return 4;
        case Format::kDouble64: return 8;
        case Format::kString: return 0;
        case Format::kInt32: return 4;
        case Format::kInt16: return 2;
        case Format::kInt8: return 1;
        case Format::kInt64: return 8;
    }
    return 8;
}

std::string xml_escape(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        switch (c) {
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '&': out += "&amp;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            default: out += c;
        }
    }
    return out;
}

namespace {
std::string num(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}
}  // namespace

std::string stream_header_xml(const StreamInfo& info) {
    std::string x = "<?xml version=\"1.0\"?>\n<info>\n";
    x += "  <name>" + xml_escape(info.name) + "</name>\n";
    x += "  <type>" + xml_escape(info.type) + "</type>\n";
    x += "  <channel_count>" + std::to_string(info.channels.size()) + "</channel_count>\n";
    x += "  <nominal_srate>" + num(info.nominal_srate) + "</nominal_srate>\n";
    x += "  <channel_format>" + std::string(format_name(info.format)) + "</channel_format>\n";
    x += "  <source_id>" + xml_escape(info.source_id) + "</source_id>\n";
    x += "  <version>1.1000000000000001</version>\n";
    x += "  <created_at>" + num(info.created_at) + "</created_at>\n";
    x += "  <desc>\n    <channels>\n";
    for (const auto& c : info.channels) {
        x += "      <channel><label>" + xml_escape(c.label) + "</label><unit>" +
             xml_escape(c.unit) + "</unit><type>" + xml_escape(c.type) + "</type></channel>\n";
    }
    x += "    </channels>\n";
    x += info.desc_extra_xml;
    x += "  </desc>\n</info>\n";
    return x;
}

void ChunkEncoder::put(const void* p, std::size_t n) {
    const auto* b = static_cast<const uint8_t*>(p);
    buf_.insert(buf_.end(), b, b + n);
}

template <typename T>
void ChunkEncoder::put_le(T v) {
    put(&v, sizeof v);  // little-endian host (static_assert above)
}

void ChunkEncoder::magic() { put("XDF:", 4); }

void ChunkEncoder::begin_chunk(Tag tag) {
    chunk_start_ = buf_.size();
    buf_.resize(buf_.size() + 9);  // worst case: 1 + 8 length bytes, shrunk in end_chunk()
    put_le(static_cast<uint16_t>(tag));
}

void ChunkEncoder::end_chunk() {
    const std::size_t body = chunk_start_ + 9;
    const uint64_t len = buf_.size() - body;  // tag + content
    uint8_t nbytes = len <= 0xFF ? 1 : len <= 0xFFFFFFFFull ? 4 : 8;
    uint8_t* p = buf_.data() + chunk_start_;
    p[0] = nbytes;
    std::memcpy(p + 1, &len, nbytes);  // the low bytes of a little-endian u64
    const std::size_t slack = 8 - nbytes;
    if (slack != 0) {
        std::memmove(p + 1 + nbytes, p + 9, len);
        buf_.resize(buf_.size() - slack);
    }
}

void ChunkEncoder::file_header(std::string_view extra_xml) {
    begin_chunk(Tag::kFileHeader);
    std::string x = "<?xml version=\"1.0\"?>\n<info>\n  <version>1.0</version>\n";
    x += extra_xml;
    x += "</info>\n";
    put(x.data(), x.size());
    end_chunk();
}

void ChunkEncoder::stream_header(uint32_t id, const StreamInfo& info) {
    begin_chunk(Tag::kStreamHeader);
    put_le(id);
    const std::string x = stream_header_xml(info);
    put(x.data(), x.size());
    end_chunk();
}

void ChunkEncoder::sample_count(std::size_t n) {
    // varlen, same 1/4/8 scheme as chunk lengths
    if (n <= 0xFF) {
        put_le(uint8_t{1});
        put_le(static_cast<uint8_t>(n));
    } else if (n <= 0xFFFFFFFFull) {
        put_le(uint8_t{4});
        put_le(static_cast<uint32_t>(n));
    } else {
        put_le(uint8_t{8});
        put_le(static_cast<uint64_t>(n));
    }
}

void ChunkEncoder::string_samples(uint32_t id, const double* stamps, const std::string* values,
                                  std::size_t n) {
    begin_chunk(Tag::kSamples);
    put_le(id);
    sample_count(n);
    for (std::size_t i = 0; i < n; ++i) {
        put_le(uint8_t{8});
        put_le(stamps[i]);
        put_le(uint8_t{4});
        put_le(static_cast<uint32_t>(values[i].size()));
        put(values[i].data(), values[i].size());
    }
    end_chunk();
}

void ChunkEncoder::samples(uint32_t id, Format format, int channels, const double* stamps,
                           const double* values, std::size_t n) {
    begin_chunk(Tag::kSamples);
    put_le(id);
    sample_count(n);
    const std::size_t row = static_cast<std::size_t>(channels);
    buf_.reserve(buf_.size() + n * (9 + row * static_cast<std::size_t>(format_bytes(format))));
    for (std::size_t i = 0; i < n; ++i) {
        put_le(uint8_t{8});
        put_le(stamps[i]);
        const double* v = values + i * row;
        for (std::size_t c = 0; c < row; ++c) {
            switch (format) {
                case Format::kDouble64: put_le(v[c]); break;
                case Format::kFloat32: put_le(static_cast<float>(v[c])); break;
                case Format::kInt64: put_le(static_cast<int64_t>(v[c])); break;
                case Format::kInt32: put_le(static_cast<int32_t>(v[c])); break;
                case Format::kInt16: put_le(static_cast<int16_t>(v[c])); break;
                case Format::kInt8: put_le(static_cast<int8_t>(v[c])); break;
                case Format::kString: {
                    // numbers as text: varlen length + bytes
                    const std::string s = num(v[c]);
                    put_le(uint8_t{4});
                    put_le(static_cast<uint32_t>(s.size()));
                    put(s.data(), s.size());
                    break;
                }
            }
        }
    }
    end_chunk();
}

void ChunkEncoder::clock_offset(uint32_t id, double collection_time_s, double offset_s) {
    begin_chunk(Tag::kClockOffset);
    put_le(id);
    put_le(collection_time_s);
    put_le(offset_s);
    end_chunk();
}

void ChunkEncoder::boundary() {
    begin_chunk(Tag::kBoundary);
    put(kBoundaryUuid.data(), kBoundaryUuid.size());
    end_chunk();
}

void ChunkEncoder::stream_footer(uint32_t id, double first_ts, double last_ts,
                                 uint64_t sample_count, std::string_view extra_xml) {
    begin_chunk(Tag::kStreamFooter);
    put_le(id);
    std::string x = "<?xml version=\"1.0\"?>\n<info>\n";
    x += "  <writer>fovea</writer>\n";
    x += "  <first_timestamp>" + num(first_ts) + "</first_timestamp>\n";
    x += "  <last_timestamp>" + num(last_ts) + "</last_timestamp>\n";
    x += "  <sample_count>" + std::to_string(sample_count) + "</sample_count>\n";
    x += extra_xml;
    x += "</info>\n";
    put(x.data(), x.size());
    end_chunk();
}

}  // namespace fovea::record::xdf
