// fovea::LatencyHistogram: a log-bucketed latency histogram (HDR-style) shared by fovead (device
// hops) and the SDK (render hops), so both sides bucket, merge and report identically.
//
// Values are nanoseconds. Values below 64 ns get one bucket each; above, every power of two is
// split into 64 linear sub-buckets, so a bucket is at most 1/64 (1.6 %) of its value wide and a
// reported percentile (the bucket midpoint, clamped to [min, max]) is within 0.8 % of the true
// sample. Values up to 2^42 ns (73 minutes) are bucketed; larger ones land in the top bucket and
// still update max exactly. Memory is fixed: kBucketCount counters (19 KB), no allocation.
//
// Threading: record() is for ONE writer thread (relaxed load + store, no read-modify-write), any
// number of threads may call snapshot()/percentile() concurrently and see each counter whole
// (a snapshot taken during writes may be a few samples behind between fields). For several
// writers use record_shared() (atomic fetch_add) or one histogram per thread and merge().
// Header-only, no dependency beyond the standard library.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

namespace fovea {

class LatencyHistogram {
public:
    static constexpr int kSubBucketBits = 6;
    static constexpr uint64_t kSubBuckets = uint64_t{1} << kSubBucketBits;  // per octave
    static constexpr int kMaxExponent = 41;  // values < 2^(kMaxExponent+1) ns are bucketed
    static constexpr int kBucketCount =
        static_cast<int>((kMaxExponent - kSubBucketBits + 2) * kSubBuckets);

    // Bucket of a value (ns); values past the range map to the last bucket.
    static constexpr int bucket_of(uint64_t v) {
        if (v < kSubBuckets) return static_cast<int>(v);
        const int e = 63 - std::countl_zero(v);
        if (e > kMaxExponent) return kBucketCount - 1;
        const uint64_t m = v >> (e - kSubBucketBits);  // top kSubBucketBits+1 bits: [64, 128)
        return static_cast<int>(static_cast<uint64_t>(e - kSubBucketBits + 1) * kSubBuckets +
                                (m - kSubBuckets));
    }
    // Smallest value in bucket `i` and the bucket's width.
    static constexpr uint64_t bucket_lower(int i) {
        const uint64_t k = static_cast<uint64_t>(i) / kSubBuckets;
        const uint64_t sub = static_cast<uint64_t>(i) % kSubBuckets;
        if (k == 0) return sub;
        return (kSubBuckets + sub) << (k - 1);
    }
    static constexpr uint64_t bucket_width(int i) {
        const uint64_t k = static_cast<uint64_t>(i) / kSubBuckets;
        return k == 0 ? 1 : uint64_t{1} << (k - 1);
    }

    LatencyHistogram() { reset(); }
    LatencyHistogram(const LatencyHistogram& o) { copy_from(o); }
    LatencyHistogram& operator=(const LatencyHistogram& o) {
        if (this != &o) copy_from(o);
        return *this;
    }

