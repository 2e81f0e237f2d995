#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>

#include "fovea/record/xdf.hpp"

namespace fovea::record::xdf {

namespace {

// Bounds-checked little-endian cursor over one chunk or the whole file.
struct Cursor {
    const uint8_t* p;
    std::size_t n;
    std::size_t pos = 0;
    bool ok = true;

    template <typename T>
    T get() {
        T v{};
        if (pos + sizeof v > n) {
            ok = false;
            pos = n;
            return v;
        }
        std::memcpy(&v, p + pos, sizeof v);
        pos += sizeof v;
        return v;
    }
    bool varlen(uint64_t& out) {
        const uint8_t nb = get<uint8_t>();
        if (!ok) return false;
        if (nb == 1) {
            out = get<uint8_t>();
        } else if (nb == 4) {
            out = get<uint32_t>();
        } else if (nb == 8) {
            out = get<uint64_t>();
        } else {
            ok = false;
            return false;
        }
        return ok;
    }
    std::string_view rest() const { return {reinterpret_cast<const char*>(p + pos), n - pos}; }
};

std::optional<Format> parse_format(std::string_view s) {
    for (Format f : {Format::kFloat32, Format::kDouble64, Format::kString, Format::kInt32,
                     Format::kInt16, Format::kInt8, Format::kInt64}) {
        if (format_name(f) == s) return f;
    }
    return std::nullopt;
}

std::string xml_unescape(std::string_view s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] != '&') {
            out += s[i];
            continue;
        }
        static constexpr std::pair<std::string_view, char> kEntities[] = {
            {"&lt;", '<'}, {"&gt;", '>'}, {"&amp;", '&'}, {"&quot;", '"'}, {"&apos;", '\''}};
        bool matched = false;
        for (const auto& [e, c] : kEntities) {
            if (s.substr(i, e.size()) == e) {
                out += c;
                i += e.size() - 1;
                matched = true;
                break;
            }
        }
        if (!matched) out += '&';
    }
    return out;
}

// Every <tag>text</tag> inside `xml`, in order.
std::vector<std::string> xml_all(std::string_view xml, std::string_view tag) {
    std::vector<std::string> out;
    const std::string open = "<" + std::string(tag) + ">";
    const std::string close = "</" + std::string(tag) + ">";
    const std::string empty = "<" + std::string(tag) + "/>";
    std::size_t pos = 0;
    for (;;) {
        const std::size_t a = xml.find(open, pos);
        const std::size_t e = xml.find(empty, pos);
        if (e != std::string_view::npos && (a == std::string_view::npos || e < a)) {
            out.emplace_back();
            pos = e + empty.size();
            continue;
        }
        if (a == std::string_view::npos) break;
        const std::size_t b = xml.find(close, a + open.size());
        if (b == std::string_view::npos) break;
        out.push_back(xml_unescape(xml.substr(a + open.size(), b - a - open.size())));
        pos = b + close.size();
    }
    return out;
}

Result<void> parse_stream_header(Stream& s, std::string_view xml) {
    s.header_xml = std::string(xml);
    s.name = xml_text(xml, "name");
    s.type = xml_text(xml, "type");
    const std::string cc = xml_text(xml, "channel_count");
    const std::string fmt = xml_text(xml, "channel_format");
    const auto f = parse_format(fmt);
    if (!f)
        return make_error("stream " + std::to_string(s.id) + ": unknown channel_format '" + fmt +
                          "'");
    s.format = *f;
    char* end = nullptr;
    const long n = std::strtol(cc.c_str(), &end, 10);
    if (cc.empty() || *end != '\0' || n <= 0 || n > 65535) {
        return make_error("stream " + std::to_string(s.id) + ": bad channel_count '" + cc + "'");
    }
    s.channel_count = static_cast<int>(n);
    s.nominal_srate = std::strtod(xml_text(xml, "nominal_srate").c_str(), nullptr);
    const std::size_t ch = xml.find("<channels>");
    if (ch != std::string_view::npos) {
        const std::string_view sub = xml.substr(ch);
        for (const auto& c : xml_all(sub.substr(0, sub.find("</channels>")), "channel")) {
            s.labels.push_back(xml_text(c, "label"));
            s.units.push_back(xml_text(c, "unit"));
        }
    }
    return {};
}

