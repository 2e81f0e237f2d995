// Per-eye mapping from raw tracker coordinates to normalized display coordinates: a second-order
// polynomial with cross terms (x' = a0 + a1 x + a2 y + a3 xy + a4 x^2 + a5 y^2, same for y'),
// least squares over all calibration samples, one outlier-rejection pass, then a refit.
// Before that, with 8 targets or more, each target is checked against the mapping through the
// other targets; one it cannot explain (its raw position far from where they put it: the
// tracker misread the pupil there, or the eye was elsewhere) is left out of that eye's fit.
// Samples whose targets lie within 3 deg of a target's first sample belong to that target: a
// head-mounted scene camera sees a marker move a little as the head moves.
// Quality per eye in degrees: accuracy = mean angular offset from the targets; precision = RMS
// of sample-to-sample distance and SD around each target's mean.
//
// Daemon use (control-socket thread collects, loop thread applies):
//   Calibration cal(geometry);  cal.begin();            // "calibrate start"
//   cal.add_sample(target, left_raw, right_raw);       // each raw sample while a target is shown
//   auto q = cal.fit();                                 // "calibrate finish": Result<Quality>
//   cal.save(Calibration::user_path(dir, user));        // and Pipeline::set_calibration(cal)
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"

namespace fovea::gaze {

// One target of one eye against the fit through the other targets: how far that fit puts its
// samples (their median), and how far it would put a target there that fitted as well as the
// others (their residual spread, widened by the target's leverage: a studentized deleted
// residual is their ratio). A target left out was checked against the targets still in then.
struct TargetCheck {
    double x = kNaN, y = kNaN;  // normalized display coordinates (the target's median)
    double residual_deg = kNaN;
    double expected_deg = kNaN;
    int samples = 0;
    bool left_out = false;
};

struct EyeQuality {
    bool fitted = false;
    double accuracy_deg = kNaN;       // mean angular offset, all kept samples
    double precision_rms_deg = kNaN;  // RMS of sample-to-sample distances
    double precision_sd_deg = kNaN;   // SD of samples around each target's mean
    int samples_used = 0;
    int samples_rejected = 0;                // by the outlier pass
    std::vector<TargetCheck> target_checks;  // empty with fewer than 8 targets
};

struct CalibrationQuality {
    EyeQuality left, right;
    int targets = 0;
};

enum class EyeSide { kLeft, kRight };

// Not thread-safe: build it on one thread, then hand a copy to the Pipeline.
class Calibration {
public:
    static constexpr int kTerms = 6;
    using Coefficients = std::array<double, kTerms>;

    explicit Calibration(const DisplayGeometry& display = {});

    void begin();  // forget collected samples (keeps the current fit until the next fit())
    // One raw sample while the user looks at target (normalized display coordinates). Invalid
    // eyes and non-finite values are skipped and counted.
    void add_sample(double target_x, double target_y, const EyeSample& left,
                    const EyeSample& right);
    Result<CalibrationQuality> fit();
    // The collected samples as the chain shows them without a calibration (raw taken as
    // normalized display coordinates): the "before" figures. `fitted` stays false.
    CalibrationQuality evaluate_unmapped() const;

    bool fitted() const { return left_.ok || right_.ok; }
    // Map one eye's raw sample; unchanged when that eye has no fit.
    EyeSample apply(EyeSide side, const EyeSample& raw) const;
    const CalibrationQuality& quality() const { return quality_; }
    size_t samples() const { return points_.size(); }
    size_t skipped() const { return skipped_; }

    std::string to_json() const;
    static Result<Calibration> from_json(const std::string& text, const DisplayGeometry& display);
    Result<void> save(const std::string& path) const;
    static Result<Calibration> load(const std::string& path, const DisplayGeometry& display);
    // <dir>/<user>.json; user names are restricted to [A-Za-z0-9._-] (no path tricks).
    static Result<std::string> user_path(const std::string& dir, const std::string& user);

private:
    struct Point {
        double tx, ty;
        EyeSample left, right;
        size_t target;  // index into targets_
    };
    struct EyeFit {
        bool ok = false;
        Coefficients cx{}, cy{};
        double norm[3] = {0.0, 0.0, 1.0};  // raw centre x, y and 1/half-range
    };
    EyeFit fit_eye(EyeSide side, EyeQuality& quality) const;
    using MapFn = std::function<void(const EyeSample& raw, double& x, double& y)>;
    // Accuracy and precision of one eye's samples `use`, mapped to normalized coordinates.
    void measure(EyeSide side, const std::vector<size_t>& use, const MapFn& map,
                 EyeQuality& quality) const;

    // Which target a sample at (tx, ty) belongs to; adds one when none is near.
    size_t target_of(double tx, double ty);

    DisplayGeometry display_;
    std::vector<Point> points_;
    std::vector<std::pair<double, double>> targets_;  // each target's first sample, degrees
    size_t skipped_ = 0;
    EyeFit left_, right_;
    CalibrationQuality quality_;
};

}  // namespace fovea::gaze
