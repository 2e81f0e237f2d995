#include <algorithm>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fovea/gaze/sample.hpp"
#include "fovea/latency_histogram.hpp"
#include "fovea/record/latency_stats.hpp"

using fovea::LatencyHistogram;
using fovea::record::Hop;
using fovea::record::LatencyStats;

namespace {
uint64_t exact_quantile(std::vector<int64_t> v, double q) {
    std::sort(v.begin(), v.end());
    auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
    rank = std::clamp<std::size_t>(rank, 1, v.size());
    return static_cast<uint64_t>(v[rank - 1]);
}
}  // namespace

TEST(LatencyHistogram, EveryValueLandsInABucketThatContainsIt) {
    std::mt19937_64 rng(1);
    for (int i = 0; i < 200000; ++i) {
        const uint64_t v = rng() >> (rng() % 64);
        const int b = LatencyHistogram::bucket_of(v);
        ASSERT_GE(b, 0);
        ASSERT_LT(b, LatencyHistogram::kBucketCount);
        if (v < (uint64_t{1} << (LatencyHistogram::kMaxExponent + 1))) {
            const uint64_t lo = LatencyHistogram::bucket_lower(b);
            const uint64_t w = LatencyHistogram::bucket_width(b);
            ASSERT_LE(lo, v);
            ASSERT_LT(v - lo, w);
            // relative width bounded by 1/64
            ASSERT_LE(static_cast<double>(w - 1), static_cast<double>(v) / 64.0 + 1e-9);
        }
    }
    // buckets tile the range without gaps
    for (int b = 0; b + 1 < LatencyHistogram::kBucketCount; ++b) {
        ASSERT_EQ(LatencyHistogram::bucket_lower(b) + LatencyHistogram::bucket_width(b),
                  LatencyHistogram::bucket_lower(b + 1));
    }
}

