// The simulated eye tracker: a pure, seeded, deterministic generator of binocular raw samples
// with ground-truth event labels. No I/O, no clocks, no threads: the same seed gives the same
// samples on every machine (own PRNG and normal deviates, no <random> distributions).
//
// Model (degrees of visual angle from the display centre, +x right, +y down):
// - fixations: slow drift (random-walk direction, pulled back to the target) + tremor + noise;
// - saccades on a published main sequence (gaze/main_sequence.hpp: kPublished, Dai et al. 2016
//   peak velocity, Carpenter 1988 duration), never the one the landing predictor assumes: each
//   seed is a subject whose curve is scaled by ~10 % (subject_main_sequence()), each saccade's
//   duration spreads +-15-20 % around it, and the velocity profile is a skewed beta whose peak
//   falls at 30-45 % of the duration, earlier for larger saccades;
// - post-saccadic oscillation: damped, 10-40 ms, slightly larger in the abducting eye;
// - smooth pursuit at 2-30 deg/s with a ramped onset;
// - blinks of 100-400 ms: lid edges drag gaze down and shrink the pupil, the middle is invalid.
// Measurement noise is added per eye; the truth is noise-free.
//
// For calibration tests (`fovea calibrate`, DESIGN.md §4):
// - look_at(): the eyes fixate a target (a main-sequence saccade after a 150-250 ms latency,
//   then fixations on it with drift, tremor, noise and the occasional blink) until release();
// - `distortion` S > 0 bends each eye's raw output with a known second-order polynomial, the
//   kind a tracker shows before it is calibrated. With u = x - 0.5, v = y - 0.5 the measured
//   normalized position (noise included), the output is
//     left:  u' = u + S (0.035 + 0.06 u + 0.03 v + 0.10 u v + 0.08 u^2 - 0.04 v^2)
//            v' = v + S (-0.030 + 0.02 u + 0.07 v - 0.06 u v + 0.03 u^2 + 0.09 v^2)
//     right: the same plus S (-0.010, +0.008)
//   S = 1 puts the raw gaze ~2-3 deg off on a 24" screen at 60 cm; see distort().
#pragma once

#include <array>
#include <cstdint>

#include "fovea/gaze/main_sequence.hpp"
#include "fovea/gaze/sample.hpp"
#include "fovea/result.hpp"

namespace fovea::drivers::sim {

struct SimConfig {
    uint64_t seed = 1;
    double rate_hz = 1000.0;  // 60..2000
    gaze::DisplayGeometry display;
    bool binocular = true;  // false: only the left eye is valid

    double noise_deg = 0.03;    // tracker measurement noise, RMS per axis and eye
    double tremor_deg = 0.008;  // ocular tremor amplitude (~84 Hz)
    double drift_dps = 0.25;    // fixational drift speed
    double vergence_deg = 0.3;  // horizontal disparity between the eyes while fixating
    double fixation_mean_ms = 280.0;
    double saccade_median_deg = 4.0;  // amplitudes are log-normal, clamped to 0.5..30 deg
    double blink_rate_hz = 0.25;      // ~15 blinks a minute
    double pursuit_share = 0.15;      // fraction of time in smooth pursuit
    double pupil_mm = 3.5;
    double distortion = 0.0;  // strength S of the raw-output distortion above, 0..3 (0: off)
    gaze::MainSequence main_sequence = gaze::kPublished;  // the population's curve

    // The device clock as the raw samples report it.
    int counter_bits = 32;        // 16, 32 or 64
    double tick_hz = 1e6;         // counter ticks per second
    double drift_ppm = 0.0;       // device oscillator error: ticks run fast by this much
    int64_t counter_offset = -1;  // counter value at t = 0; -1: wrap ~10 s into the run
    int64_t start_ns = 0;         // t_true_ns of the first sample (e.g. CLOCK_MONOTONIC at open)
};

// Checks ranges (rate 60..2000 Hz, counter bits, non-negative noise, ...).
Result<void> validate(const SimConfig& config);

// What the generator knows and a tracker would not: the noise-free gaze and the event.
struct SimTruth {
    gaze::Event event = gaze::Event::kFixation;
    double x_deg = 0.0, y_deg = 0.0;  // cyclopean gaze, no measurement noise
    // The current saccade, or the most recent one once it has ended (amplitude 0 before any).
    bool in_saccade = false;
    int64_t saccade_onset_ns = 0;
    int64_t saccade_end_ns = 0;
    double saccade_amplitude_deg = 0.0;
    double saccade_peak_velocity_dps = 0.0;
    double landing_x_deg = 0.0, landing_y_deg = 0.0;
};

class SimTracker {
public:
    // `config` must pass validate() (asserted).
    explicit SimTracker(const SimConfig& config);

