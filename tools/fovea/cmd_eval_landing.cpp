// `fovea eval-landing DIR [--json]`: landing-point error of the in-flight saccade predictor on
// hand-labelled saccades > 2 deg, at 25/50/75 % of each saccade's labelled duration, against the
// naive "current position" baseline, and how well the predictor's own uncertainty radius
// covers its error (median radius, share of errors inside it). `--cv` refits the predictor's
// late correction and radius scale (constants fitted on these labels) leaving one subject out and
// scores every subject with the constants fitted without it: the honest figure for unseen data.
// An "oracle" row scales the displacement so far by the median landed/displacement ratio of all
// saccades > 5 deg at that exact fraction: told the fraction no causal predictor knows, and fitted
// in-sample, it shows how much of the error the first part of a saccade cannot resolve.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <map>
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
    bool cv = false;
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

// One labelled saccade: where it landed and what the predictor saw at 25/50/75 % of its
// duration (and, for fitting the late correction, at 15-95 % in 5 % steps).
struct Saccade {
    std::string subject;  // recording name up to the first '_' (e.g. UH29)
    double amplitude = 0.0, land_x = 0.0, land_y = 0.0;
    gaze::LandingObservation at[3];
    double naive[3] = {};
    std::vector<gaze::LateCorrectionRow> fit_rows;
};

constexpr int kFitFromPct = 15, kFitToPct = 95, kFitStepPct = 5;

// Saccades > 5 deg: landing = onset + direction x displacement x (median landed/displacement
// ratio at this fraction, over all of them), errors per fraction.
std::array<std::vector<double>, 3> oracle_errors(const std::vector<Saccade>& saccades) {
    std::array<std::vector<double>, 3> errors;
    for (int q = 0; q < 3; ++q) {
        std::vector<double> ratio;
        for (const auto& s : saccades) {
            const gaze::LandingObservation& o = s.at[q];
            if (s.amplitude <= 5.0 || !o.valid || !(o.displacement_deg > 0.1)) continue;
            ratio.push_back(((s.land_x - o.x0_deg) * o.ux + (s.land_y - o.y0_deg) * o.uy) /
                            o.displacement_deg);
        }
        const double k = median(ratio);
        for (const auto& s : saccades) {
            const gaze::LandingObservation& o = s.at[q];
            if (s.amplitude <= 5.0) continue;
            if (!o.valid || !(o.displacement_deg > 0.1) || !std::isfinite(k)) {
                errors[q].push_back(s.naive[q]);
                continue;
            }
            const double along = o.displacement_deg * k;
            errors[q].push_back(std::hypot(o.x0_deg + along * o.ux - s.land_x,
                                           o.y0_deg + along * o.uy - s.land_y));
        }
    }
    return errors;
}

void score(const gaze::LandingPredictor& predictor, const Saccade& s, Errors& all, Errors& big) {
    for (int q = 0; q < 3; ++q) {
        const gaze::LandingEstimate e_est = predictor.estimate(s.at[q]);
        // No estimate yet (too few samples): the predictor falls back to the position.
        const double err = e_est.valid ? std::hypot(e_est.x_deg - s.land_x, e_est.y_deg - s.land_y)
                                       : s.naive[q];
        for (Errors* e : {&all, s.amplitude > 5.0 ? &big : nullptr}) {
            if (!e) continue;
            e->pred[q].push_back(err);
            e->naive[q].push_back(s.naive[q]);
            if (e_est.valid) {
                e->radius[q].push_back(e_est.uncertainty_deg);
                e->covered[q] += err <= e_est.uncertainty_deg;
            }
        }
    }
}

