#include "gaze_format.hpp"

#include <time.h>

#include <cinttypes>

namespace fovea::cli {

const char* event_name(uint32_t event) {
    switch (event) {
        case FOVEA_EVENT_FIXATION: return "fixation";
        case FOVEA_EVENT_SACCADE: return "saccade";
        case FOVEA_EVENT_PSO: return "pso";
        case FOVEA_EVENT_PURSUIT: return "pursuit";
        case FOVEA_EVENT_BLINK: return "blink";
        default: return "unknown";
    }
}

int64_t monotonic_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

void write_csv_header(std::FILE* f, const std::string& comment) {
    std::fprintf(f, "# fovea gaze recording v1 %s\n", comment.c_str());
    std::fputs(
        "index,t_capture_ns,t_receive_ns,t_processed_ns,t_publish_ns,"
        "left_x,left_y,left_deg_x,left_deg_y,left_pupil_mm,left_valid,"
        "right_x,right_y,right_deg_x,right_deg_y,right_pupil_mm,right_valid,"
        "x,y,deg_x,deg_y,pupil_mm,valid,event,flags,clock_uncertainty_us,"
        "saccade_onset_ns,saccade_amplitude_deg,saccade_peak_velocity_dps,saccade_direction_deg,"
        "landing_x,landing_y,landing_uncertainty_deg\n",
        f);
}

namespace {
void eye_cols(std::FILE* f, const fovea_eye& e) {
    std::fprintf(f, "%.6f,%.6f,%.4f,%.4f,%.3f,%u,", e.norm_x, e.norm_y, e.deg_x, e.deg_y,
                 e.pupil_mm, e.valid & FOVEA_VALID);
}
}  // namespace

void write_csv_row(std::FILE* f, const fovea_gaze_record& r) {
    std::fprintf(f, "%" PRIu64 ",%" PRId64 ",%" PRId64 ",%" PRId64 ",%" PRId64 ",", r.index,
                 r.t_capture_ns, r.t_receive_ns, r.t_processed_ns, r.t_publish_ns);
    eye_cols(f, r.left);
    eye_cols(f, r.right);
    eye_cols(f, r.combined);
    std::fprintf(f, "%s,%u,%.2f,%" PRId64 ",%.3f,%.1f,%.2f,", event_name(r.event), r.flags,
                 r.clock_uncertainty_us, r.saccade_onset_ns, r.saccade_amplitude_deg,
                 r.saccade_peak_velocity_dps, r.saccade_direction_deg);
    if (r.flags & FOVEA_FLAG_LANDING_VALID)
        std::fprintf(f, "%.6f,%.6f,%.3f\n", r.landing_norm_x, r.landing_norm_y,
                     r.landing_uncertainty_deg);
    else
        std::fputs(",,\n", f);
}

std::string watch_line(const fovea_gaze_record& r, int64_t now_ns) {
    char buf[256];
    const auto& c = r.combined;
    std::snprintf(buf, sizeof buf,
                  "#%-8" PRIu64
                  " t=%.6f s  gaze=(%.4f, %.4f) (%+7.2f°, %+7.2f°)  L%c R%c  "
                  "pupil=%.2f mm  %-8s  age=%.0f µs (capture→publish %.0f µs)",
                  r.index, static_cast<double>(r.t_capture_ns) / 1e9, c.norm_x, c.norm_y, c.deg_x,
                  c.deg_y, r.left.valid ? '+' : '-', r.right.valid ? '+' : '-', c.pupil_mm,
                  event_name(r.event), static_cast<double>(now_ns - r.t_capture_ns) / 1e3,
                  static_cast<double>(r.t_publish_ns - r.t_capture_ns) / 1e3);
    return buf;
}

}  // namespace fovea::cli