// Samples chunk content (after the stream id) into s; false if malformed.
bool parse_samples(Stream& s, Cursor& c) {
    uint64_t n = 0;
    if (!c.varlen(n)) return false;
    const std::size_t row = static_cast<std::size_t>(s.channel_count);
    const std::size_t vb = static_cast<std::size_t>(format_bytes(s.format));
    if (s.format != Format::kString && n > (c.n - c.pos) / (1 + row * vb)) return false;
    const double tdiff = s.nominal_srate > 0 ? 1.0 / s.nominal_srate : 0.0;
    for (uint64_t i = 0; i < n; ++i) {
        const uint8_t tsb = c.get<uint8_t>();
        double ts = 0;
        if (tsb == 8) {
            ts = c.get<double>();
        } else if (tsb == 0) {
            ts = (s.stamps.empty() ? 0.0 : s.stamps.back()) + tdiff;  // deduced, as pyxdf does
        } else {
            return false;
        }
        if (!c.ok) return false;
        s.stamps.push_back(ts);
        for (std::size_t k = 0; k < row; ++k) {
            switch (s.format) {
                case Format::kDouble64: s.values.push_back(c.get<double>()); break;
                case Format::kFloat32: s.values.push_back(c.get<float>()); break;
                case Format::kInt64:
                    s.values.push_back(static_cast<double>(c.get<int64_t>()));
                    break;
                case Format::kInt32: s.values.push_back(c.get<int32_t>()); break;
                case Format::kInt16: s.values.push_back(c.get<int16_t>()); break;
                case Format::kInt8: s.values.push_back(c.get<int8_t>()); break;
                case Format::kString: {
                    uint64_t len = 0;
                    if (!c.varlen(len) || len > c.n - c.pos) return false;
                    s.string_values.emplace_back(reinterpret_cast<const char*>(c.p + c.pos), len);
                    c.pos += len;
                    break;
                }
            }
        }
        if (!c.ok) return false;
    }
    return true;
}

}  // namespace

std::string xml_text(std::string_view xml, std::string_view tag) {
    const std::string open = "<" + std::string(tag) + ">";
    const std::size_t a = xml.find(open);
    if (a == std::string_view::npos) return {};
    const std::size_t b = xml.find("</" + std::string(tag) + ">", a);
    if (b == std::string_view::npos) return {};
    return xml_unescape(xml.substr(a + open.size(), b - a - open.size()));
}

int Stream::channel_index(std::string_view label) const {
    for (std::size_t i = 0; i < labels.size(); ++i) {
        if (labels[i] == label) return static_cast<int>(i);
    }
    return -1;
}

Stream* File::find(uint32_t id) {
    for (auto& s : streams) {
        if (s.id == id) return &s;
    }
    return nullptr;
}

const Stream* File::find(std::string_view name) const {
    for (const auto& s : streams) {
        if (s.name == name) return &s;
    }
    return nullptr;
}

Result<File> parse(const uint8_t* data, std::size_t size) {
    File f;
    f.file_size = size;
    if (size < 4 || std::memcmp(data, "XDF:", 4) != 0) {
        return make_error("not an XDF file (no \"XDF:\" magic)");
    }
    std::size_t pos = 4;
    f.valid_bytes = 4;
    bool have_file_header = false;
    auto stop = [&](std::string why) {
        f.truncated = true;
        f.truncation_reason = std::move(why);
    };
    while (pos < size) {
        Cursor head{data + pos, size - pos};
        uint64_t len = 0;
        if (!head.varlen(len)) {
            stop(head.ok ? "bad chunk length prefix" : "partial chunk header");
            break;
        }
        if (len < 2 || len > size - pos - head.pos) {
            stop(len < 2 ? "chunk length < 2" : "partial last chunk (file cut short)");
            break;
        }
        const uint16_t tag = head.get<uint16_t>();
        Cursor c{data + pos + head.pos, static_cast<std::size_t>(len - 2)};
        const ChunkInfo info{pos, len, tag};
        bool good = true;
        switch (static_cast<Tag>(tag)) {
            case Tag::kFileHeader:
                f.file_header_xml.assign(c.rest());
                have_file_header = true;
                break;
            case Tag::kStreamHeader: {
                Stream s;
                s.id = c.get<uint32_t>();
                if (!c.ok) {
                    good = false;
                    break;
                }
                if (f.find(s.id))
                    return make_error("duplicate stream header " + std::to_string(s.id));
                if (auto r = parse_stream_header(s, c.rest()); !r) return r.error();
                f.streams.push_back(std::move(s));
                break;
            }
            case Tag::kSamples: {
                const uint32_t id = c.get<uint32_t>();
                Stream* s = c.ok ? f.find(id) : nullptr;
                if (!s) {
                    good = false;
                    break;
                }
                const std::size_t keep_s = s->stamps.size(), keep_v = s->values.size(),
                                  keep_str = s->string_values.size();
                if (!parse_samples(*s, c) || c.pos != c.n) {
                    s->stamps.resize(keep_s);
                    s->values.resize(keep_v);
                    s->string_values.resize(keep_str);
                    good = false;
                }
                break;
            }
            case Tag::kClockOffset: {
                const uint32_t id = c.get<uint32_t>();
                const double t = c.get<double>(), o = c.get<double>();
                Stream* s = c.ok ? f.find(id) : nullptr;
                if (!s) {
                    good = false;
                    break;
                }
                s->clock_offsets.emplace_back(t, o);
                break;
            }
            case Tag::kBoundary:
                if (c.n != kBoundaryUuid.size() ||
                    std::memcmp(c.p, kBoundaryUuid.data(), kBoundaryUuid.size()) != 0) {
                    good = false;
                }
                ++f.boundaries;
                break;
            case Tag::kStreamFooter: {
                const uint32_t id = c.get<uint32_t>();
                Stream* s = c.ok ? f.find(id) : nullptr;
                if (!s) {
                    good = false;
                    break;
                }
                s->footer_xml.assign(c.rest());
                break;
            }
            default: break;  // unknown tags are skipped, as the spec asks
        }
        if (!good) {
            stop("malformed chunk (tag " + std::to_string(tag) + ") at byte " +
                 std::to_string(pos));
            break;
        }
        f.chunks.push_back(info);
        pos += head.pos + static_cast<std::size_t>(len - 2);
        f.valid_bytes = pos;
    }
    if (!have_file_header) return make_error("XDF file has no FileHeader chunk");
    return f;
}

