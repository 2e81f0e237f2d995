// Parser and generator throughput: serial frame decoding (clean and with 30 % garbage bursts),
// Gazepoint element stream + record decoding, simulated tracker samples.
//   build-*/tests/drivers/drivers_bench --benchmark_repetitions=5
//   --benchmark_report_aggregates_only
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "gazepoint/opengaze.hpp"
#include "serial/device_sim.hpp"
#include "serial/protocol.hpp"
#include "sim/sim_tracker.hpp"

namespace {

using namespace fovea::drivers;

std::vector<uint8_t> serial_stream(double garbage) {
    serial::FaultOptions f;
    f.garbage = garbage;
    serial::DeviceEmulator dev(sim::SimConfig{}, f, "bench");
    std::vector<uint8_t> bytes;
    for (int i = 0; i < 20000; ++i) dev.next_sample(bytes);
    return bytes;
}

void BM_SerialDecode(benchmark::State& state) {
    const auto bytes = serial_stream(state.range(0) / 100.0);
    uint64_t samples = 0;
    for (auto _ : state) {
        serial::FrameDecoder d;
        d.feed(
            bytes,
            [&](const serial::Frame& f) {
                if (auto s = serial::decode_sample(f.payload)) samples += s->left.valid;
            },
            [](serial::FrameDecoder::Reject) {});
        benchmark::DoNotOptimize(samples);
    }
    state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * bytes.size()));
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * 20000));
}
BENCHMARK(BM_SerialDecode)->Arg(0)->Arg(30)->Unit(benchmark::kMillisecond);

void BM_GazepointDecode(benchmark::State& state) {
    std::string text;
    sim::SimTracker sim(sim::SimConfig{});
    for (int i = 0; i < 20000; ++i) {
        const auto f = sim.next();
        char buf[512];
        std::snprintf(
            buf, sizeof buf,
            "<REC CNT=\"%d\" TIME_TICK=\"%llu\" LPOGX=\"%.5f\" LPOGY=\"%.5f\" LPOGV=\"1\" "
            "RPOGX=\"%.5f\" RPOGY=\"%.5f\" RPOGV=\"1\" BPOGX=\"0.5\" BPOGY=\"0.5\" "
            "BPOGV=\"1\" LPUPILD=\"0.003500\" LPUPILV=\"1\" RPUPILD=\"0.003600\" "
            "RPUPILV=\"1\" />\r\n",
            i, static_cast<unsigned long long>(f.raw.device_ticks), f.raw.left.x, f.raw.left.y,
            f.raw.right.x, f.raw.right.y);
        text += buf;
    }
    uint64_t samples = 0;
    for (auto _ : state) {
        gazepoint::ElementStream s;
        s.feed(text, [&](const gazepoint::Element& e) {
            std::optional<uint64_t> cnt;
            samples += gazepoint::decode_record(e, gazepoint::ServerClock{1e7},
                                                gazepoint::GazeSource::kEyes, &cnt)
                           .has_value();
        });
        benchmark::DoNotOptimize(samples);
    }
    state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * text.size()));
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * 20000));
}
BENCHMARK(BM_GazepointDecode)->Unit(benchmark::kMillisecond);

void BM_SimTrackerNext(benchmark::State& state) {
    sim::SimConfig c;
    c.rate_hz = 2000;
    sim::SimTracker sim(c);
    for (auto _ : state) benchmark::DoNotOptimize(sim.next());
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}
BENCHMARK(BM_SimTrackerNext);

}  // namespace

BENCHMARK_MAIN();
