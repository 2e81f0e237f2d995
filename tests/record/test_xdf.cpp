#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "fovea/record/xdf.hpp"
#include "libxdf_oracle.hpp"
#include "test_util.hpp"

namespace xdf = fovea::record::xdf;
using fovea::record::test::expect_libxdf_agrees;
using fovea::record::test::ScratchDir;

namespace {

void write_bytes(const std::string& path, const std::vector<uint8_t>& b) {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

xdf::StreamInfo info(const char* name, xdf::Format f, int channels, double srate) {
    xdf::StreamInfo s;
    s.name = name;
    s.type = "Test";
    s.format = f;
    s.nominal_srate = srate;
    s.source_id = std::string("test-") + name;
    for (int c = 0; c < channels; ++c) s.channels.push_back({"ch" + std::to_string(c), "u", "T"});
    return s;
}

// A file with one stream per numeric format, `n` samples each, in chunks of 100.
std::vector<uint8_t> make_file(int n, bool footers) {
    xdf::ChunkEncoder e;
    e.magic();
    e.file_header();
    const xdf::Format fmts[] = {xdf::Format::kDouble64, xdf::Format::kFloat32, xdf::Format::kInt64,
                                xdf::Format::kInt32,    xdf::Format::kInt16,   xdf::Format::kInt8};
    for (uint32_t id = 0; id < 6; ++id)
        e.stream_header(id + 10,
                        info(std::string(xdf::format_name(fmts[id])).c_str(), fmts[id], 3, 500));
    for (int a = 0; a < n; a += 100) {
        for (uint32_t id = 0; id < 6; ++id) {
            std::vector<double> st, v;
            for (int i = a; i < std::min(n, a + 100); ++i) {
                st.push_back(1000.0 + i * 0.002);
                v.push_back(i % 100);
                v.push_back(-(i % 50));
                v.push_back(id == 0 ? i * 0.125 : 7);
            }
            e.samples(id + 10, fmts[id], 3, st.data(), v.data(), st.size());
        }
        e.clock_offset(10, 1000.0 + a * 0.002, 0.0);
        e.boundary();
    }
    if (footers) {
        for (uint32_t id = 0; id < 6; ++id)
            e.stream_footer(id + 10, 1000.0, 1000.0 + (n - 1) * 0.002, n);
    }
    return e.buffer();
}

}  // namespace

TEST(Xdf, ChunkLengthUsesTheSmallestPrefixThatFits) {
    xdf::ChunkEncoder e;
    e.boundary();  // 2 + 16 bytes: 1-byte length
    ASSERT_EQ(e.buffer().size(), 2u + 18u);
    EXPECT_EQ(e.buffer()[0], 1);
    EXPECT_EQ(e.buffer()[1], 18);
    EXPECT_EQ(e.buffer()[2], 5);  // tag, little-endian u16
    EXPECT_EQ(e.buffer()[3], 0);
    EXPECT_EQ(0, std::memcmp(e.buffer().data() + 4, xdf::kBoundaryUuid.data(), 16));
    e.clear();
    std::vector<double> st(100, 1.0), v(100 * 4, 2.0);  // > 255 bytes: 4-byte length
    e.samples(1, xdf::Format::kDouble64, 4, st.data(), v.data(), st.size());
    EXPECT_EQ(e.buffer()[0], 4);
    uint32_t len = 0;
    std::memcpy(&len, e.buffer().data() + 1, 4);
    EXPECT_EQ(len, e.buffer().size() - 5);
    // sample count is a varlen too: [1][100]
    EXPECT_EQ(e.buffer()[5 + 2 + 4], 1);
    EXPECT_EQ(e.buffer()[5 + 2 + 4 + 1], 100);
}

TEST(Xdf, EveryNumericFormatRoundTrips) {
    const auto bytes = make_file(1000, true);
    auto f = xdf::parse(bytes.data(), bytes.size());
    ASSERT_TRUE(f.ok()) << f.error().message;
    EXPECT_FALSE(f->truncated);
    ASSERT_EQ(f->streams.size(), 6u);
    EXPECT_EQ(f->boundaries, 10u);
    for (const auto& s : f->streams) {
        ASSERT_EQ(s.sample_count(), 1000u) << s.name;
        EXPECT_EQ(s.labels.size(), 3u);
        EXPECT_EQ(s.clock_offsets.size(), s.id == 10 ? 10u : 0u);
        EXPECT_FALSE(s.footer_xml.empty());
        for (int i = 0; i < 1000; ++i) {
            ASSERT_EQ(s.stamps[i], 1000.0 + i * 0.002);
            ASSERT_EQ(s.value(i, 0), i % 100) << s.name;
            ASSERT_EQ(s.value(i, 1), -(i % 50)) << s.name;
            ASSERT_EQ(s.value(i, 2), s.id == 10 ? i * 0.125 : 7) << s.name;
        }
    }
}

TEST(Xdf, LibxdfReadsEveryFormatAsWeDo) {
    const ScratchDir dir("libxdf");
    const std::string path = (dir / "formats.xdf").string();
    write_bytes(path, make_file(1000, true));
    expect_libxdf_agrees(path);
}

TEST(Xdf, TruncatedAtEveryByteReadsUpToTheLastWholeChunk) {
    const auto full = make_file(300, true);
    auto whole = xdf::parse(full.data(), full.size());
    ASSERT_TRUE(whole.ok());
    std::size_t header_end = 0;  // after the last stream header
    for (const auto& c : whole->chunks) {
        if (c.tag == 2) header_end = c.offset + c.length + 5;
    }
    for (std::size_t cut = header_end + 8; cut < full.size(); cut += 7) {
        auto f = xdf::parse(full.data(), cut);
        ASSERT_TRUE(f.ok()) << "cut " << cut << ": " << f.error().message;
        ASSERT_LE(f->valid_bytes, cut);
        // whole chunks before the cut are all kept
        uint64_t expect_end = 4;
        for (const auto& c : whole->chunks) {
            const uint64_t prefix = c.length <= 0xFF ? 1 : c.length <= 0xFFFFFFFF ? 4 : 8;
            const uint64_t end = c.offset + 1 + prefix + c.length;
            if (end <= cut) expect_end = end;
        }
        ASSERT_EQ(f->valid_bytes, expect_end) << "cut " << cut;
        ASSERT_EQ(f->truncated, cut != expect_end);
    }
}

TEST(Xdf, RepairClosesAFileCutAnywhereAndLibxdfAgrees) {
    const auto full = make_file(300, false);
    auto whole = xdf::parse(full.data(), full.size());
    ASSERT_TRUE(whole.ok());
    std::size_t header_end = 0;  // after the last stream header
    for (const auto& c : whole->chunks) {
        if (c.tag == 2) header_end = c.offset + c.length + 5;
    }
    const ScratchDir dir("repair");
    std::mt19937 rng(5);
    int compared = 0;  // cuts libxdf could load
    for (int k = 0; k < 12; ++k) {
        const std::size_t cut = header_end + rng() % (full.size() - header_end);
        const std::string path = (dir / ("cut" + std::to_string(k) + ".xdf")).string();
        write_bytes(path,
                    std::vector<uint8_t>(full.begin(), full.begin() + static_cast<long>(cut)));
        auto before = xdf::read_file(path);
        ASSERT_TRUE(before.ok());
        auto rep = xdf::repair(path);
        ASSERT_TRUE(rep.ok()) << rep.error().message;
        EXPECT_EQ(rep->footers_added, 6);
        EXPECT_EQ(rep->bytes_dropped, cut - before->valid_bytes);
        auto after = xdf::read_file(path);
        ASSERT_TRUE(after.ok());
        EXPECT_FALSE(after->truncated);
        for (std::size_t i = 0; i < after->streams.size(); ++i) {
            EXPECT_EQ(after->streams[i].sample_count(), before->streams[i].sample_count());
            EXPECT_FALSE(after->streams[i].footer_xml.empty());
        }
        auto again = xdf::repair(path);
        ASSERT_TRUE(again.ok());
        EXPECT_TRUE(again->already_closed);
        // libxdf 0.99.8 crashes (Xdf::syncTimeStamps) on a stream without samples, so cuts
        // before every stream's first chunk are ours alone.
        if (std::all_of(after->streams.begin(), after->streams.end(),
                        [](const xdf::Stream& s) { return s.sample_count() > 0; })) {
            expect_libxdf_agrees(path);
            ++compared;
        }
    }
    EXPECT_GE(compared, 6);
}

TEST(Xdf, GarbageIsAClearErrorNotACrash) {
    const std::vector<uint8_t> junk = {'N', 'O', 'P', 'E', 1, 2, 3};
    auto r = xdf::parse(junk.data(), junk.size());
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("magic"), std::string::npos);
    auto missing = xdf::read_file("/nonexistent/x.xdf");
    ASSERT_FALSE(missing.ok());
    // random bytes after a valid prefix: truncated, never a crash
    auto bytes = make_file(100, true);
    std::mt19937 rng(9);
    for (int k = 0; k < 200; ++k) {
        auto b = bytes;
        for (int m = 0; m < 4; ++m) b[600 + rng() % (b.size() - 600)] = static_cast<uint8_t>(rng());
        auto f = xdf::parse(b.data(), b.size());
        if (f.ok()) {
            for (const auto& s : f->streams) { ASSERT_EQ(s.values.size(), s.stamps.size() * 3); }
        }
    }
}
