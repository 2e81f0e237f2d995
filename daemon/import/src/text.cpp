#include "text.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace fovea::import::detail {
namespace {

constexpr std::size_t kBlock = 256 << 10;  // read size; the buffer's usual size

}  // namespace

Result<std::unique_ptr<ByteSource>> ByteSource::file(const std::string& path) {
    std::unique_ptr<ByteSource> s(new ByteSource());
    s->file_ = std::fopen(path.c_str(), "rb");
    if (!s->file_) return make_error("cannot open " + path + ": " + std::strerror(errno), errno);
    return s;
}

std::unique_ptr<ByteSource> ByteSource::memory(std::string_view data) {
    std::unique_ptr<ByteSource> s(new ByteSource());
    s->memory_ = data;
    return s;
}

ByteSource::~ByteSource() {
    if (file_) std::fclose(file_);
}

std::size_t ByteSource::read(char* out, std::size_t n) {
    if (!file_) {
        const std::size_t k = std::min(n, memory_.size() - memory_pos_);
        std::memcpy(out, memory_.data() + memory_pos_, k);
        memory_pos_ += k;
        return k;
    }
    const std::size_t k = std::fread(out, 1, n, file_);
    if (k == 0 && std::ferror(file_)) error_ = std::string("read error: ") + std::strerror(errno);
    return k;
}

BlockBuffer::BlockBuffer(std::unique_ptr<ByteSource> source) : source_(std::move(source)) {
    if (const auto view = source_->memory_view()) {
        data_ = view->data();
        end_ = view->size();
        eof_ = true;
        return;
    }
    buf_.reset(new char[kBlock]);
    capacity_ = kBlock;
    data_ = buf_.get();
}

bool BlockBuffer::fill() {
    if (eof_ || at_limit()) return false;
    if (begin_ > 0) {  // keep the unconsumed tail at the front
        std::memmove(buf_.get(), data_ + begin_, end_ - begin_);
        end_ -= begin_;
        begin_ = 0;
    }
    if (end_ == capacity_) {
        std::unique_ptr<char[]> bigger(new char[capacity_ * 2]);
        std::memcpy(bigger.get(), buf_.get(), end_);
        buf_ = std::move(bigger);
        data_ = buf_.get();
        capacity_ *= 2;
    }
    const std::size_t n = source_->read(buf_.get() + end_, capacity_ - end_);
    if (n == 0) {
        eof_ = true;
        return false;
    }
    end_ += n;
    return true;
}

bool LineReader::next(std::string_view& line) {
    std::size_t scanned = buf_.begin();
    for (;;) {
        const char* d = buf_.data();
        const void* nl = std::memchr(d + scanned, '\n', buf_.end() - scanned);
        if (nl) {
            const std::size_t pos = static_cast<const char*>(nl) - d;
            std::size_t stop = pos;
            if (stop > buf_.begin() && d[stop - 1] == '\r') --stop;
            line = std::string_view(d + buf_.begin(), stop - buf_.begin());
            buf_.consume_to(pos + 1);
            ++line_no_;
            unterminated_ = false;
            return true;
        }
        const std::size_t have = buf_.end() - buf_.begin();
        if (!buf_.fill()) {
            if (buf_.end() == buf_.begin()) return false;
            // The input ended inside a line (or the line outgrew the buffer): hand it out whole.
            line = std::string_view(buf_.data() + buf_.begin(), buf_.end() - buf_.begin());
            buf_.consume_to(buf_.end());
            ++line_no_;
            unterminated_ = true;
            return true;
        }
        scanned = buf_.begin() + have;
    }
}

int column_index(const std::vector<std::string>& columns, std::string_view name) {
    for (std::size_t i = 0; i < columns.size(); ++i)
        if (columns[i] == name) return static_cast<int>(i);
    return -1;
}

}  // namespace fovea::import::detail
