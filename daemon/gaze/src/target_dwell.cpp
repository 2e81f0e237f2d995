#include "fovea/gaze/target_dwell.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace fovea::gaze {

namespace {

bool tracked(const EyeSample& e) {
    return e.valid && std::isfinite(e.x) && std::isfinite(e.y) && std::fabs(e.x) < 1e6 &&
           std::fabs(e.y) < 1e6;
}

double median(std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

}  // namespace

TargetDwell target_dwell(const std::vector<TargetSample>& samples, bool use_left, bool use_right,
                         const TargetDwellRules& rules) {
    TargetDwell out;
    const auto eye = [&](size_t i, int e) -> const EyeSample* {
        const EyeSample& s = e == 0 ? samples[i].left : samples[i].right;
        return (e == 0 ? use_left : use_right) && tracked(s) ? &s : nullptr;
    };

    // Lost samples, then the lid's artefacts around them.
    std::vector<int64_t> lost_t;
    for (size_t i = 0; i < samples.size(); ++i) {
        if (!eye(i, 0) && !eye(i, 1)) lost_t.push_back(samples[i].t_ns);
    }
    out.lost = lost_t.size();
    std::sort(lost_t.begin(), lost_t.end());
    const auto ns = [](double s) { return static_cast<int64_t>(std::llround(s * 1e9)); };
    const int64_t before_ns = ns(rules.lid_before_s), after_ns = ns(rules.lid_after_s);
    std::vector<size_t> clean;
    for (size_t i = 0; i < samples.size(); ++i) {
        if (!eye(i, 0) && !eye(i, 1)) continue;
        const int64_t t = samples[i].t_ns;
        const auto it = std::lower_bound(lost_t.begin(), lost_t.end(), t - after_ns);
        if (it != lost_t.end() && *it <= t + before_ns) {
            ++out.lid;
        } else {
            clean.push_back(i);
        }
    }
    if (clean.empty()) return out;

    // Eye e of the k-th clean sample, or null when it is not used or not tracked.
    const auto at = [&](size_t k, int e) { return eye(clean[k], e); };

    // Where the eyes ended up: the median of the final min_dwell_s (at least 3 samples), and
    // the noise there.
    const int64_t end_t = samples[clean.back()].t_ns;
    size_t tail = clean.size() - 1;
    while (tail > 0 && (end_t - samples[clean[tail - 1]].t_ns <= ns(rules.min_dwell_s) ||
                        clean.size() - tail < 3)) {
        --tail;
    }
    std::array<double, 4> anchor;  // x, y per eye; NaN for an eye with no sample there
    double radius[2] = {rules.dwell_radius_deg, rules.dwell_radius_deg};
    for (int e = 0; e < 2; ++e) {
        std::vector<double> xs, ys;
        double s2s = 0;
        int steps = 0;
        for (size_t k = tail; k < clean.size(); ++k) {
            const EyeSample* s = at(k, e);
            if (!s) continue;
            if (k > tail && at(k - 1, e)) {
                s2s += std::pow(s->x - xs.back(), 2) + std::pow(s->y - ys.back(), 2);
                ++steps;
            }
            xs.push_back(s->x);
            ys.push_back(s->y);
        }
        anchor[2 * e] = xs.empty() ? kNaN : median(xs);
        anchor[2 * e + 1] = ys.empty() ? kNaN : median(ys);
        if (steps > 0)
            radius[e] = std::max(radius[e], rules.noise_radius_factor * std::sqrt(s2s / steps / 2));
    }
    const auto off = [&](size_t k) {
        for (int e = 0; e < 2; ++e) {
            const EyeSample* s = at(k, e);
            if (!s || !std::isfinite(anchor[2 * e])) continue;
            if (std::hypot(s->x - anchor[2 * e], s->y - anchor[2 * e + 1]) > radius[e]) return true;
        }
        return false;
    };

    // Walk back to where the gaze left the dwell for two samples in a row (one is a spike).
    size_t first = clean.size() - 1;
    while (first > 0 && !(off(first - 1) && (first < 2 || off(first - 2)))) --first;
    if (first > 0) {
        const int64_t settled_t = samples[clean[first]].t_ns + ns(rules.settle_after_saccade_s);
        while (first + 1 < clean.size() && samples[clean[first]].t_ns < settled_t) ++first;
    }
    for (size_t k = first; k < clean.size(); ++k) {
        if (!off(k)) out.keep.push_back(clean[k]);
    }
    out.dwell_s = (end_t - samples[clean[first]].t_ns) * 1e-9;
    if (out.dwell_s < rules.min_dwell_s) out.keep.clear();
    out.unsettled = clean.size() - out.keep.size();
    return out;
}

}  // namespace fovea::gaze
