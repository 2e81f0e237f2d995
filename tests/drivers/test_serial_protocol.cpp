// The serial protocol on byte streams: round trips, garbage, truncation, CRC errors, absurd values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "serial/device_sim.hpp"
#include "serial/protocol.hpp"

namespace fovea::drivers::serial {
namespace {

struct Collected {
    std::vector<Frame> frames;
    std::vector<std::vector<uint8_t>> payloads;
    std::vector<FrameDecoder::Reject> rejects;
};

void feed_all(FrameDecoder& d, std::span<const uint8_t> bytes, Collected& c) {
    d.feed(
        bytes,
        [&](const Frame& f) {
            c.frames.push_back(f);
            c.payloads.emplace_back(f.payload.begin(), f.payload.end());
        },
        [&](FrameDecoder::Reject r) { c.rejects.push_back(r); });
}

std::vector<gaze::RawSample> decode_samples(const Collected& c) {
    std::vector<gaze::RawSample> out;
    for (size_t i = 0; i < c.frames.size(); ++i) {
        if (c.frames[i].type != static_cast<uint8_t>(FrameType::kSample)) continue;
        if (auto s = decode_sample(c.payloads[i])) out.push_back(*s);
    }
    return out;
}

gaze::RawSample sample(uint64_t ticks, double x = 0.25, double y = 0.75) {
    gaze::RawSample s;
    s.device_ticks = ticks;
    s.left = {x, y, 3.25, true};
    s.right = {x + 0.01, y - 0.01, 3.5, true};
    return s;
}

TEST(SerialProtocol, Crc32MatchesTheStandardCheckValue) {
    const char* check = "123456789";
    EXPECT_EQ(crc32({reinterpret_cast<const uint8_t*>(check), 9}), 0xCBF43926u);
}

TEST(SerialProtocol, SampleAndHelloRoundTrip) {
    std::vector<uint8_t> bytes;
    Hello h;
    h.name = "Test tracker";
    h.counter_bits = 16;
    h.tick_hz = 32768;
    h.rate_mhz = 500'000;
    encode_hello(h, 7, bytes);
    auto s = sample(0x1234'5678'9abcULL);
    s.right = {};  // right eye lost
    encode_sample(s, 8, bytes);
    std::vector<uint8_t> one;
    encode_sample(sample(1000), 5, one);
    EXPECT_EQ(one.size(), 40u);  // PROTOCOL.md's example
    FrameDecoder d;
    Collected c;
    feed_all(d, bytes, c);
    ASSERT_EQ(c.frames.size(), 2u);
    EXPECT_TRUE(c.rejects.empty());
    EXPECT_EQ(c.frames[0].seq, 7);
    const auto hh = decode_hello(c.payloads[0]);
    ASSERT_TRUE(hh);
    EXPECT_EQ(hh->name, "Test tracker");
    EXPECT_EQ(hh->counter_bits, 16);
    EXPECT_EQ(hh->tick_hz, 32768u);
    EXPECT_EQ(hh->rate_mhz, 500'000u);
    const auto ss = decode_sample(c.payloads[1]);
    ASSERT_TRUE(ss);
    EXPECT_EQ(ss->device_ticks, 0x1234'5678'9abcULL);
    EXPECT_FLOAT_EQ(ss->left.x, 0.25f);
    EXPECT_FLOAT_EQ(ss->left.y, 0.75f);
    EXPECT_DOUBLE_EQ(ss->left.pupil_mm, 3.25);
    EXPECT_TRUE(ss->left.valid);
    EXPECT_FALSE(ss->right.valid);
    EXPECT_TRUE(std::isnan(ss->right.x));
}

TEST(SerialProtocol, CobsHandlesZerosAndLongRunsAtEveryPayloadLength) {
    std::mt19937 rng(1);
    for (size_t len = 0; len + kHeaderSize + kCrcSize <= kMaxFrameSize; ++len) {
        for (int pattern = 0; pattern < 3; ++pattern) {
            std::vector<uint8_t> payload(len);
            for (auto& b : payload) {
                b = pattern == 0 ? 0 : pattern == 1 ? 0xFF : static_cast<uint8_t>(rng() % 3);
            }
            std::vector<uint8_t> bytes;
            encode_frame(FrameType::kSample, static_cast<uint16_t>(len), payload, bytes);
            EXPECT_LE(bytes.size(), kMaxEncodedSize + 2);
            FrameDecoder d;
            Collected c;
            feed_all(d, bytes, c);
            ASSERT_EQ(c.frames.size(), 1u) << "len " << len << " pattern " << pattern;
            EXPECT_EQ(c.payloads[0], payload);
        }
    }
}

TEST(SerialProtocol, GarbageBetweenFramesNeverLosesAGoodFrame) {
    sim::SimConfig sc;
    FaultOptions faults;
    faults.garbage = 0.3;
    faults.seed = 5;
    DeviceEmulator dev(sc, faults, "t");
    std::vector<uint8_t> bytes;
    std::vector<gaze::RawSample> sent;
    for (int i = 0; i < 20000; ++i) {
        gaze::RawSample s;
        dev.next_sample(bytes, &s);
        sent.push_back(s);
    }
    FrameDecoder d;
    Collected c;
    feed_all(d, bytes, c);
    const auto got = decode_samples(c);
    ASSERT_EQ(got.size(), sent.size());
    for (size_t i = 0; i < sent.size(); ++i) ASSERT_EQ(got[i].device_ticks, sent[i].device_ticks);
    // Every burst was rejected and counted; a burst is at least one bad chunk.
    EXPECT_GT(dev.stats().garbage_bursts, 5000u);
    EXPECT_GE(d.stats().dropped, dev.stats().garbage_bursts * 95 / 100);
    EXPECT_LE(d.stats().resyncs, dev.stats().garbage_bursts);
    EXPECT_GE(d.stats().resyncs, dev.stats().garbage_bursts * 95 / 100);
    std::printf(
        "garbage: %llu bursts, %llu frames all recovered, %llu chunks dropped, %llu "
        "resyncs, %llu garbage bytes\n",
        static_cast<unsigned long long>(dev.stats().garbage_bursts),
        static_cast<unsigned long long>(got.size()),
        static_cast<unsigned long long>(d.stats().dropped),
        static_cast<unsigned long long>(d.stats().resyncs),
        static_cast<unsigned long long>(d.stats().garbage_bytes));
}

TEST(SerialProtocol, ByteAtATimeGivesTheSameFramesAsOneBlock) {
    sim::SimConfig sc;
    FaultOptions faults;
    faults.garbage = 0.2;
    faults.corrupt = 0.1;
    DeviceEmulator dev(sc, faults, "t");
    std::vector<uint8_t> bytes;
    for (int i = 0; i < 500; ++i) dev.next_sample(bytes);
    FrameDecoder a, b;
    Collected ca, cb;
    feed_all(a, bytes, ca);
    for (size_t i = 0; i < bytes.size(); ++i) feed_all(b, {&bytes[i], 1}, cb);
    ASSERT_EQ(ca.payloads, cb.payloads);
    EXPECT_EQ(a.stats().dropped, b.stats().dropped);
    EXPECT_EQ(ca.frames.size() + dev.stats().corrupted, 500u);
}

TEST(SerialProtocol, TruncatedFrameIsDroppedAndTheNextFrameSurvives) {
    std::vector<uint8_t> one, two;
    encode_sample(sample(1), 1, one);
    encode_sample(sample(2), 2, two);
    for (size_t cut = 1; cut + 1 < one.size(); ++cut) {
        // The device stops mid-frame, then resumes with a fresh frame.
        std::vector<uint8_t> bytes(one.begin(), one.begin() + static_cast<long>(cut));
        bytes.insert(bytes.end(), two.begin(), two.end());
        FrameDecoder d;
        Collected c;
        feed_all(d, bytes, c);
        const auto got = decode_samples(c);
        ASSERT_EQ(got.size(), 1u) << "cut " << cut;
        EXPECT_EQ(got[0].device_ticks, 2u);
        EXPECT_EQ(d.stats().dropped, cut > 1 ? 1u : 0u) << "cut " << cut;
    }
}

TEST(SerialProtocol, AnySingleByteErrorIsRejectedNeverDeliveredWrong) {
    std::vector<uint8_t> frame, next;
    encode_sample(sample(42), 1, frame);
    encode_sample(sample(43), 2, next);
    for (size_t at = 1; at + 1 < frame.size(); ++at) {
        for (int flip = 1; flip < 256; flip += 17) {
            auto bytes = frame;
            bytes[at] ^= static_cast<uint8_t>(flip);
            bytes.insert(bytes.end(), next.begin(), next.end());
            FrameDecoder d;
            Collected c;
            feed_all(d, bytes, c);
            const auto got = decode_samples(c);
            ASSERT_FALSE(got.empty());
            // The corrupted frame never comes through; the good one after it always does.
            for (const auto& s : got) ASSERT_EQ(s.device_ticks, 43u) << at << " " << flip;
            ASSERT_GE(d.stats().dropped, 1u);
        }
    }
}

TEST(SerialProtocol, AbsurdValuesWithAValidCrcAreRejected) {
    const double bad[][3] = {{NAN, 0.5, 3}, {0.5, INFINITY, 3}, {1e30, 0.5, 3},
                             {0.5, -5, 3},  {0.5, 0.5, 60},     {0.5, 0.5, 0.1}};
    for (const auto& v : bad) {
        auto s = sample(1, v[0], v[1]);
        s.left.pupil_mm = v[2];
        std::vector<uint8_t> bytes;
        encode_sample(s, 1, bytes);
        FrameDecoder d;
        Collected c;
        feed_all(d, bytes, c);
        ASSERT_EQ(c.frames.size(), 1u);  // framing is fine ...
        std::string why;
        EXPECT_FALSE(decode_sample(c.payloads[0], &why));  // ... the content is not
        EXPECT_NE(why.find("absurd"), std::string::npos);
    }
    // Values of an eye flagged invalid are ignored, whatever they are.
    auto s = sample(1, NAN, 1e30);
    s.left.valid = false;
    s.right = {0.5, 0.5, 3.0, true};
    std::vector<uint8_t> bytes;
    encode_sample(s, 1, bytes);
    FrameDecoder d;
    Collected c;
    feed_all(d, bytes, c);
    EXPECT_EQ(decode_samples(c).size(), 1u);
}

TEST(SerialProtocol, ShortPayloadsAndBadHelloAreRejected) {
    std::vector<uint8_t> p(10, 1);
    EXPECT_FALSE(decode_sample(p));
    EXPECT_FALSE(decode_hello(p));
    Hello h;
    h.counter_bits = 24;
    std::vector<uint8_t> bytes;
    encode_hello(h, 0, bytes);
    FrameDecoder d;
    Collected c;
    feed_all(d, bytes, c);
    ASSERT_EQ(c.frames.size(), 1u);
    EXPECT_FALSE(decode_hello(c.payloads[0]));
}

TEST(SerialProtocol, OversizedRunIsDroppedWithoutUnboundedBuffering) {
    std::vector<uint8_t> bytes(1 << 20, 0x55);  // 1 MiB without a delimiter
    encode_sample(sample(9), 1, bytes);
    FrameDecoder d;
    Collected c;
    feed_all(d, bytes, c);
    const auto got = decode_samples(c);
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].device_ticks, 9u);
    EXPECT_EQ(d.stats().dropped, 1u);
    EXPECT_EQ(d.stats().resyncs, 1u);
}

TEST(SerialProtocol, RandomNoiseInterleavedWithFramesLosesNoGoodFrame) {
    std::mt19937_64 rng(77);
    std::vector<uint8_t> bytes;
    int sent = 0;
    for (int i = 0; i < 3000; ++i) {
        const int noise = static_cast<int>(rng() % 200);
        for (int k = 0; k < noise; ++k) bytes.push_back(static_cast<uint8_t>(rng()));
        encode_sample(sample(static_cast<uint64_t>(i)), static_cast<uint16_t>(i), bytes);
        ++sent;
    }
    FrameDecoder d;
    Collected c;
    feed_all(d, bytes, c);
    const auto got = decode_samples(c);
    ASSERT_EQ(static_cast<int>(got.size()), sent);
    for (int i = 0; i < sent; ++i) ASSERT_EQ(got[static_cast<size_t>(i)].device_ticks, uint64_t(i));
}

TEST(SerialProtocol, SequenceTrackerCountsGapsAcrossWrap) {
    SequenceTracker t;
    EXPECT_EQ(t.on_seq(65530), 0u);
    EXPECT_EQ(t.on_seq(65531), 0u);
    EXPECT_EQ(t.on_seq(65534), 2u);
    EXPECT_EQ(t.on_seq(2), 3u);  // 65535, 0, 1 missing
    EXPECT_EQ(t.on_seq(1), 0u);  // backwards: device restart, not a loss
    EXPECT_EQ(t.on_seq(2), 0u);
}

TEST(SerialProtocol, EmulatorAnswersHelloRequestAndRateChange) {
    sim::SimConfig sc;
    DeviceEmulator dev(sc, {}, "emu");
    std::vector<uint8_t> host, reply;
    encode_hello_request(0, host);
    Configure cfg;
    cfg.rate_mhz = 250'000;
    encode_configure(cfg, 1, host);
    dev.on_host_bytes(host, reply);
    FrameDecoder d;
    Collected c;
    feed_all(d, reply, c);
    ASSERT_EQ(c.frames.size(), 2u);
    const auto h = decode_hello(c.payloads[1]);
    ASSERT_TRUE(h);
    EXPECT_EQ(h->rate_mhz, 250'000u);
    EXPECT_EQ(h->name, "emu");
    EXPECT_EQ(dev.rate_hz(), 250.0);
}

}  // namespace
}  // namespace fovea::drivers::serial
