// HID page 0x12 costs: descriptor parse + tracker location, and one Tracking Data report decode.
// Run: build-*/tests/hid/hid_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only
#include <benchmark/benchmark.h>

#include "hid/session.hpp"
#include "tracker_descriptors.hpp"

using namespace fovea::drivers::hid;
using fovea::test::DescriptorBuilder;
using fovea::test::kMax32;
using fovea::test::kMin32;
using fovea::test::ReportBuilder;

namespace {

// The reference eye tracker layout (see tracker_test.cpp descriptor A) plus a head tracker.
std::vector<uint8_t> descriptor() {
    DescriptorBuilder d;
    d.usage_page(0x12).usage(0x01).collection(1);
    fovea::test::reference_tracking_data(d);
    fovea::test::status_feature(d);
    d.end_collection();
    d.usage(0x02).collection(1).usage(0x10).collection(2).report_id(0x20);
    d.logical_min(kMin32).logical_max(kMax32).report_size(32).report_count(3);
    fovea::test::xyz_point(d, 0x27);
    fovea::test::head_rotation_mrad(d);
    d.end_collection().end_collection();
    return d.bytes;
}

void BM_ParseAndLocate(benchmark::State& state) {
    const auto bytes = descriptor();
    for (auto _ : state) {
        auto s = TrackerSession::create(bytes, 531000, 299000);
        benchmark::DoNotOptimize(s);
    }
    state.counters["descriptor_bytes"] = static_cast<double>(bytes.size());
}
BENCHMARK(BM_ParseAndLocate);

// Decodes `report` against descriptor() over and over; both outputs are kept from the optimiser.
void decode_report(benchmark::State& state, const std::vector<uint8_t>& report) {
    auto s = TrackerSession::create(descriptor(), 531000, 299000);
    fovea::gaze::RawSample sample;
    fovea::drivers::HeadPose pose;
    for (auto _ : state) {
        auto out = s->on_report(report, 1, 0, sample, pose);
        benchmark::DoNotOptimize(out);
        benchmark::DoNotOptimize(sample);
        benchmark::DoNotOptimize(pose);
    }
}

void BM_DecodeGazeReport(benchmark::State& state) {
    ReportBuilder rep(43, 0x10);
    rep.put(24, 64, 123456789)
        .put(88, 32, 265500)
        .put(120, 32, 74750)
        .put(152, 32, 1000)
        .put(184, 32, 1000)
        .put(216, 32, 600000)
        .put(248, 32, 1000)
        .put(280, 32, 1000)
        .put(312, 32, 600000);
    decode_report(state, rep.data);
}
BENCHMARK(BM_DecodeGazeReport);

void BM_DecodeHeadReport(benchmark::State& state) {
    ReportBuilder rep(18, 0x20);
    rep.put(0, 32, 1000)
        .put(32, 32, 2000)
        .put(64, 32, 650000)
        .put(96, 16, 100)
        .put(112, 16, 200)
        .put(128, 16, 300);
    decode_report(state, rep.data);
}
BENCHMARK(BM_DecodeHeadReport);

}  // namespace

BENCHMARK_MAIN();
