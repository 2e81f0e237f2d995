// XDF (the Lab Streaming Layer file format, version 1.0) writer, reader and repair.
//
// File: "XDF:" then chunks. Chunk: [NumLengthBytes u8 = 1|4|8][Length (that many bytes, LE)]
// [Tag u16][content], Length counting tag + content. Tags: 1 FileHeader (XML), 2 StreamHeader
// (u32 stream id + XML), 3 Samples (u32 id, varlen sample count, per sample [TimeStampBytes u8
// 0|8][f64 stamp][values]), 4 ClockOffset (u32 id, f64 collection time, f64 offset),
// 5 Boundary (a fixed 16-byte UUID, lets readers resync after damage), 6 StreamFooter (u32 id +
// XML). All little-endian; time stamps are seconds of the host clock (CLOCK_MONOTONIC, which is
// what LSL's local_clock() reads on Linux).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "fovea/result.hpp"

namespace fovea::record::xdf {

enum class Tag : uint16_t {
    kFileHeader = 1,
    kStreamHeader = 2,
    kSamples = 3,
    kClockOffset = 4,
    kBoundary = 5,
    kStreamFooter = 6,
};

inline constexpr std::array<uint8_t, 16> kBoundaryUuid = {
    0x43, 0xA5, 0x46, 0xDC, 0xCB, 0xF5, 0x41, 0x0F, 0xB3, 0x0E, 0xD5, 0x46, 0x73, 0x83, 0xCB, 0xE4};

enum class Format { kFloat32, kDouble64, kString, kInt32, kInt16, kInt8, kInt64 };
std::string_view format_name(Format f);  // "float32", "double64", ...
int format_bytes(Format f);              // 0 for string

// What goes into a StreamHeader's <info>.
struct Channel {
    std::string label;
    std::string unit;
    std::string type;
};
struct StreamInfo {
    std::string name;
    std::string type;  // LSL content type, e.g. "Gaze"
    Format format = Format::kDouble64;
    double nominal_srate = 0.0;  // 0 = irregular
    std::string source_id;
    double created_at = 0.0;  // seconds, host clock
    std::vector<Channel> channels;
    std::string desc_extra_xml;  // more XML elements inside <desc> (already escaped)
};
std::string xml_escape(std::string_view s);
std::string stream_header_xml(const StreamInfo& info);

// Chunk encoder: appends chunks to an in-memory buffer; the owner writes buffer() out and
// clear()s it. Not thread-safe; used by one thread.
class ChunkEncoder {
public:
    void magic();
    void file_header(std::string_view extra_xml = {});
    void stream_header(uint32_t id, const StreamInfo& info);
    // `n` samples of a numeric stream with `channels` channels, values row-major as double and
    // converted to `format`; one stamp per sample (seconds).
    void samples(uint32_t id, Format format, int channels, const double* stamps,
                 const double* values, std::size_t n);
    // `n` samples of a one-channel string stream (markers): one text and one stamp each.
    void string_samples(uint32_t id, const double* stamps, const std::string* values,
                        std::size_t n);
    void clock_offset(uint32_t id, double collection_time_s, double offset_s);
    void boundary();
    void stream_footer(uint32_t id, double first_ts, double last_ts, uint64_t sample_count,
                       std::string_view extra_xml = {});

    const std::vector<uint8_t>& buffer() const { return buf_; }
    void clear() { buf_.clear(); }

private:
    void sample_count(std::size_t n);
    void begin_chunk(Tag tag);  // reserves an 8-byte length, patched in end_chunk()
    void end_chunk();
    void put(const void* p, std::size_t n);
    template <typename T>
    void put_le(T v);

    std::vector<uint8_t> buf_;
    std::size_t chunk_start_ = 0;
};

// ---- Reading -------------------------------------------------------------------------------

struct ChunkInfo {
    uint64_t offset = 0;  // of the NumLengthBytes byte
    uint64_t length = 0;  // tag + content
    uint16_t tag = 0;
};

struct Stream {
    uint32_t id = 0;
    std::string header_xml, footer_xml;
    std::string name, type;
    Format format = Format::kDouble64;
    int channel_count = 0;
    double nominal_srate = 0.0;
    std::vector<std::string> labels, units;
    std::vector<double> stamps;                            // seconds, one per sample
    std::vector<double> values;                            // numeric formats, row-major
    std::vector<std::string> string_values;                // string format, row-major
    std::vector<std::pair<double, double>> clock_offsets;  // (collection time, offset)
    std::size_t sample_count() const { return stamps.size(); }
    int channel_index(std::string_view label) const;  // -1 if absent
    double value(std::size_t sample, int channel) const {
        return values[sample * static_cast<std::size_t>(channel_count) +
                      static_cast<std::size_t>(channel)];
    }
};

struct File {
    std::string file_header_xml;
    std::vector<Stream> streams;  // in StreamHeader order
    std::vector<ChunkInfo> chunks;
    uint64_t boundaries = 0;
    uint64_t file_size = 0;
    uint64_t valid_bytes = 0;  // end of the last whole, well-formed chunk
    bool truncated = false;    // bytes after valid_bytes (partial chunk or damage)
    std::string truncation_reason;
    Stream* find(uint32_t id);
    const Stream* find(std::string_view name) const;
};

// Parse a whole file. A file cut short (crash) reads up to the last whole chunk and sets
// `truncated`; a file that is not XDF at all, or damaged before its stream headers, is an error.
Result<File> read_file(const std::string& path);
Result<File> parse(const uint8_t* data, std::size_t size);

// XML helpers for our own headers: text of the first <tag>...</tag>, and every <label>/<unit>
// under <channels>.
std::string xml_text(std::string_view xml, std::string_view tag);

// ---- Repair --------------------------------------------------------------------------------

struct RepairReport {
    uint64_t bytes_before = 0;
    uint64_t bytes_dropped = 0;  // partial last chunk / damaged tail
    int footers_added = 0;
    uint64_t samples_kept = 0;
    bool already_closed = false;  // nothing to do
};
// Close a file a crashed writer left behind, in place: cut the partial last chunk, then append
// a boundary chunk and a StreamFooter for every stream that has none.
Result<RepairReport> repair(const std::string& path);

}  // namespace fovea::record::xdf
