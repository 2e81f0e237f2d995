// What XR_APILAYER_FOVEA_eye_gaze adds to xrLocateSpace, measured through the vendored Monado:
// rounds alternate between the layer disabled (DISABLE_XR_APILAYER_FOVEA_eye_gaze) and enabled,
// each a fresh OpenXR instance and session with a real fovead (simulated tracker) feeding the
// ring. Per round and case, every call is timed; the table shows p50/p99 over all rounds and the
// cost added against the same call without the layer, plus the gaze's age at the predicted
// display time. The frame's first gaze call also reads what fovead published since the previous
// frame (1000 Hz / 20 Hz null compositor = 50 records) and is shown apart. Writes a CSV with one
// row per round and case.
//   openxr_locate_bench [--rounds N] [--frames N] [--calls N] [--csv FILE]
// Needs FOVEA_MONADO_RUNTIME_JSON (tests/openxr/build_monado.sh prints it).
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "../support/child_process.hpp"
#include "fovea/client.h"
#include "headless_session.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

struct Samples {
    std::map<std::string, std::vector<double>> us;  // per case, every call
    std::vector<double> age_ms;
};

// One instance + session; `calls` of each case per frame for `frames` frames.
bool run_round(bool layer, int frames, int calls, const std::string& instance, Samples& out,
               std::string& error) {
    if (layer)
        unsetenv("DISABLE_XR_APILAYER_FOVEA_eye_gaze");
    else
        setenv("DISABLE_XR_APILAYER_FOVEA_eye_gaze", "1", 1);
    auto s = fovea::xr::HeadlessSession::create({"fovea openxr_locate_bench", true});
    if (!s) {
        error = s.error().message;
        return false;
    }
    fovea::xr::HeadlessSession& x = **s;
    if (layer != x.eye_gaze()) {
        error = layer ? "the layer did not provide eye gaze" : "eye gaze without the layer";
        return false;
    }
    if (auto f = x.wait_until_focused(20000); !f) {
        error = f.error().message;
        return false;
    }
    fovea_client* ring = nullptr;
    fovea_client_open(instance.c_str(), FOVEA_STREAM_GAZE, &ring);
    const char* mode = layer ? "layer" : "no layer";
    for (int i = 0; i < frames; ++i) {
        auto f = x.begin_frame();
        if (!f) {
            error = f.error().message;
            fovea_client_close(&ring);
            return false;
        }
        const auto timed = [&](const char* what, auto&& call) {
            const auto t0 = Clock::now();
            call();
            out.us[std::string(mode) + ": " + what].push_back(
                std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        };
        const XrTime t = f->display_time;
        // The runtime's first locate at a new time costs more than the repeats; both modes pay it.
        timed("VIEW in LOCAL, first in frame",
              [&] { x.locate(x.view_space(), x.local_space(), t); });
        if (layer) {
            // The frame's first gaze call reads what fovead published since the last frame.
            timed("gaze, first in frame", [&] { x.locate_gaze(x.view_space(), t); });
            fovea_gaze_record r{};
            if (ring && fovea_client_latest(ring, &r) == FOVEA_OK)
                out.age_ms.push_back((x.to_monotonic_ns(t) - r.t_capture_ns) / 1e6);
        }
        for (int c = 0; c < calls; ++c) {  // round robin, so load drifts hit every case alike
            timed("VIEW in LOCAL", [&] { x.locate(x.view_space(), x.local_space(), t); });
            if (!layer) continue;
            timed("gaze in VIEW", [&] { x.locate_gaze(x.view_space(), t); });
            timed("gaze in LOCAL", [&] { x.locate_gaze(x.local_space(), t); });
        }
        if (auto e = x.end_frame(*f); !e) {
            error = e.error().message;
            fovea_client_close(&ring);
            return false;
        }
    }
    fovea_client_close(&ring);
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    int rounds = 3, frames = 20, calls = 100;
    std::string csv = "openxr_locate_bench.csv";
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--rounds")
            rounds = std::atoi(argv[i + 1]);
        else if (a == "--frames")
            frames = std::atoi(argv[i + 1]);
        else if (a == "--calls")
            calls = std::atoi(argv[i + 1]);
        else if (a == "--csv")
            csv = argv[i + 1];
        else {
            std::fprintf(stderr, "unknown option %s\n", argv[i]);
            return 2;
        }
    }
    const char* rt = std::getenv("FOVEA_MONADO_RUNTIME_JSON");
    if (!rt || !fs::exists(rt)) {
        std::fprintf(stderr,
                     "openxr_locate_bench: set FOVEA_MONADO_RUNTIME_JSON to the runtime "
                     "manifest tests/openxr/build_monado.sh prints\n");
        return 77;
    }
    const std::string instance = "xrbench" + std::to_string(getpid());
    const fs::path dir = fs::temp_directory_path() / ("fv-" + instance);
    fs::create_directories(dir);
    std::ofstream(dir / "fovead.toml") << "display_profile = \"generic-2x1440x1600\"\n";
    setenv("FOVEA_RUNTIME_DIR", dir.c_str(), 1);
    setenv("XR_RUNTIME_JSON", rt, 1);
    setenv("XRT_COMPOSITOR_NULL", "1", 1);
    setenv("XDG_DATA_HOME", FOVEA_OPENXR_LAYER_XDG_DATA_HOME, 1);
    setenv("FOVEA_INSTANCE", instance.c_str(), 1);
    setenv("FOVEA_OPENXR_LOG", "quiet", 1);
    auto daemon = fovea::testing::spawn_logged(
        fovea::testing::kFoveadBinary,
        {"--instance", instance, "--config", (dir / "fovead.toml").string(), "--log-level", "warn"},
        (dir / "fovead.out").string(), (dir / "fovead.err").string());
    std::this_thread::sleep_for(std::chrono::milliseconds(500));

    std::ofstream out(csv);
    out << "round,case,calls,p50_us,p99_us,max_us\n";
    Samples all;
    for (int r = 0; r < rounds; ++r) {
        for (bool layer : {false, true}) {  // interleaved: load drifts hit both alike
            Samples one;
            std::string error;
            if (!run_round(layer, frames, calls, instance, one, error)) {
                std::fprintf(stderr, "openxr_locate_bench: %s\n", error.c_str());
                fs::remove_all(dir);
                return 1;
            }
            for (auto& [name, v] : one.us) {
                out << r << ',' << name << ',' << v.size() << ',' << quantile(v, 0.5) << ','
                    << quantile(v, 0.99) << ',' << quantile(v, 1.0) << '\n';
                auto& dst = all.us[name];
                dst.insert(dst.end(), v.begin(), v.end());
            }
            all.age_ms.insert(all.age_ms.end(), one.age_ms.begin(), one.age_ms.end());
        }
    }
    // Each case against the same call without the layer; the ring read against the runtime's
    // first call of a frame (what an app pays on top of it, once per frame).
    const auto base = [&](const std::string& name, double q) {
        const bool first = name.find("first in frame") != std::string::npos;
        return quantile(
            all.us[first ? "no layer: VIEW in LOCAL, first in frame" : "no layer: VIEW in LOCAL"],
            q);
    };
    std::printf(
        "xrLocateSpace through Monado, %d rounds x %d frames x %d calls per case "
        "(load %.1f)\n",
        rounds, frames, calls, [] {
            double l = 0;
            std::ifstream("/proc/loadavg") >> l;
            return l;
        }());
    std::printf("%-38s %10s %10s %12s %12s\n", "case", "p50 us", "p99 us", "added p50",
                "added p99");
    for (const char* name :
         {"no layer: VIEW in LOCAL", "layer: VIEW in LOCAL", "layer: gaze in VIEW",
          "layer: gaze in LOCAL", "no layer: VIEW in LOCAL, first in frame",
          "layer: VIEW in LOCAL, first in frame", "layer: gaze, first in frame"}) {
        const auto& v = all.us[name];
        const double p50 = quantile(v, 0.5), p99 = quantile(v, 0.99);
        std::printf("%-38s %10.2f %10.2f %12.2f %12.2f\n", name, p50, p99, p50 - base(name, 0.5),
                    p99 - base(name, 0.99));
        out << "all," << name << ',' << v.size() << ',' << p50 << ',' << p99 << ','
            << quantile(v, 1.0) << '\n';
    }
    std::printf(
        "gaze age at the predicted display time: median %.1f ms, p95 %.1f ms (%zu frames)\n",
        quantile(all.age_ms, 0.5), quantile(all.age_ms, 0.95), all.age_ms.size());
    out << "all,gaze_age_ms," << all.age_ms.size() << ',' << quantile(all.age_ms, 0.5) << ','
        << quantile(all.age_ms, 0.99) << ',' << quantile(all.age_ms, 1.0) << '\n';
    std::printf("CSV: %s\n", csv.c_str());
    daemon.reset();
    fs::remove_all(dir);
    return 0;
}
