// ns per sample for each gaze stage and the whole chain (target: <= 2 us per binocular sample
// for filter + detect + predict). Run: gaze_bench [--benchmark_repetitions=5]
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "fovea/gaze/pipeline.hpp"
#include "synthetic.hpp"

namespace fovea::gaze {
namespace {

const test::Synthetic& data() {
    static const test::Synthetic s = test::make_synthetic(1000.0);
    return s;
}

std::vector<RawSample> raw() {
    const auto& s = data();
    DisplayGeometry d;
    std::vector<RawSample> out(s.in.size());
    for (size_t i = 0; i < out.size(); ++i) {
        out[i].left.valid = out[i].right.valid = s.in[i].valid;
        if (s.in[i].valid) {
            d.to_normalized(s.in[i].x_deg, s.in[i].y_deg, out[i].left.x, out[i].left.y);
            out[i].right = out[i].left;
            out[i].right.x += 0.001;
        }
    }
    return out;
}

void BM_OneEuroBinocular(benchmark::State& st) {
    OneEuroFilter f[4];
    const auto& s = data();
    size_t i = 0;
    double t = 0;
    for (auto _ : st) {
        const auto& in = s.in[i];
        t += 0.001;
        for (auto& k : f) benchmark::DoNotOptimize(k.filter(in.x_deg, t));
        if (++i == s.in.size()) i = 0;
    }
    st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_OneEuroBinocular);

void BM_KalmanBinocular(benchmark::State& st) {
    KalmanCv f[4];
    const auto& s = data();
    size_t i = 0;
    double t = 0;
    for (auto _ : st) {
        t += 0.001;
        for (auto& k : f) benchmark::DoNotOptimize(k.filter(s.in[i].x_deg, t));
        if (++i == s.in.size()) i = 0;
    }
    st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_KalmanBinocular);

void BM_ClockSync(benchmark::State& st) {
    ClockSync c(DeviceClock{32, 1e6});
    uint64_t i = 0;
    for (auto _ : st) {
        benchmark::DoNotOptimize(
            c.update(i * 1000, static_cast<int64_t>(i) * 1'000'000 + (i * 7919) % 3'000'000));
        ++i;
    }
    st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_ClockSync);

void BM_DetectorOnline(benchmark::State& st) {
    const auto& s = data();
    EventDetector d({}, 1000.0, DetectorMode::kOnline);
    DetectorOutput o;
    size_t i = 0;
    double t0 = 0;
    for (auto _ : st) {
        DetectorInput in = s.in[i];
        in.t_s += t0;
        d.push(in);
        while (d.pop(o)) benchmark::DoNotOptimize(o);
        if (++i == s.in.size()) {
            i = 0;
            t0 += s.in.back().t_s + 0.001;
        }
    }
    st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_DetectorOnline);

void BM_LandingPredictCall(benchmark::State& st) {
    LandingPredictor p;
    const double amp = 10, dur = p.duration_s(amp);
    std::vector<double> t, x, y;
    for (double u = 0; u < 0.5 * dur; u += 0.001) {
        t.push_back(u);
        x.push_back(amp * p.profile(u / dur, amp));
        y.push_back(0);
    }
    for (auto _ : st) benchmark::DoNotOptimize(p.predict(t, x, y));
    st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_LandingPredictCall);

// Whole chain per binocular sample: clock + calibration-free filter + detect + predict.
void BM_PipelineBinocular(benchmark::State& st) {
    const auto r = raw();
    PipelineConfig c;
    c.nominal_rate_hz = 1000.0;
    c.clock = DeviceClock{64, 1e6};
    c.filter = static_cast<FilterKind>(st.range(0));
    Pipeline p(c);
    std::vector<GazeSample> out;
    uint64_t i = 0;
    for (auto _ : st) {
        RawSample s = r[i % r.size()];
        s.device_ticks = i * 1000;
        s.t_receive_ns = static_cast<int64_t>(i) * 1'000'000 + 100'000;
        p.process(s, out);
        benchmark::DoNotOptimize(out.data());
        ++i;
    }
    st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_PipelineBinocular)
    ->Arg(static_cast<int>(FilterKind::kOneEuro))
    ->Arg(static_cast<int>(FilterKind::kKalman));

}  // namespace
}  // namespace fovea::gaze

BENCHMARK_MAIN();