TEST(LatencyHistogram, PercentilesWithinOnePercentOfExactOnHeavyTailedData) {
    std::mt19937_64 rng(7);
    std::lognormal_distribution<double> d(std::log(800'000.0), 0.8);  // ~0.8 ms median
    std::vector<int64_t> v;
    LatencyHistogram h;
    for (int i = 0; i < 100000; ++i) {
        const auto x = static_cast<int64_t>(d(rng));
        v.push_back(x);
        h.record(x);
    }
    for (double q : {0.5, 0.9, 0.99, 0.999}) {
        const double exact = static_cast<double>(exact_quantile(v, q));
        EXPECT_NEAR(static_cast<double>(h.percentile(q)), exact, exact * 0.01) << "q=" << q;
    }
    EXPECT_EQ(h.percentile(1.0), static_cast<uint64_t>(*std::max_element(v.begin(), v.end())));
    EXPECT_EQ(h.min_ns(), static_cast<uint64_t>(*std::min_element(v.begin(), v.end())));
    EXPECT_EQ(h.count(), v.size());
}

TEST(LatencyHistogram, MergeEqualsRecordingEverythingInOne) {
    std::mt19937_64 rng(3);
    LatencyHistogram a, b, all;
    for (int i = 0; i < 5000; ++i) {
        const auto x = static_cast<int64_t>(rng() % 50'000'000);
        ((i % 3) ? a : b).record(x);
        all.record(x);
    }
    a.merge(b);
    EXPECT_EQ(a.count(), all.count());
    EXPECT_EQ(a.sum_ns(), all.sum_ns());
    EXPECT_EQ(a.min_ns(), all.min_ns());
    EXPECT_EQ(a.max_ns(), all.max_ns());
    for (int i = 0; i < LatencyHistogram::kBucketCount; ++i) {
        ASSERT_EQ(a.bucket_count(i), all.bucket_count(i));
    }
    for (double q : {0.5, 0.99, 0.999}) EXPECT_EQ(a.percentile(q), all.percentile(q));
}

TEST(LatencyHistogram, NegativeAndHugeValuesAreCountedNotLost) {
    LatencyHistogram h;
    h.record(-5);
    h.record(int64_t{1} << 50);  // beyond the bucketed range: top bucket, max stays exact
    EXPECT_EQ(h.count(), 2u);
    EXPECT_EQ(h.negative(), 1u);
    EXPECT_EQ(h.min_ns(), 0u);
    EXPECT_EQ(h.max_ns(), uint64_t{1} << 50);
    EXPECT_EQ(h.bucket_count(LatencyHistogram::kBucketCount - 1), 1u);
}

TEST(LatencyHistogram, EmptyHistogramReportsZeros) {
    LatencyHistogram h;
    EXPECT_EQ(h.count(), 0u);
    EXPECT_EQ(h.percentile(0.5), 0u);
    EXPECT_EQ(h.max_ns(), 0u);
    EXPECT_EQ(h.min_ns(), 0u);
}

TEST(LatencyHistogram, ReaderThreadSeesMonotonicCountsWhileOneWriterRecords) {
    LatencyHistogram h;
    std::atomic<bool> done{false};
    std::thread writer([&] {
        for (int i = 0; i < 200000; ++i) h.record(1000 + i % 5000);
        done = true;
    });
    uint64_t last = 0;
    while (!done) {
        const uint64_t n = h.count();
        ASSERT_GE(n, last);
        last = n;
        (void)h.percentile(0.99);
    }
    writer.join();
    EXPECT_EQ(h.count(), 200000u);
}

TEST(LatencyHistogram, SharedRecordIsExactUnderContention) {
    LatencyHistogram h;
    std::vector<std::thread> t;
    for (int k = 0; k < 4; ++k) {
        t.emplace_back([&, k] {
            for (int i = 0; i < 50000; ++i) h.record_shared(k * 1000 + i);
        });
    }
    for (auto& x : t) x.join();
    EXPECT_EQ(h.count(), 200000u);
    uint64_t total = 0;
    for (int i = 0; i < LatencyHistogram::kBucketCount; ++i) total += h.bucket_count(i);
    EXPECT_EQ(total, 200000u);
    EXPECT_EQ(h.max_ns(), 3000u + 49999u);
}

TEST(LatencyStats, JsonRoundTripKeepsEveryBucket) {
    LatencyStats s;
    fovea::gaze::GazeSample g;
    for (int i = 0; i < 1000; ++i) {
        g.t_capture_ns = 1'000'000'000 + i * 1'000'000;
        g.t_receive_ns = g.t_capture_ns + 2'000'000 + i * 100;
        g.t_processed_ns = g.t_receive_ns + 15'000;
        s.record_published(g, g.t_processed_ns + 3'000);
    }
    s.hop(Hop::kPublishToRead).record(-1);
    const nlohmann::json j = s.to_json();
    EXPECT_TRUE(j.contains("capture_to_receive"));
    EXPECT_TRUE(j.contains("publish_to_read"));
    EXPECT_FALSE(j.contains("submit_to_present"));  // empty hops are left out
    EXPECT_NEAR(j["receive_to_processed"]["p50_us"].get<double>(), 15.0, 0.15);
    auto back = LatencyStats::from_json(nlohmann::json::parse(j.dump()));
    ASSERT_TRUE(back.ok()) << back.error().message;
    for (int h = 0; h < fovea::record::kHopCount; ++h) {
        const auto& a = s.hop(static_cast<Hop>(h));
        const auto& b = back->hop(static_cast<Hop>(h));
        ASSERT_EQ(a.count(), b.count());
        EXPECT_EQ(a.negative(), b.negative());
        EXPECT_EQ(a.percentile(0.999), b.percentile(0.999));
        EXPECT_EQ(a.max_ns(), b.max_ns());
    }
}

TEST(LatencyStats, FromJsonRejectsInconsistentCounts) {
    nlohmann::json j = {
        {"capture_to_receive",
         {{"count", 5}, {"sum_ns", 10}, {"min_ns", 1}, {"max_ns", 3}, {"buckets", {{1, 2}}}}}};
    auto r = LatencyStats::from_json(j);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("capture_to_receive"), std::string::npos);
    j["capture_to_receive"]["buckets"] = {{999999, 5}};
    EXPECT_FALSE(LatencyStats::from_json(j).ok());
}

TEST(LatencyStats, FromJsonRejectsCountsThatAreNotNonNegativeIntegers) {
    // Found by fuzz_latency_json: get<uint64_t>() of 2.8e42 is undefined behaviour, not an error.
    const nlohmann::json good = {
        {"count", 1}, {"sum_ns", 10}, {"min_ns", 10}, {"max_ns", 10}, {"buckets", {{1, 1}}}};
    fovea::LatencyHistogram h;
    ASSERT_TRUE(fovea::record::histogram_from_json(good, h).ok());
    for (const char* key : {"count", "negative", "sum_ns", "min_ns", "max_ns"}) {
        for (const nlohmann::json& bad : {nlohmann::json(2.8e42), nlohmann::json(-1),
                                          nlohmann::json(1.5), nlohmann::json("7")}) {
            nlohmann::json j = good;
            j[key] = bad;
            const auto r = fovea::record::histogram_from_json(j, h);
            EXPECT_FALSE(r.ok()) << key << " = " << bad.dump();
            if (!r.ok()) { EXPECT_NE(r.error().message.find(key), std::string::npos); }
        }
    }
    nlohmann::json j = good;
    j["buckets"] = {{1e30, 1}};  // a float bucket index
    EXPECT_FALSE(fovea::record::histogram_from_json(j, h).ok());
}