// The radius scale that holds 2/3 of the errors of saccades > 5 deg at 25/50/75 % (other
// subjects than `excluded`): radius = scale x A x f^-power + noise, so each estimate needs
// scale >= (error - noise) / (A f^-power); the scale is the 2/3 quantile of that ratio.
double fit_uncertainty_scale(const gaze::LandingParams& params,
                             const std::vector<Saccade>& saccades, const std::string& excluded) {
    const gaze::LandingPredictor predictor(params);
    std::vector<double> need;
    for (const auto& s : saccades) {
        if (s.subject == excluded || s.amplitude <= 5.0) continue;
        for (const auto& obs : s.at) {
            const gaze::LandingEstimate e = predictor.estimate(obs);
            if (!e.valid) continue;
            const double err = std::hypot(e.x_deg - s.land_x, e.y_deg - s.land_y);
            const double f = std::max(0.05, e.fraction);
            need.push_back(std::max(0.0, err - params.position_noise_deg) /
                           (e.amplitude_deg * std::pow(f, -params.uncertainty_power)));
        }
    }
    if (need.empty()) return params.uncertainty_scale;
    const auto k = need.begin() + static_cast<long>(2 * need.size() / 3);
    std::nth_element(need.begin(), k, need.end());
    return *k;
}

int run(const Options& o) {
    auto set = gaze::load_labelled_dir(o.dir);
    if (!set) {
        std::fprintf(stderr, "eval-landing: %s\n", set.error().message.c_str());
        return 1;
    }
    const gaze::LandingPredictor predictor;
    std::vector<Saccade> saccades;
    size_t skipped_invalid = 0;
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
            Saccade s;
            s.subject = f.recording.substr(0, f.recording.find('_'));
            s.land_x = in[b].x_deg;
            s.land_y = in[b].y_deg;
            s.amplitude = std::hypot(s.land_x - in[a].x_deg, s.land_y - in[a].y_deg);
            if (s.amplitude <= kMinAmplitude) continue;
            const double dur = in[b].t_s - in[a].t_s;
            // What the predictor sees once `fraction` of the labelled duration has elapsed: the
            // samples from the labelled onset up to then, nothing later.
            std::vector<double> t, x, y;
            auto observe_at = [&](double fraction) {
                t.clear();
                x.clear();
                y.clear();
                for (size_t k = a; k <= b && in[k].t_s - in[a].t_s <= fraction * dur + 1e-9; ++k) {
                    t.push_back(in[k].t_s - in[a].t_s);
                    x.push_back(in[k].x_deg);
                    y.push_back(in[k].y_deg);
                }
                return predictor.observe(t, x, y);
            };
            for (int q = 0; q < 3; ++q) {
                s.at[q] = observe_at(kFractions[q]);
                s.naive[q] = std::hypot(x.back() - s.land_x, y.back() - s.land_y);
            }
            if (o.cv) {
                for (int pct = kFitFromPct; pct <= kFitToPct; pct += kFitStepPct) {
                    gaze::LateCorrectionRow r{observe_at(pct / 100.0), 0.0};
                    if (!r.obs.valid) continue;
                    r.landed_along_deg = (s.land_x - r.obs.x0_deg) * r.obs.ux +
                                         (s.land_y - r.obs.y0_deg) * r.obs.uy;
                    s.fit_rows.push_back(r);
                }
            }
            saccades.push_back(std::move(s));
        }
    }
    Errors all, big;
    for (const auto& s : saccades) score(predictor, s, all, big);
    const std::array<std::vector<double>, 3> oracle = oracle_errors(saccades);

    // Leave one subject out: fit the late correction and the radius scale on the others, score
    // the subject.
    Errors cv_all, cv_big;
    gaze::LateCorrection fit_all;
    double scale_all = NAN;
    std::map<std::string, gaze::LateCorrection> fit_without;
    if (o.cv) {
        auto fit_excluding = [&](const std::string& subject) {
            std::vector<gaze::LateCorrectionRow> rows;
            for (const auto& s : saccades)
                if (s.subject != subject)
                    rows.insert(rows.end(), s.fit_rows.begin(), s.fit_rows.end());
            return predictor.fit_late_correction(rows);
        };
        fit_all = fit_excluding("");
        scale_all = fit_uncertainty_scale(gaze::LandingParams{}, saccades, "");
        for (const auto& s : saccades)
            if (!fit_without.count(s.subject)) fit_without[s.subject] = fit_excluding(s.subject);
        for (const auto& [subject, c] : fit_without) {
            gaze::LandingParams p;
            p.late_bias = c.bias;
            p.late_displacement = c.displacement;
            p.late_speed = c.speed;
            p.uncertainty_scale = fit_uncertainty_scale(p, saccades, subject);
            const gaze::LandingPredictor held_out(p);
            for (const auto& s : saccades)
                if (s.subject == subject) score(held_out, s, cv_all, cv_big);
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
        for (int q = 0; q < 3; ++q)
            j["median_error_deg"]["gt5"][std::to_string(static_cast<int>(kFractions[q] * 100))]
             ["oracle_fraction_known"] = median(oracle[q]);
        j["saccades"] = saccades.size();
        j["skipped_invalid"] = skipped_invalid;
        if (o.cv) {
            j["cv_leave_one_subject_out"]["gt2"] = block(cv_all);
            j["cv_leave_one_subject_out"]["gt5"] = block(cv_big);
            j["cv_leave_one_subject_out"]["subjects"] = fit_without.size();
            j["late_correction_fit_all"] = {{"bias", fit_all.bias},
                                            {"displacement", fit_all.displacement},
                                            {"speed", fit_all.speed},
                                            {"rows", fit_all.rows}};
            j["uncertainty_scale_fit_all"] = scale_all;
        }
        std::printf("%s\n", j.dump().c_str());
        return 0;
    }
    std::printf(
        "eval-landing: %zu labelled saccades > %.0f deg (all coder files), %zu skipped "
        "(lost samples)\n",
        saccades.size(), kMinAmplitude, skipped_invalid);
    std::printf("median landing error, deg      %8s %8s %8s\n", "25%", "50%", "75%");
    auto row = [](const char* name, const std::vector<double>* v) {
        std::printf("%-30s %8.2f %8.2f %8.2f\n", name, median(v[0]), median(v[1]), median(v[2]));
    };
    row("> 2 deg  predictor", all.pred);
    row("> 2 deg  current position", all.naive);
    row("> 5 deg  predictor", big.pred);
    row("> 5 deg  current position", big.naive);
    row("> 5 deg  oracle (fraction)", oracle.data());
    row("> 5 deg  uncertainty radius", big.radius);
    std::printf("%-30s %7.0f%% %7.0f%% %7.0f%%\n", "> 5 deg  error within it", 100 * coverage(big, 0),
                100 * coverage(big, 1), 100 * coverage(big, 2));
    if (o.cv) {
        std::printf(
            "leave-one-subject-out (%zu subjects; late correction and radius scale refitted "
            "without each):\n",
            fit_without.size());
        row("> 2 deg  predictor (CV)", cv_all.pred);
        row("> 5 deg  predictor (CV)", cv_big.pred);
        std::printf("%-30s %7.0f%% %7.0f%% %7.0f%%\n", "> 5 deg  within radius (CV)",
                    100 * coverage(cv_big, 0), 100 * coverage(cv_big, 1),
                    100 * coverage(cv_big, 2));
        std::printf("late correction fitted on all (%zu rows): bias %.3f displacement %.3f "
                    "speed %.3f\n",
                    fit_all.rows, fit_all.bias, fit_all.displacement, fit_all.speed);
        std::printf("radius scale fitted on all (2/3 of the > 5 deg errors): %.4f\n", scale_all);
    }
    std::printf("target: > 5 deg predictor at 50%% <= 1.00 deg\n");
    return 0;
}

void setup(CLI::App& app) {
    auto o = std::make_shared<Options>();
    app.add_option("dir", o->dir, "Directory of labelled CSV files (lund2013 format)")->required();
    app.add_flag("--json", o->json, "Print one JSON object");
    app.add_flag("--cv", o->cv,
                 "Also refit the late correction and the radius scale leaving one subject out "
                 "at a time and score each subject with the constants fitted without it");
    app.callback([o] {
        const int rc = run(*o);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
}

const Command kEvalLanding{
    "eval-landing", "Landing-prediction error on labelled saccades vs current position", &setup};

}  // namespace
}  // namespace fovea::cli
