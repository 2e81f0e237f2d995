#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "fovea/demo/demo.hpp"

namespace fovea::demo {

GazeTrace GazeTrace::scripted(double duration_s, uint64_t seed, const vk::EyeDisplay& d) {
    GazeTrace tr;
    uint64_t s = seed * 6364136223846793005ull + 1442695040888963407ull;
    auto uniform = [&s] {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(s >> 11) * (1.0 / 9007199254740992.0);
    };
    const double ppd = d.pixels_per_degree();
    const double step = 0.002;  // 500 Hz
    double t = 0.0, x = 0.5, y = 0.5;
    while (t < duration_s) {
        // Fixation with small noise around (x, y).
        const double fix_end = t + 0.2 + 0.25 * uniform();
        for (; t < fix_end && t < duration_s; t += step) {
            Sample smp{t, {}};
            smp.gaze.x = static_cast<float>(x + (uniform() - 0.5) * 0.1 * ppd / d.width_px);
            smp.gaze.y = static_cast<float>(y + (uniform() - 0.5) * 0.1 * ppd / d.height_px);
            smp.gaze.uncertainty_deg = 0.5f;
            smp.gaze.age_s = 0.02f;
            tr.samples_.push_back(smp);
        }
        // Saccade to a new target in the central 80 % of the screen.
        const double nx = 0.1 + 0.8 * uniform(), ny = 0.1 + 0.8 * uniform();
        const double amp = std::hypot((nx - x) * d.width_px, (ny - y) * d.height_px) / ppd;
        const double dur = (2.2 * amp + 21.0) * 1e-3;
        const double t0 = t;
        for (; t < t0 + dur && t < duration_s; t += step) {
            const double u = (t - t0) / dur;
            const double p = u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);  // minimum jerk
            Sample smp{t, {}};
            smp.gaze.x = static_cast<float>(x + (nx - x) * p);
            smp.gaze.y = static_cast<float>(y + (ny - y) * p);
            smp.gaze.uncertainty_deg = 0.5f;
            smp.gaze.age_s = 0.02f;
            smp.gaze.in_saccade = true;
            smp.gaze.landing_valid = u > 0.3;  // predictors need part of the saccade
            smp.gaze.landing_x = static_cast<float>(nx);
            smp.gaze.landing_y = static_cast<float>(ny);
            smp.gaze.landing_uncertainty_deg = static_cast<float>(0.1 * amp + 0.5);
            tr.samples_.push_back(smp);
        }
        x = nx;
        y = ny;
    }
    return tr;
}

Result<GazeTrace> GazeTrace::load(const std::string& path, size_t* dropped_lines) {
    std::ifstream in(path);
    if (!in) return make_error("cannot open gaze trace " + path);
    GazeTrace tr;
    std::string line;
    size_t dropped = 0, lineno = 0;
    while (std::getline(in, line)) {
        ++lineno;
        if (line.empty() || line[0] == '#') continue;
        std::vector<double> v;
        std::stringstream ss(line);
        std::string cell;
        bool ok = true;
        while (std::getline(ss, cell, ',')) {
            try {
                size_t used = 0;
                v.push_back(std::stod(cell, &used));
            } catch (...) {
                ok = false;
                break;
            }
        }
        if (!ok || v.size() < 3) {
            if (lineno > 1) ++dropped;  // the first line may be a header
            continue;
        }
        Sample s{v[0], {}};
        s.gaze.x = static_cast<float>(v[1]);
        s.gaze.y = static_cast<float>(v[2]);
        if (v.size() > 3) s.gaze.in_saccade = static_cast<int>(v[3]) == 2;
        if (v.size() > 5 && std::isfinite(v[4]) && std::isfinite(v[5])) {
            s.gaze.landing_valid = true;
            s.gaze.landing_x = static_cast<float>(v[4]);
            s.gaze.landing_y = static_cast<float>(v[5]);
        }
        if (v.size() > 6) s.gaze.landing_uncertainty_deg = static_cast<float>(v[6]);
        if (v.size() > 7) s.gaze.uncertainty_deg = static_cast<float>(v[7]);
        if (!tr.samples_.empty() && !(s.t_s >= tr.samples_.back().t_s)) {
            ++dropped;  // time must not go backwards
            continue;
        }
        tr.samples_.push_back(s);
    }
    if (dropped_lines) *dropped_lines = dropped;
    if (tr.samples_.empty()) return make_error("gaze trace " + path + " has no valid samples");
    return tr;
}

vk::GazeState GazeTrace::at(double t) const {
    if (samples_.empty()) return {};
    auto it = std::upper_bound(samples_.begin(), samples_.end(), t,
                               [](double v, const Sample& s) { return v < s.t_s; });
    if (it == samples_.begin()) return samples_.front().gaze;
    return std::prev(it)->gaze;
}

}  // namespace fovea::demo
