#include "fovea/gaze/target_dwell.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "median.hpp"

namespace fovea::gaze {

namespace {

constexpr int kMaxDwells = 32;

bool tracked(const EyeSample& e) {
    return e.valid && std::isfinite(e.x) && std::isfinite(e.y) && std::fabs(e.x) < 1e6 &&
           std::fabs(e.y) < 1e6;
}

}  // namespace

TargetDwell target_dwell(const std::vector<TargetSample>& samples, bool use_left, bool use_right,
                         const TargetDwellRules& rules, const TargetSample* previous) {
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

    // The dwell that ends at clean sample `last`: where the eyes were over its final min_dwell_s
    // (at least 3 samples) and the noise there, then back to where the gaze left that place for
    // two samples in a row (one is a spike).
    struct Dwell {
        size_t start = 0;                // the clean sample where the gaze entered it
        std::array<double, 4> anchor{};  // x, y per eye; NaN for an eye with no sample
        double radius[2] = {0, 0};
        double seconds = 0;        // from the first sample after settling
        std::vector<size_t> keep;  // its samples after settling, within the radius
    };
    const auto dwell_ending_at = [&](size_t last) {
        Dwell d;
        const int64_t end_t = samples[clean[last]].t_ns;
        size_t tail = last;
        while (tail > 0 && (end_t - samples[clean[tail - 1]].t_ns <= ns(rules.min_dwell_s) ||
                            last + 1 - tail < 3)) {
            --tail;
        }
        for (int e = 0; e < 2; ++e) {
            std::vector<double> xs, ys;
            double s2s = 0;
            int steps = 0;
            for (size_t k = tail; k <= last; ++k) {
                const EyeSample* s = at(k, e);
                if (!s) continue;
                if (k > tail && at(k - 1, e)) {
                    s2s += std::pow(s->x - xs.back(), 2) + std::pow(s->y - ys.back(), 2);
                    ++steps;
                }
                xs.push_back(s->x);
                ys.push_back(s->y);
            }
            d.anchor[2 * e] = xs.empty() ? kNaN : detail::median(xs);
            d.anchor[2 * e + 1] = ys.empty() ? kNaN : detail::median(ys);
            d.radius[e] = rules.dwell_radius_deg;
            if (steps > 0) {
                d.radius[e] =
                    std::max(d.radius[e], rules.noise_radius_factor * std::sqrt(s2s / steps / 2));
            }
        }
        const auto off = [&](size_t k) {
            for (int e = 0; e < 2; ++e) {
                const EyeSample* s = at(k, e);
                if (!s || !std::isfinite(d.anchor[2 * e])) continue;
                if (std::hypot(s->x - d.anchor[2 * e], s->y - d.anchor[2 * e + 1]) > d.radius[e])
                    return true;
            }
            return false;
        };
        size_t first = last;
        while (first > 0 && !(off(first - 1) && (first < 2 || off(first - 2)))) --first;
        d.start = first;
        if (first > 0) {
            const int64_t settled_t = samples[clean[first]].t_ns + ns(rules.settle_after_saccade_s);
            while (first < last && samples[clean[first]].t_ns < settled_t) ++first;
        }
        d.seconds = (end_t - samples[clean[first]].t_ns) * 1e-9;
        for (size_t k = first; k <= last; ++k) {
            if (!off(k)) d.keep.push_back(clean[k]);
        }
        return d;
    };
    // Where the eyes were at the previous target, if known and within this dwell's radius for
    // every eye both have.
    const auto at_previous = [&](const Dwell& d) {
        if (!previous) return false;
        bool compared = false;
        for (int e = 0; e < 2; ++e) {
            const EyeSample& p = e == 0 ? previous->left : previous->right;
            if (!(e == 0 ? use_left : use_right) || !tracked(p) || !std::isfinite(d.anchor[2 * e]))
                continue;
            if (std::hypot(p.x - d.anchor[2 * e], p.y - d.anchor[2 * e + 1]) > d.radius[e])
                return false;
            compared = true;
        }
        return compared;
    };

    // The final dwell; knowing where the eyes came from, the longest dwell not there (the eyes
    // may leave before the collection ends: a glance, or anticipating the next target).
    const Dwell final_dwell = dwell_ending_at(clean.size() - 1);
    const Dwell* chosen = &final_dwell;
    Dwell longest;
    if (previous) {
        bool found = false;
        // Bounded: a gaze that never rests would otherwise cost a walk per sample.
        Dwell d = final_dwell;
        for (int dwells = 0; dwells < kMaxDwells; ++dwells) {
            if (!at_previous(d) && d.seconds >= rules.min_dwell_s &&
                (!found || d.seconds > longest.seconds)) {
                longest = d;
                found = true;
            }
            if (d.start == 0) break;
            d = dwell_ending_at(d.start - 1);
        }
        if (found) chosen = &longest;  // else nothing but the previous target: the final dwell
    }
    out.keep = chosen->keep;
    out.dwell_s = chosen->seconds;
    if (out.dwell_s < rules.min_dwell_s) out.keep.clear();
    out.unsettled = clean.size() - out.keep.size();
    for (int e = 0; e < 2; ++e) {
        EyeSample& a = e == 0 ? out.at.left : out.at.right;
        a.x = chosen->anchor[2 * e];
        a.y = chosen->anchor[2 * e + 1];
        a.valid = !out.keep.empty() && std::isfinite(a.x) && std::isfinite(a.y);
    }
    return out;
}

}  // namespace fovea::gaze
