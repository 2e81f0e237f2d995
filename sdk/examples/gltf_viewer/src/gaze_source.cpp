#include "gltf_viewer/gaze_source.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <vector>

#include "fovea/client.hpp"

namespace gltfv {
namespace {

class FixedGaze final : public GazeSource {
public:
    FixedGaze(float x, float y) : x_(x), y_(y) {}
    fovea::vk::GazeState at(double) override {
        fovea::vk::GazeState g;
        g.x = x_;
        g.y = y_;
        return g;
    }
    std::string describe() const override {
        char b[64];
        std::snprintf(b, sizeof(b), "fixed gaze (%.2f, %.2f)", x_, y_);
        return b;
    }

private:
    float x_, y_;
};

class TraceGaze final : public GazeSource {
public:
    struct Sample {
        double t;
        fovea::vk::GazeState g;
    };
    TraceGaze(std::vector<Sample> s, std::string path, size_t dropped)
        : samples_(std::move(s)), path_(std::move(path)), dropped_(dropped) {}
    fovea::vk::GazeState at(double t) override {
        const Sample* best = &samples_.front();
        for (const Sample& s : samples_) {  // nearest earlier sample
            if (s.t > t) break;
            best = &s;
        }
        return best->g;
    }
    std::string describe() const override {
        return "gaze trace " + path_ + " (" + std::to_string(samples_.size()) + " samples, " +
               std::to_string(dropped_) + " bad lines skipped)";
    }

private:
    std::vector<Sample> samples_;
    std::string path_;
    size_t dropped_;
};

class LiveGaze final : public GazeSource {
public:
    explicit LiveGaze(const std::string& instance) : client_(instance), instance_(instance) {}
    fovea::vk::GazeState at(double) override {
        timespec ts;
        clock_gettime(CLOCK_MONOTONIC, &ts);
        const int64_t now = int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec;
        const auto r = client_.latest();
        if (!r) {  // nothing published yet: NaN, which the Foveator resolves (centre, then held)
            fovea::vk::GazeState g;
            g.x = g.y = NAN;
            return g;
        }
        return fovea::vk::GazeState::from_record(*r, now);
    }
    std::string describe() const override { return "live gaze from fovead '" + instance_ + "'"; }

private:
    fovea::Client client_;
    std::string instance_;
};

}  // namespace

std::unique_ptr<GazeSource> make_gaze_source(const std::string& spec, std::string& error) {
    if (spec.empty() || spec == "centre" || spec == "center")
        return std::make_unique<FixedGaze>(0.5f, 0.5f);
    float x, y;
    char tail;
    if (std::sscanf(spec.c_str(), "%f,%f%c", &x, &y, &tail) == 2) {
        if (!std::isfinite(x) || !std::isfinite(y)) {
            error = "--gaze " + spec + ": coordinates must be finite";
            return nullptr;
        }
        return std::make_unique<FixedGaze>(x, y);
    }
    if (spec == "fovead" || spec.rfind("fovead:", 0) == 0) {
        const std::string instance = spec == "fovead" ? "default" : spec.substr(7);
        try {
            return std::make_unique<LiveGaze>(instance);
        } catch (const fovea::ClientError& e) {
            error = "--gaze " + spec + ": " + e.what() + " (is fovead running?)";
            return nullptr;
        }
    }
    std::ifstream in(spec);
    if (!in) {
        error = "--gaze " + spec + ": not centre, X,Y, fovead[:instance] or a readable trace file";
        return nullptr;
    }
    std::vector<TraceGaze::Sample> samples;
    size_t dropped = 0;
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
        std::stringstream ss(line);
        std::vector<double> v;
        std::string cell;
        bool ok = true;
        while (std::getline(ss, cell, ',')) {
            char* end = nullptr;
            const double d = std::strtod(cell.c_str(), &end);
            if (end == cell.c_str()) ok = false;
            v.push_back(d);
        }
        if (!ok || v.size() < 3 || !std::isfinite(v[0]) ||
            (!samples.empty() && v[0] < samples.back().t)) {
            ++dropped;
            continue;
        }
        TraceGaze::Sample s{v[0], {}};
        s.g.x = float(v[1]);  // NaN stays NaN: a blink the Foveator holds through
        s.g.y = float(v[2]);
        if (v.size() >= 7) {
            s.g.in_saccade = int(v[3]) == 2;
            s.g.landing_valid = std::isfinite(v[4]) && std::isfinite(v[5]);
            s.g.landing_x = float(v[4]);
            s.g.landing_y = float(v[5]);
            s.g.landing_uncertainty_deg = float(v[6]);
        }
        if (v.size() >= 8) s.g.uncertainty_deg = float(v[7]);
        samples.push_back(s);
    }
    if (samples.empty()) {
        error = "--gaze " + spec + ": no valid samples (t_s,x,y per line after a header)";
        return nullptr;
    }
    return std::make_unique<TraceGaze>(std::move(samples), spec, dropped);
}

}  // namespace gltfv
