#include "fovea/eval/detector_params.hpp"

#include <charconv>
#include <cmath>
#include <utility>

namespace fovea::eval {
namespace {

using gaze::DetectorParams;

struct Field {
    const char* name;
    double DetectorParams::*real = nullptr;
    int DetectorParams::*integer = nullptr;
};

// The one list of DetectorParams' fields by name; a field missing here cannot be set from the
// command line (detector_params_test checks the count against the struct's size).
constexpr Field kFields[] = {
    {"velocity_half_window_s", &DetectorParams::velocity_half_window_s},
    {"initial_peak_dps", &DetectorParams::initial_peak_dps},
    {"stats_bound_dps", &DetectorParams::stats_bound_dps},
    {"peak_sd", &DetectorParams::peak_sd},
    {"onset_sd", &DetectorParams::onset_sd},
    {"stats_exclude_flanks", nullptr, &DetectorParams::stats_exclude_flanks},
    {"min_peak_dps", &DetectorParams::min_peak_dps},
    {"onset_extra_samples", nullptr, &DetectorParams::onset_extra_samples},
    {"offset_peak_fraction", &DetectorParams::offset_peak_fraction},
    {"offset_half_window_s", &DetectorParams::offset_half_window_s},
    {"trim_window_excess", nullptr, &DetectorParams::trim_window_excess},
    {"local_noise_window_s", &DetectorParams::local_noise_window_s},
    {"local_noise_sd", &DetectorParams::local_noise_sd},
    {"relative_window_s", &DetectorParams::relative_window_s},
    {"min_saccade_s", &DetectorParams::min_saccade_s},
    {"max_saccade_s", &DetectorParams::max_saccade_s},
    {"pso_window_s", &DetectorParams::pso_window_s},
    {"pso_onset_factor", &DetectorParams::pso_onset_factor},
    {"pso_peak_fraction", &DetectorParams::pso_peak_fraction},
    {"smooth_half_window_s", &DetectorParams::smooth_half_window_s},
    {"pursuit_dps", &DetectorParams::pursuit_dps},
    {"pursuit_ref_window_s", &DetectorParams::pursuit_ref_window_s},
    {"pursuit_floor_sd", &DetectorParams::pursuit_floor_sd},
    {"pursuit_span_exponent", &DetectorParams::pursuit_span_exponent},
    {"pursuit_catch_up", nullptr, &DetectorParams::pursuit_catch_up},
    {"pursuit_join_cos", &DetectorParams::pursuit_join_cos},
    {"pursuit_join_ratio", &DetectorParams::pursuit_join_ratio},
    {"pursuit_join_min_speed", &DetectorParams::pursuit_join_min_speed},
    {"pursuit_join_max_deg", &DetectorParams::pursuit_join_max_deg},
    {"pursuit_skip_jumps", nullptr, &DetectorParams::pursuit_skip_jumps},
    {"noise_prior_deg", &DetectorParams::noise_prior_deg},
    {"noise_prior_samples", &DetectorParams::noise_prior_samples},
    {"noise_reference_s", &DetectorParams::noise_reference_s},
    {"noise_prior_ratio", &DetectorParams::noise_prior_ratio},
    {"min_pursuit_window_s", &DetectorParams::min_pursuit_window_s},
    {"pursuit_hysteresis", &DetectorParams::pursuit_hysteresis},
    {"min_blink_s", &DetectorParams::min_blink_s},
    {"blink_pre_s", &DetectorParams::blink_pre_s},
    {"blink_post_s", &DetectorParams::blink_post_s},
    {"lookahead_s", &DetectorParams::lookahead_s},
    {"threshold_horizon_s", &DetectorParams::threshold_horizon_s},
    {"microsaccade_lambda", &DetectorParams::microsaccade_lambda},
    {"microsaccade_half_window_s", &DetectorParams::microsaccade_half_window_s},
    {"microsaccade_min_s", &DetectorParams::microsaccade_min_s},
    {"microsaccade_min_interval_s", &DetectorParams::microsaccade_min_interval_s},
    {"microsaccade_warmup_values", &DetectorParams::microsaccade_warmup_values},
    {"online_microsaccades", nullptr, &DetectorParams::online_microsaccades},
};

std::string names_list() {
    std::string s;
    for (const Field& f : kFields) s += (s.empty() ? "" : ", ") + std::string(f.name);
    return s;
}

}  // namespace

std::vector<std::string> detector_param_names() {
    std::vector<std::string> out;
    for (const Field& f : kFields) out.emplace_back(f.name);
    return out;
}

Result<void> set_detector_param(DetectorParams& params, std::string_view assignment) {
    const size_t eq = assignment.find('=');
    if (eq == std::string_view::npos) {
        return make_error("detector parameter '" + std::string(assignment) + "' is not KEY=VALUE");
    }
    const std::string_view key = assignment.substr(0, eq);
    const std::string_view text = assignment.substr(eq + 1);
    for (const Field& f : kFields) {
        if (key != f.name) continue;
        const char* end = text.data() + text.size();
        if (f.integer) {
            int v = 0;
            const auto [p, ec] = std::from_chars(text.data(), end, v);
            if (ec != std::errc{} || p != end || text.empty()) {
                return make_error("detector parameter " + std::string(key) +
                                  " takes an integer, not '" + std::string(text) + "'");
            }
            params.*f.integer = v;
            return {};
        }
        double v = 0;
        const auto [p, ec] = std::from_chars(text.data(), end, v);
        if (ec != std::errc{} || p != end || text.empty() || !std::isfinite(v)) {
            return make_error("detector parameter " + std::string(key) +
                              " takes a finite number, not '" + std::string(text) + "'");
        }
        params.*f.real = v;
        return {};
    }
    return make_error("no detector parameter '" + std::string(key) + "' (known: " + names_list() +
                      ")");
}

}  // namespace fovea::eval