Result<File> read_file(const std::string& path) {
    std::FILE* fp = std::fopen(path.c_str(), "rb");
    if (!fp) return make_error("cannot open " + path + ": " + std::strerror(errno), errno);
    std::vector<uint8_t> data;
    uint8_t buf[1 << 16];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, fp)) > 0) data.insert(data.end(), buf, buf + n);
    const bool err = std::ferror(fp);
    std::fclose(fp);
    if (err) return make_error("cannot read " + path);
    auto r = parse(data.data(), data.size());
    if (!r) return make_error(path + ": " + r.error().message);
    return r;
}

Result<RepairReport> repair(const std::string& path) {
    auto parsed = read_file(path);
    if (!parsed) return parsed.error();
    File& f = *parsed;
    RepairReport rep;
    rep.bytes_before = f.file_size;
    rep.bytes_dropped = f.file_size - f.valid_bytes;
    for (const auto& s : f.streams) rep.samples_kept += s.sample_count();
    bool missing_footer = false;
    for (const auto& s : f.streams) missing_footer |= s.footer_xml.empty();
    if (!f.truncated && !missing_footer) {
        rep.already_closed = true;
        return rep;
    }
    const int fd = ::open(path.c_str(), O_WRONLY);
    if (fd < 0)
        return make_error("cannot open " + path + " for writing: " + std::strerror(errno), errno);
    auto fail = [&](const char* what) {
        const int e = errno;
        ::close(fd);
        return make_error(std::string(what) + " " + path + ": " + std::strerror(e), e);
    };
    if (::ftruncate(fd, static_cast<off_t>(f.valid_bytes)) != 0) return fail("cannot truncate");
    ChunkEncoder enc;
    enc.boundary();
    for (const auto& s : f.streams) {
        if (!s.footer_xml.empty()) continue;
        std::string extra = "  <repaired_by>fovea repair</repaired_by>\n  <clock_offsets>";
        for (const auto& [t, o] : s.clock_offsets) {
            char b[96];
            std::snprintf(b, sizeof b, "<offset><time>%.17g</time><value>%.17g</value></offset>", t,
                          o);
            extra += b;
        }
        extra += "</clock_offsets>\n";
        const double first = s.stamps.empty() ? 0.0 : s.stamps.front();
        const double last = s.stamps.empty() ? 0.0 : s.stamps.back();
        enc.stream_footer(s.id, first, last, s.sample_count(), extra);
        ++rep.footers_added;
    }
    const auto& b = enc.buffer();
    if (::lseek(fd, static_cast<off_t>(f.valid_bytes), SEEK_SET) < 0) return fail("cannot seek");
    std::size_t done = 0;
    while (done < b.size()) {
        const ssize_t w = ::write(fd, b.data() + done, b.size() - done);
        if (w < 0) {
            if (errno == EINTR) continue;
            return fail("cannot write");
        }
        done += static_cast<std::size_t>(w);
    }
    if (::fsync(fd) != 0) return fail("cannot sync");
    ::close(fd);
    return rep;
}

}  // namespace fovea::record::xdf
