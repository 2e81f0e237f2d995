// Benchmarks: histogram record() cost, XDF encoding throughput, Recorder push cost.
//   build-*/tests/record/record_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "fovea/latency_histogram.hpp"
#include "fovea/record/recorder.hpp"
#include "fovea/record/streams.hpp"
#include "fovea/record/xdf.hpp"

namespace {

std::vector<int64_t> latencies() {
    std::mt19937_64 rng(1);
    std::lognormal_distribution<double> d(13.5, 1.0);  // ~0.7 ms median, heavy tail
    std::vector<int64_t> v(4096);
    for (auto& x : v) x = static_cast<int64_t>(d(rng));
    return v;
}

void BM_HistogramRecord(benchmark::State& state) {
    fovea::LatencyHistogram h;
    const auto v = latencies();
    std::size_t i = 0;
    for (auto _ : state) { h.record(v[i++ & 4095]); }
    benchmark::DoNotOptimize(h.count());
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_HistogramRecord);

void BM_HistogramRecordShared(benchmark::State& state) {
    fovea::LatencyHistogram h;
    const auto v = latencies();
    std::size_t i = 0;
    for (auto _ : state) { h.record_shared(v[i++ & 4095]); }
    benchmark::DoNotOptimize(h.count());
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_HistogramRecordShared);

void BM_HistogramP99(benchmark::State& state) {
    fovea::LatencyHistogram h;
    for (auto x : latencies()) h.record(x);
    for (auto _ : state) benchmark::DoNotOptimize(h.percentile(0.99));
}
BENCHMARK(BM_HistogramP99);

// Encoding 1000 processed-gaze rows (one second at 1 kHz) into Samples chunks.
void BM_XdfEncodeGazeSecond(benchmark::State& state) {
    const int ch = fovea::record::gaze_channel_count();
    std::vector<double> stamps(1000), rows(1000 * static_cast<std::size_t>(ch));
    for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<double>(i) * 0.25;
    for (std::size_t i = 0; i < stamps.size(); ++i)
        stamps[i] = 1000.0 + static_cast<double>(i) * 1e-3;
    fovea::record::xdf::ChunkEncoder enc;
    std::size_t bytes = 0;
    for (auto _ : state) {
        enc.clear();
        enc.samples(2, fovea::record::xdf::Format::kDouble64, ch, stamps.data(), rows.data(), 1000);
        bytes = enc.buffer().size();
        benchmark::DoNotOptimize(enc.buffer().data());
    }
    state.SetItemsProcessed(state.iterations() * 1000);
    state.SetBytesProcessed(state.iterations() * static_cast<int64_t>(bytes));
}
BENCHMARK(BM_XdfEncodeGazeSecond);

// The daemon-side cost of recording one sample (raw + gaze + latency rows into the queue),
// with the writer thread writing to /tmp concurrently.
void BM_RecorderPush(benchmark::State& state) {
    fovea::record::RecorderOptions o;
    o.path = "/tmp/fovea_bench_recorder.xdf";
    o.max_pending_samples = 1 << 22;
    auto rec = fovea::record::Recorder::start(o);
    if (!rec.ok()) {
        state.SkipWithError(rec.error().message.c_str());
        return;
    }
    fovea::gaze::RawSample raw;
    fovea::gaze::GazeSample g;
    int64_t t = fovea::record::monotonic_ns();
    for (auto _ : state) {
        raw.t_receive_ns = t;
        g.t_capture_ns = t;
        (*rec)->push_raw(raw, true);
        (*rec)->push_gaze(g, t, 1);
        t += 1000;
    }
    auto st = (*rec)->stop();
    state.SetItemsProcessed(state.iterations());
    if (st.ok()) {
        state.counters["bytes_per_sample"] =
            static_cast<double>(st->bytes_written) / static_cast<double>(state.iterations());
        state.counters["dropped"] = static_cast<double>(st->dropped_samples);
    }
    std::remove(o.path.c_str());
}
BENCHMARK(BM_RecorderPush)->Iterations(200000);

}  // namespace

BENCHMARK_MAIN();