    // Record one latency in ns. Negative values (a clock mapping that put the capture after the
    // receive) cannot be bucketed: they count as 0 ns and are counted in negative().
    // Single writer only (see the header comment).
    void record(int64_t ns) {
        uint64_t v = 0;
        if (ns < 0) {
            bump(negative_);
        } else {
            v = static_cast<uint64_t>(ns);
        }
        bump(counts_[static_cast<std::size_t>(bucket_of(v))]);
        bump(count_);
        sum_.store(sum_.load(std::memory_order_relaxed) + v, std::memory_order_relaxed);
        if (v < min_.load(std::memory_order_relaxed)) min_.store(v, std::memory_order_relaxed);
        if (v > max_.load(std::memory_order_relaxed)) max_.store(v, std::memory_order_relaxed);
    }
    // Record from any thread (atomic read-modify-writes; a few ns slower).
    void record_shared(int64_t ns) {
        uint64_t v = 0;
        if (ns < 0) {
            negative_.fetch_add(1, std::memory_order_relaxed);
        } else {
            v = static_cast<uint64_t>(ns);
        }
        counts_[static_cast<std::size_t>(bucket_of(v))].fetch_add(1, std::memory_order_relaxed);
        count_.fetch_add(1, std::memory_order_relaxed);
        sum_.fetch_add(v, std::memory_order_relaxed);
        uint64_t cur = min_.load(std::memory_order_relaxed);
        while (v < cur && !min_.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {}
        cur = max_.load(std::memory_order_relaxed);
        while (v > cur && !max_.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {}
    }

    // Add every sample of `o` (same bucketing, so merging is exact). Writer thread of *this.
    void merge(const LatencyHistogram& o) {
        for (int i = 0; i < kBucketCount; ++i) {
            const uint64_t c = o.bucket_count(i);
            if (c != 0) add_bucket(i, c);
        }
        add_totals(o.count(), o.sum_ns(), o.negative(), o.count() ? o.min_ns() : kNoMin,
                   o.max_ns());
    }

    void reset() {
        for (auto& c : counts_) c.store(0, std::memory_order_relaxed);
        count_.store(0, std::memory_order_relaxed);
        sum_.store(0, std::memory_order_relaxed);
        negative_.store(0, std::memory_order_relaxed);
        min_.store(kNoMin, std::memory_order_relaxed);
        max_.store(0, std::memory_order_relaxed);
    }

    uint64_t count() const { return count_.load(std::memory_order_relaxed); }
    uint64_t negative() const { return negative_.load(std::memory_order_relaxed); }
    uint64_t sum_ns() const { return sum_.load(std::memory_order_relaxed); }
    uint64_t min_ns() const {
        const uint64_t m = min_.load(std::memory_order_relaxed);
        return m == kNoMin ? 0 : m;
    }
    uint64_t max_ns() const { return max_.load(std::memory_order_relaxed); }
    double mean_ns() const {
        const uint64_t n = count();
        return n ? static_cast<double>(sum_ns()) / static_cast<double>(n) : 0.0;
    }
    uint64_t bucket_count(int i) const {
        return counts_[static_cast<std::size_t>(i)].load(std::memory_order_relaxed);
    }

    // Value at quantile q in [0, 1] (0.5 = median, 1 = max), ns: the midpoint of the bucket
    // holding the ceil(q * count)-th smallest sample, clamped to [min, max]. 0 when empty.
    uint64_t percentile(double q) const {
        const uint64_t n = count();
        if (n == 0) return 0;
        if (q >= 1.0) return max_ns();
        q = std::max(q, 0.0);
        uint64_t rank = static_cast<uint64_t>(q * static_cast<double>(n) + 0.999999999);
        rank = std::clamp<uint64_t>(rank, 1, n);
        uint64_t seen = 0;
        int i = 0;
        for (; i < kBucketCount; ++i) {
            seen += bucket_count(i);
            if (seen >= rank) break;
        }
        if (i == kBucketCount) return max_ns();  // counters raced ahead of count_
        const uint64_t mid = bucket_lower(i) + (bucket_width(i) - 1) / 2;
        return std::clamp(mid, min_ns(), max_ns());
    }

    // Sparse form for serialisation: (bucket index, count) of every non-empty bucket.
    struct Sparse {
        std::vector<std::pair<int, uint64_t>> buckets;
        uint64_t count = 0, sum_ns = 0, negative = 0, min_ns = 0, max_ns = 0;
    };
    Sparse sparse() const {
        Sparse s;
        for (int i = 0; i < kBucketCount; ++i) {
            if (const uint64_t c = bucket_count(i)) s.buckets.emplace_back(i, c);
        }
        s.count = count();
        s.sum_ns = sum_ns();
        s.negative = negative();
        s.min_ns = min_ns();
        s.max_ns = max_ns();
        return s;
    }
    // Rebuild from sparse(); false (and *this reset) if a bucket index is out of range or the
    // bucket counts do not add up to `count`.
    bool assign(const Sparse& s) {
        reset();
        uint64_t total = 0;
        for (const auto& [i, c] : s.buckets) {
            if (i < 0 || i >= kBucketCount) {
                reset();
                return false;
            }
            add_bucket(i, c);
            total += c;
        }
        if (total != s.count) {
            reset();
            return false;
        }
        add_totals(s.count, s.sum_ns, s.negative, s.count ? s.min_ns : kNoMin, s.max_ns);
        return true;
    }

private:
    static constexpr uint64_t kNoMin = std::numeric_limits<uint64_t>::max();

    static void bump(std::atomic<uint64_t>& a) {
        a.store(a.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
    }
    void add_bucket(int i, uint64_t c) {
        auto& a = counts_[static_cast<std::size_t>(i)];
        a.store(a.load(std::memory_order_relaxed) + c, std::memory_order_relaxed);
    }
    void add_totals(uint64_t n, uint64_t sum, uint64_t neg, uint64_t mn, uint64_t mx) {
        count_.store(count() + n, std::memory_order_relaxed);
        sum_.store(sum_ns() + sum, std::memory_order_relaxed);
        negative_.store(negative() + neg, std::memory_order_relaxed);
        if (mn < min_.load(std::memory_order_relaxed)) min_.store(mn, std::memory_order_relaxed);
        if (mx > max_ns()) max_.store(mx, std::memory_order_relaxed);
    }
    void copy_from(const LatencyHistogram& o) {
        for (int i = 0; i < kBucketCount; ++i) {
            counts_[static_cast<std::size_t>(i)].store(o.bucket_count(i),
                                                       std::memory_order_relaxed);
        }
        count_.store(o.count(), std::memory_order_relaxed);
        sum_.store(o.sum_ns(), std::memory_order_relaxed);
        negative_.store(o.negative(), std::memory_order_relaxed);
        min_.store(o.min_.load(std::memory_order_relaxed), std::memory_order_relaxed);
        max_.store(o.max_ns(), std::memory_order_relaxed);
    }

    std::array<std::atomic<uint64_t>, kBucketCount> counts_;
    std::atomic<uint64_t> count_, sum_, negative_, min_, max_;
};

static_assert(LatencyHistogram::bucket_of(63) == 63);
static_assert(LatencyHistogram::bucket_of(64) == 64);
static_assert(LatencyHistogram::bucket_of(127) == 127);
static_assert(LatencyHistogram::bucket_of(128) == 128);
static_assert(LatencyHistogram::bucket_lower(LatencyHistogram::bucket_of(1000003)) <= 1000003);

}  // namespace fovea
