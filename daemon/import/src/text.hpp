// Line-by-line reading in constant memory and the field parsing every text importer shares.
#pragma once

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fovea/result.hpp"

namespace fovea::import::detail {

// Bytes of a file or of memory, read in blocks. One thread.
class ByteSource {
public:
    static Result<std::unique_ptr<ByteSource>> file(const std::string& path);
    static std::unique_ptr<ByteSource> memory(std::string_view data);
    ~ByteSource();
    ByteSource(const ByteSource&) = delete;
    ByteSource& operator=(const ByteSource&) = delete;

    // Up to `n` bytes into `out`; 0 at the end or on error (error() then says which).
    std::size_t read(char* out, std::size_t n);
    // The whole input, when it is bytes in memory (readers then parse it in place).
    std::optional<std::string_view> memory_view() const {
        if (file_) return std::nullopt;
        return memory_;
    }
    const std::string& error() const { return error_; }

private:
    ByteSource() = default;
    std::FILE* file_ = nullptr;
    std::string_view memory_;
    std::size_t memory_pos_ = 0;
    std::string error_;
};

// A window [begin, end) over the input that refills in blocks, keeping the unconsumed tail.
// Bytes in memory are used in place. One thread.
class BlockBuffer {
public:
    explicit BlockBuffer(std::unique_ptr<ByteSource> source);
    const char* data() const { return data_; }
    std::size_t begin() const { return begin_; }
    std::size_t end() const { return end_; }
    // Everything before `pos` is done with.
    void consume_to(std::size_t pos) {
        consumed_ += pos - begin_;
        begin_ = pos;
    }
    // More bytes after end(); false at the end of the input or when the unconsumed tail is
    // already the most a buffer may hold (kMaxWindow). Moves the window: data() changes.
    bool fill();
    bool at_limit() const { return end_ - begin_ >= kMaxWindow; }
    uint64_t consumed() const { return consumed_; }
    const std::string& error() const { return source_->error(); }

    static constexpr std::size_t kMaxWindow = 64u << 20;

private:
    std::unique_ptr<ByteSource> source_;
    std::unique_ptr<char[]> buf_;  // not zero-filled: only [begin_, end_) is ever read
    const char* data_ = nullptr;   // buf_, or the caller's bytes for a memory source
    std::size_t capacity_ = 0, begin_ = 0, end_ = 0;
    uint64_t consumed_ = 0;
    bool eof_ = false;
};

// Lines without their terminator (\n or \r\n).
class LineReader {
public:
    explicit LineReader(std::unique_ptr<ByteSource> source) : buf_(std::move(source)) {}
    // False at the end of the input. `line` stays valid until the next call.
    bool next(std::string_view& line);
    uint64_t line_number() const { return line_no_; }
    uint64_t bytes() const { return buf_.consumed(); }
    // The line last returned had no terminator: the input ended inside it.
    bool unterminated() const { return unterminated_; }
    const std::string& error() const { return buf_.error(); }

private:
    BlockBuffer buf_;
    uint64_t line_no_ = 0;
    bool unterminated_ = false;
};

inline std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r'))
        s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
        s.remove_suffix(1);
    return s;
}

// `line` cut at every `sep` into `out` (reused, so no allocation per line once warm).
inline void split(std::string_view line, char sep, std::vector<std::string_view>& out) {
    out.clear();
    std::size_t start = 0;
    for (;;) {
        const std::size_t p = line.find(sep, start);
        if (p == std::string_view::npos) {
            out.push_back(line.substr(start));
            return;
        }
        out.push_back(line.substr(start, p - start));
        start = p + 1;
    }
}

// `line` cut at runs of blanks (spaces and tabs).
inline void split_blanks(std::string_view line, std::vector<std::string_view>& out) {
    out.clear();
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        const std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
}

// A whole field as a double: blanks around it allowed, "nan"/"inf" accepted, junk rejected.
inline bool parse_double(std::string_view s, double& out) {
    s = trim(s);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    if (s.empty()) return false;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

inline bool parse_int(std::string_view s, int64_t& out) {
    s = trim(s);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    if (s.empty()) return false;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// Index of `name` in `columns` (trimmed, exact), or -1.
int column_index(const std::vector<std::string>& columns, std::string_view name);

using fovea::printable;  // text fit for one issue line

}  // namespace fovea::import::detail
