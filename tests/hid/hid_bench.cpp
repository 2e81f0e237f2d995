// HID page 0x12 costs: descriptor parse + tracker location, and one Tracking Data report decode.
// Run: build-*/tests/hid/hid_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only
#include <benchmark/benchmark.h>

#include "hid/session.hpp"
#include "hid_builders.hpp"

using namespace fovea::drivers::hid;
using fovea::test::DescriptorBuilder;
using fovea::test::kConstVarAbs;
using fovea::test::kDataVarAbs;
using fovea::test::ReportBuilder;

namespace {

// The reference eye tracker layout (see tracker_test.cpp descriptor A) plus a head tracker.
std::vector<uint8_t> descriptor() {
    DescriptorBuilder d;
    d.usage_page(0x12).usage(0x01).collection(1).usage(0x10).collection(2).report_id(0x10);
    d.logical_min(0).logical_max(255).report_size(8).report_count(3).input(kConstVarAbs);
    d.usage(0x20).report_count(8).input(kDataVarAbs);
    d.report_count(1).report_size(32).logical_min(-2147483647 - 1).logical_max(2147483647);
    d.usage(0x24)
        .collection(0)
        .report_count(2)
        .usage(0x21)
        .usage(0x22)
        .input(kDataVarAbs)
        .end_collection();
    for (uint16_t eye : {0x25, 0x26})
        d.usage(eye)
            .collection(0)
            .report_count(3)
            .usage(0x21)
            .usage(0x22)
            .usage(0x23)
            .input(kDataVarAbs)
            .end_collection();
    d.end_collection();
    d.usage(0x13)
        .collection(2)
        .report_id(0x13)
        .report_size(8)
        .report_count(1)
        .logical_min(0)
        .logical_max(4)
        .usage(0x301)
        .feature(kDataVarAbs)
        .report_size(16)
        .logical_max(0x7FFF)
        .usage(0x300)
        .feature(kDataVarAbs)
        .end_collection();
    d.end_collection();
    d.usage(0x02).collection(1).usage(0x10).collection(2).report_id(0x20);
    d.logical_min(-2147483647 - 1).logical_max(2147483647).report_size(32).report_count(3);
    d.usage(0x27)
        .collection(0)
        .usage(0x21)
        .usage(0x22)
        .usage(0x23)
        .input(kDataVarAbs)
        .end_collection();
    d.unit(0x12)
        .unit_exponent(-3)
        .logical_min(-3142)
        .logical_max(3142)
        .report_size(16)
        .report_count(3)
        .usage_min(0x29)
        .usage_max(0x2B)
        .input(kDataVarAbs);
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

void BM_DecodeGazeReport(benchmark::State& state) {
    auto s = TrackerSession::create(descriptor(), 531000, 299000);
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
    fovea::gaze::RawSample sample;
    fovea::drivers::HeadPose pose;
    for (auto _ : state) {
        auto out = s->on_report(rep.data, 1, 0, sample, pose);
        benchmark::DoNotOptimize(out);
        benchmark::DoNotOptimize(sample);
    }
}
BENCHMARK(BM_DecodeGazeReport);

void BM_DecodeHeadReport(benchmark::State& state) {
    auto s = TrackerSession::create(descriptor(), 531000, 299000);
    ReportBuilder rep(18, 0x20);
    rep.put(0, 32, 1000)
        .put(32, 32, 2000)
        .put(64, 32, 650000)
        .put(96, 16, 100)
        .put(112, 16, 200)
        .put(128, 16, 300);
    fovea::gaze::RawSample sample;
    fovea::drivers::HeadPose pose;
    for (auto _ : state) {
        auto out = s->on_report(rep.data, 1, 0, sample, pose);
        benchmark::DoNotOptimize(out);
        benchmark::DoNotOptimize(pose);
    }
}
BENCHMARK(BM_DecodeHeadReport);

}  // namespace

BENCHMARK_MAIN();
