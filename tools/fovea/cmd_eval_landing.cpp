// `fovea eval-landing DIR [--json]`: landing-point error of the in-flight saccade predictor on
// hand-labelled saccades > 2 deg, at 25/50/75 % of each saccade's labelled duration, against the
// naive "current position" baseline, and how well the predictor's own uncertainty radius
// covers its error (median radius, share of errors inside it).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "command.hpp"
#include "fovea/gaze/labelled.hpp"
#include "fovea/gaze/landing.hpp"

namespace fovea::cli {
namespace {

struct Options {
    std::string dir;
    bool json = false;
};

constexpr double kFractions[3] = {0.25, 0.50, 0.75};
constexpr double kMinAmplitude = 2.0;

struct Errors {
    std::vector<double> pred[3], naive[3];
    std::vector<double> radius[3];  // predictor's uncertainty where it made an estimate
    size_t covered[3] = {};         // ... and its error was inside that radius
};

double median(std::vector<double> v) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int run(const Options& o) {
    auto set = gaze::load_labelled_dir(o.dir);
    if (!set) {
        std::fprintf(stderr, "eval-landing: %s\n", set.error().message.c_str());
        return 1;
    }
    const gaze::LandingPredictor predictor;
    Errors all, big;
    size_t saccades = 0, skipped_invalid = 0;
    for (const auto& f : set->files) {
        const auto in = gaze::detector_input(f);
        const size_t n = f.labels.size();
        size_t i = 0;
        while (i < n) {
            if (f.labels[i] != gaze::Event::kSaccade) {
                ++i;
                continue;
            }
            size_t j = i;
            while (j < n && f.labels[j] == gaze::Event::kSaccade) ++j;
            const size_t a = i, b = j - 1;  // onset and last saccade sample
            i = j;
            bool valid = true;
            for (size_t k = a; k <= b; ++k) valid = valid && in[k].valid;
            if (!valid || b - a < 2) {
                if (!valid) ++skipped_invalid;
                continue;
            }
            const double lx = in[b].x_deg, ly = in[b].y_deg;
            const double amp = std::hypot(lx - in[a].x_deg, ly - in[a].y_deg);
            if (amp <= kMinAmplitude) continue;
            ++saccades;
            const double dur = in[b].t_s - in[a].t_s;
            std::vector<double> t, x, y;
            for (int q = 0; q < 3; ++q) {
                t.clear();
                x.clear();
                y.clear();
                for (size_t k = a; k <= b && in[k].t_s - in[a].t_s <= kFractions[q] * dur + 1e-9;
                     ++k) {
                    t.push_back(in[k].t_s - in[a].t_s);
                    x.push_back(in[k].x_deg);
                    y.push_back(in[k].y_deg);
                }
                const double naive = std::hypot(x.back() - lx, y.back() - ly);
                const gaze::LandingEstimate e_est = predictor.predict(t, x, y);
                // No estimate yet (too few samples): the predictor falls back to the position.
                const double err =
                    e_est.valid ? std::hypot(e_est.x_deg - lx, e_est.y_deg - ly) : naive;
                for (Errors* e : {&all, amp > 5.0 ? &big : nullptr}) {
                    if (!e) continue;
                    e->pred[q].push_back(err);
                    e->naive[q].push_back(naive);
                    if (e_est.valid) {
                        e->radius[q].push_back(e_est.uncertainty_deg);
                        e->covered[q] += err <= e_est.uncertainty_deg;
                    }
                }
            }
        }
    }
    auto coverage = [](const Errors& e, int q) {
        return e.radius[q].empty() ? NAN
                                   : static_cast<double>(e.covered[q]) /
                                         static_cast<double>(e.radius[q].size());
    };
    auto block = [&](const Errors& e) {
        nlohmann::json j;
        j["saccades"] = e.pred[0].size();
        for (int q = 0; q < 3; ++q) {
            const std::string key = std::to_string(static_cast<int>(kFractions[q] * 100));
            j[key]["predictor"] = median(e.pred[q]);
            j[key]["current"] = median(e.naive[q]);
            j[key]["uncertainty"] = median(e.radius[q]);
            j[key]["within_uncertainty"] = coverage(e, q);
        }
        return j;
    };
    if (o.json) {
        nlohmann::json j;
        j["median_error_deg"]["gt2"] = block(all);
        j["median_error_deg"]["gt5"] = block(big);
        j["saccades"] = saccades;
        j["skipped_invalid"] = skipped_invalid;
        std::printf("%s\n", j.dump().c_str());
        return 0;
    }
    std::printf(
        "eval-landing: %zu labelled saccades > %.0f deg (all coder files), %zu skipped "
        "(lost samples)\n",
        saccades, kMinAmplitude, skipped_invalid);
    std::printf("median landing error, deg      %8s %8s %8s\n", "25%", "50%", "75%");
    auto row = [](const char* name, const std::vector<double>* v) {
        std::printf("%-30s %8.2f %8.2f %8.2f\n", name, median(v[0]), median(v[1]), median(v[2]));
    };
    row("> 2 deg  predictor", all.pred);
    row("> 2 deg  current position", all.naive);
    row("> 5 deg  predictor", big.pred);
    row("> 5 deg  current position", big.naive);
    row("> 5 deg  uncertainty radius", big.radius);
    std::printf("%-30s %7.0f%% %7.0f%% %7.0f%%\n", "> 5 deg  error within it", 100 * coverage(big, 0),
                100 * coverage(big, 1), 100 * coverage(big, 2));
    std::printf("target: > 5 deg predictor at 50%% <= 1.00 deg\n");
    return 0;
}

void setup(CLI::App& app) {
    auto o = std::make_shared<Options>();
    app.add_option("dir", o->dir, "Directory of labelled CSV files (lund2013 format)")->required();
    app.add_flag("--json", o->json, "Print one JSON object");
    app.callback([o] {
        const int rc = run(*o);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
}

const Command kEvalLanding{
    "eval-landing", "Landing-prediction error on labelled saccades vs current position", &setup};

}  // namespace
}  // namespace fovea::cli