    struct Frame {
        gaze::RawSample raw;  // device_ticks, left/right, truth = truth.event; t_receive_ns = 0
        SimTruth truth;
        int64_t t_true_ns = 0;  // when the sample was taken, on the start_ns time base
    };
    // The next sample, 1/rate_hz after the previous one.
    Frame next();

    // Fixate a target (degrees from the display centre, clamped to the display) from the next
    // sample on, after a saccadic latency; release() returns to free viewing.
    void look_at(double x_deg, double y_deg);
    void release();
    bool has_target() const { return target_held_; }

    const SimConfig& config() const { return config_; }
    // This subject's main sequence (the population curve scaled per seed).
    const gaze::MainSequence& subject_main_sequence() const { return subject_; }
    uint64_t samples_generated() const { return index_; }

private:
    enum class Phase { kFixation, kSaccade, kPso, kPursuit, kBlink };

    struct Rng {
        std::array<uint64_t, 4> s{};
        explicit Rng(uint64_t seed);
        uint64_t next_u64();
        double uniform();  // [0, 1)
        double uniform(double lo, double hi);
        double normal();  // N(0, 1), Box-Muller
    };

    void start_next_phase(int64_t t_ns);
    void start_fixation(int64_t t_ns, double mean_ms);
    bool start_saccade(int64_t t_ns);
    // amp_deg is |(dx, dy)| as the caller chose it (passed on so a clamped amplitude stays
    // exactly within its bound instead of being recomputed with rounding).
    void begin_saccade(int64_t t_ns, double dx, double dy, double amp_deg);
    void maybe_go_to_target(int64_t t_ns);
    void start_pursuit(int64_t t_ns);
    void start_blink(int64_t t_ns);
    void advance(int64_t t_ns, double dt_s);
    double saccade_progress(double tau) const;  // 0..1 position fraction at normalized time tau
    void clamp_to_display(double& x, double& y) const;
    uint64_t device_ticks(int64_t t_rel_ns) const;
    void eye_outputs(int64_t t_ns, gaze::EyeSample& left, gaze::EyeSample& right);

    SimConfig config_;
    Rng rng_;
    Rng shape_rng_;  // subject and saccade-shape draws (main sequence spread, skew)
    gaze::MainSequence subject_;
    uint64_t index_ = 0;
    int64_t prev_t_ns_ = 0;
    uint64_t counter_offset_ = 0;
    double half_w_deg_ = 0.0, half_h_deg_ = 0.0;  // usable display half-extent
    double p_blink_ = 0.0, p_pursuit_ = 0.0;      // chance the next movement is a blink/pursuit

    Phase phase_ = Phase::kFixation;
    int64_t phase_start_ns_ = 0, phase_end_ns_ = 0;
    double x_ = 0.0, y_ = 0.0;  // cyclopean eye position (no tremor, no noise)
    // Fixation drift.
    double fix_x_ = 0.0, fix_y_ = 0.0, drift_dir_ = 0.0;
    // Saccade: start, target, velocity-profile shape and its cumulative table.
    double sac_x0_ = 0.0, sac_y0_ = 0.0, sac_dx_ = 0.0, sac_dy_ = 0.0;
    static constexpr int kProfileSteps = 256;
    std::array<double, kProfileSteps + 1> profile_cdf_{};
    // PSO: amplitude along the saccade direction, period, decay.
    double pso_amp_deg_ = 0.0, pso_period_s_ = 0.0, pso_decay_s_ = 0.0;
    double pso_eye_ratio_ = 1.0;  // abducting-eye amplitude / adducting
    // Pursuit.
    double pur_vx_ = 0.0, pur_vy_ = 0.0;
    // Blink: lid edges (closing, opening) drag the measured gaze down and shrink the pupil.
    double blink_in_s_ = 0.0, blink_out_s_ = 0.0, blink_sag_deg_ = 0.0;
    // Slow pupil change (hippus) and tremor phases.
    double hippus_phase_ = 0.0, tremor_phase_x_ = 0.0, tremor_phase_y_ = 0.0;
    // Per-eye constant calibration residuals.
    double bias_lx_ = 0.0, bias_ly_ = 0.0, bias_rx_ = 0.0, bias_ry_ = 0.0;
    double anisocoria_mm_ = 0.0;
    SimTruth truth_;
    // The target look_at() set: fixated from target_go_ns_ on.
    bool target_held_ = false, target_pending_ = false;
    double target_x_ = 0.0, target_y_ = 0.0;
    int64_t target_go_ns_ = 0;
};

// The documented raw-output distortion of strength `s` (see the top of this file) for one eye,
// on normalized display coordinates.
void distort(double s, bool right_eye, double& x, double& y);

}  // namespace fovea::drivers::sim
