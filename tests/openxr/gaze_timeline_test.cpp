// The layer's gaze timeline and record mapping, on samples with known answers.
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "ring_writer.hpp"

#include "gaze_geometry.hpp"
#include "gaze_source.hpp"
#include "gaze_timeline.hpp"

namespace {

using namespace fovea::openxr;

constexpr int64_t kMs = 1'000'000;

// A view-space direction `deg` degrees to the right of straight ahead.
Vec3 yaw(double deg) {
    const double r = deg * M_PI / 180;
    return {std::sin(r), 0, -std::cos(r)};
}
double yaw_of(const Vec3& d) { return std::atan2(d[0], -d[2]) * 180 / M_PI; }

GazeSample sample(int64_t t, double deg, bool valid = true) {
    GazeSample s;
    s.t_ns = t;
    s.valid = valid;
    s.direction = yaw(deg);
    return s;
}

TEST(GazeTimeline, InterpolatesBetweenSamplesAtTheRequestedTime) {
    GazeTimeline tl;
    for (int i = 0; i <= 10; ++i) tl.push(sample(i * kMs, i * 1.0));  // 1000 deg/s
    const GazeEstimate e = tl.at(4 * kMs + kMs / 4, 10 * kMs);
    ASSERT_TRUE(e.tracked());
    EXPECT_EQ(e.method, GazeMethod::kInterpolated);
    EXPECT_NEAR(yaw_of(e.direction), 4.25, 1e-9);
    EXPECT_EQ(e.t_expressed_ns, 4 * kMs + kMs / 4);
}

TEST(GazeTimeline, UntrackedNeighbourDecidesByNearness) {
    GazeTimeline tl;
    tl.push(sample(0, 0));
    tl.push(sample(10 * kMs, 0, false));  // blink
    tl.push(sample(20 * kMs, 0));
    EXPECT_TRUE(tl.at(4 * kMs, 20 * kMs).tracked());
    EXPECT_EQ(tl.at(6 * kMs, 20 * kMs).status, GazeStatus::kUntracked);
    EXPECT_EQ(tl.at(14 * kMs, 20 * kMs).status, GazeStatus::kUntracked);
    EXPECT_TRUE(tl.at(16 * kMs, 20 * kMs).tracked());
}

TEST(GazeTimeline, HoldsAFixationAndClampsThePredictionHorizon) {
    TimelineParams p;
    p.max_prediction_ns = 30 * kMs;
    GazeTimeline tl(p);
    tl.push(sample(0, 5));
    tl.push(sample(kMs, 5));
    const GazeEstimate e = tl.at(100 * kMs, 2 * kMs);
    ASSERT_TRUE(e.tracked());
    EXPECT_EQ(e.method, GazeMethod::kHeld);
    EXPECT_NEAR(yaw_of(e.direction), 5, 1e-9);
    EXPECT_EQ(e.t_expressed_ns, 31 * kMs);  // newest + horizon
}

TEST(GazeTimeline, StaleDataIsInvalidButThePastStillInterpolates) {
    GazeTimeline tl;
    tl.push(sample(0, 0));
    tl.push(sample(kMs, 1));
    EXPECT_EQ(tl.at(20 * kMs, 200 * kMs).status, GazeStatus::kStale);
    EXPECT_TRUE(tl.at(kMs / 2, 200 * kMs).tracked());  // what was, stays known
    EXPECT_EQ(tl.at(-kMs, 2 * kMs).status, GazeStatus::kTooOld);
    EXPECT_EQ(GazeTimeline().at(0, 0).status, GazeStatus::kNoData);
}

TEST(GazeTimeline, SaccadeExtrapolatesTowardsTheLandingPointAndStopsThere) {
    GazeTimeline tl;
    // A 10 deg saccade from 0 with onset at t = 0; 2 deg covered after 10 ms.
    GazeSample s = sample(10 * kMs, 2);
    s.saccade = true;
    s.landing = yaw(10);
    s.saccade_onset_ns = 0;
    s.saccade_amplitude_deg = 2;
    tl.push(sample(9 * kMs, 1.7));
    tl.push(s);
    // Main sequence: D = 2.6 * 10 + 17 = 43 ms; minimum jerk in between.
    const double done = 10.0 / 43, then = 20.0 / 43;
    const auto mj = [](double t) { return t * t * t * (10 - 15 * t + 6 * t * t); };
    const double f = (mj(then) - mj(done)) / (1 - mj(done));
    const GazeEstimate mid = tl.at(20 * kMs, 10 * kMs);
    ASSERT_TRUE(mid.tracked());
    EXPECT_EQ(mid.method, GazeMethod::kLanding);
    EXPECT_NEAR(yaw_of(mid.direction), 2 + 8 * f, 1e-6);
    const GazeEstimate late = tl.at(55 * kMs, 10 * kMs);
    EXPECT_NEAR(yaw_of(late.direction), 10, 1e-6);  // landed, never beyond
}

TEST(GazeTimeline, PursuitContinuesAtTheEyesAngularVelocity) {
    GazeTimeline tl;
    for (int i = 0; i <= 20; ++i) {
        GazeSample s = sample(i * kMs, 0.02 * i);  // 20 deg/s
        s.pursuit = true;
        tl.push(s);
    }
    const GazeEstimate e = tl.at(30 * kMs, 20 * kMs);
    EXPECT_EQ(e.method, GazeMethod::kPursuit);
    EXPECT_NEAR(yaw_of(e.direction), 0.6, 1e-6);
}

TEST(GazeTimeline, ClockStepsBackAreNudgedAndJumpsRestart) {
    GazeTimeline tl;
    tl.push(sample(100 * kMs, 0));
    tl.push(sample(100 * kMs - 10, 1));  // jitter: nudged after the newest
    EXPECT_EQ(tl.size(), 2u);
    EXPECT_EQ(tl.newest_ns(), 100 * kMs + 1);
    tl.push(sample(kMs, 2));  // the device clock was reset
    EXPECT_EQ(tl.size(), 1u);
    EXPECT_EQ(tl.clock_jumps(), 1u);
}

TEST(GazeTimeline, KeepsOnlyItsCapacity) {
    GazeTimeline tl({}, 8);
    for (int i = 0; i < 100; ++i) tl.push(sample(i * kMs, 0));
    EXPECT_EQ(tl.size(), 8u);
    EXPECT_EQ(tl.at(50 * kMs, 99 * kMs).status, GazeStatus::kTooOld);
}

fovea_eye_geometry hmd(double temporal, double nasal, double vertical, double ipd) {
    fovea_eye_geometry g{};
    g.fov_deg[0][0] = g.fov_deg[1][1] = static_cast<float>(temporal);
    g.fov_deg[0][1] = g.fov_deg[1][0] = static_cast<float>(nasal);
    for (int e = 0; e < 2; ++e) g.fov_deg[e][2] = g.fov_deg[e][3] = static_cast<float>(vertical);
    g.ipd_m = static_cast<float>(ipd);
    return g;
}

// Normalized display coordinates of a view-space direction on an eye's view.
void to_norm(const fovea_eye_geometry& g, int eye, const Vec3& d, float& nx, float& ny) {
    const double l = std::tan(g.fov_deg[eye][0] * M_PI / 180),
                 r = std::tan(g.fov_deg[eye][1] * M_PI / 180);
    const double u = std::tan(g.fov_deg[eye][2] * M_PI / 180),
                 dn = std::tan(g.fov_deg[eye][3] * M_PI / 180);
    const double tx = d[0] / -d[2], ty = -d[1] / -d[2];  // eye frame: +y down, +z forward
    nx = static_cast<float>((tx + l) / (l + r));
    ny = static_cast<float>((ty + u) / (u + dn));
}

TEST(GazeGeometry, CombinedGazePointsAtTheVergencePoint) {
    const fovea_eye_geometry g = hmd(52, 46, 53, 0.064);
    const GazeGeometry geo(g);
    ASSERT_TRUE(geo.has_eye_views());
    // Both eyes fixate a point 0.5 m ahead, 0.1 m right and 0.05 m up of the midpoint.
    const Vec3 target{0.1, 0.05, -0.5};
    fovea_gaze_record r{};
    r.left.valid = r.right.valid = FOVEA_VALID;
    to_norm(g, 0, normalized(add(target, {0.032, 0, 0})), r.left.norm_x, r.left.norm_y);
    to_norm(g, 1, normalized(add(target, {-0.032, 0, 0})), r.right.norm_x, r.right.norm_y);
    const auto d = geo.combined(r);
    ASSERT_TRUE(d.has_value());
    EXPECT_LT(angle_deg(*d, normalized(target)), 0.01);  // float coordinates: ~1e-3 deg
    // One eye: its own ray.
    r.right.valid = 0;
    const auto mono = geo.combined(r);
    ASSERT_TRUE(mono.has_value());
    EXPECT_LT(angle_deg(*mono, normalized(add(target, {0.032, 0, 0}))), 0.01);
    // Blinks and untracked eyes give no gaze.
    r.left.valid = 0;
    EXPECT_FALSE(geo.combined(r).has_value());
    r.left.valid = r.right.valid = FOVEA_VALID;
    r.event = FOVEA_EVENT_BLINK;
    EXPECT_FALSE(geo.combined(r).has_value());
}

TEST(GazeGeometry, ParallelEyesGiveTheirCommonDirection) {
    const fovea_eye_geometry g = hmd(45, 45, 45, 0.063);
    const GazeGeometry geo(g);
    fovea_gaze_record r{};
    r.left.valid = r.right.valid = FOVEA_VALID;
    const Vec3 d = normalized(Vec3{0.2, -0.1, -1});
    to_norm(g, 0, d, r.left.norm_x, r.left.norm_y);
    to_norm(g, 1, d, r.right.norm_x, r.right.norm_y);
    const auto c = geo.combined(r);
    ASSERT_TRUE(c.has_value());
    EXPECT_LT(angle_deg(*c, d), 0.01);
}

TEST(GazeGeometry, NoiseOnNearlyParallelEyesStaysNoiseSized) {
    // 0.3 deg of vergence (12 m) and 0.03 deg of noise per eye: the rays' closest points slide
    // far along them (the distance is ill-conditioned), the direction to them must not.
    const fovea_eye_geometry g = hmd(45, 45, 45, 0.063);
    const GazeGeometry geo(g);
    const Vec3 ahead = normalized(Vec3{0.1, 0.05, -1});
    uint64_t state = 1;
    const auto noise = [&] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return (static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5) * 2 * 0.03 * M_PI /
               180;
    };
    double worst = 0;
    for (int i = 0; i < 2000; ++i) {
        fovea_gaze_record r{};
        r.left.valid = r.right.valid = FOVEA_VALID;
        const double half = 0.15 * M_PI / 180;
        to_norm(g, 0, normalized(add(ahead, {half + noise(), noise(), 0})), r.left.norm_x,
                r.left.norm_y);
        to_norm(g, 1, normalized(add(ahead, {-half + noise(), noise(), 0})), r.right.norm_x,
                r.right.norm_y);
        worst = std::max(worst, angle_deg(*geo.combined(r), ahead));
    }
    EXPECT_LT(worst, 0.06);
}

TEST(GazeGeometry, WithoutEyeViewsTheDegreesFromTheCentreAreUsed) {
    const GazeGeometry geo;
    fovea_gaze_record r{};
    r.combined.valid = FOVEA_VALID;
    r.combined.deg_x = 10;  // right
    r.combined.deg_y = -5;  // up (ring degrees: +y down)
    const auto d = geo.combined(r);
    ASSERT_TRUE(d.has_value());
    EXPECT_NEAR(std::atan2((*d)[0], -(*d)[2]) * 180 / M_PI, 10, 1e-9);
    EXPECT_GT((*d)[1], 0);  // OpenXR +y is up
    r.combined.deg_x = NAN;
    EXPECT_FALSE(geo.combined(r).has_value());
}

TEST(GazeGeometry, LandingTurnsTheCurrentGazeByThePredictedMove) {
    const GazeGeometry geo;
    fovea_gaze_record r{};
    r.combined.valid = FOVEA_VALID;
    r.combined.deg_x = 2;
    r.landing_deg_x = 12;
    r.flags = FOVEA_FLAG_LANDING_VALID;
    const auto cur = geo.combined(r);
    const auto land = geo.landing(r, *cur);
    ASSERT_TRUE(land.has_value());
    EXPECT_NEAR(std::atan2((*land)[0], -(*land)[2]) * 180 / M_PI, 12, 1e-6);
    r.flags = 0;
    EXPECT_FALSE(geo.landing(r, *cur).has_value());
}

TEST(GazeSource, SaccadeRecordsCarryTheirLandingIntoTheTimeline) {
    const GazeGeometry geo;
    fovea_gaze_record r{};
    r.t_capture_ns = 50 * kMs;
    r.combined.valid = FOVEA_VALID;
    r.event = FOVEA_EVENT_SACCADE;
    r.flags = FOVEA_FLAG_LANDING_VALID;
    r.saccade_onset_ns = 40 * kMs;
    r.saccade_amplitude_deg = 3;
    r.landing_deg_x = 8;
    const GazeSample s = to_sample(r, geo);
    EXPECT_TRUE(s.valid);
    EXPECT_TRUE(s.saccade);
    EXPECT_EQ(s.saccade_onset_ns, 40 * kMs);
    r.saccade_onset_ns = 60 * kMs;  // an onset after the sample cannot be right
    EXPECT_FALSE(to_sample(r, geo).saccade);
}

TEST(GazeSource, AbsentDaemonGivesNoDataWithoutBlocking) {
    GazeSourceOptions o;
    o.instance = "openxr-absent-" + std::to_string(getpid());
    GazeSource src(o);
    const int64_t t0 = monotonic_now_ns();
    for (int i = 0; i < 1000; ++i) EXPECT_EQ(src.at(t0).status, GazeStatus::kNoData);
    EXPECT_LT(monotonic_now_ns() - t0, 500 * kMs);  // 1000 calls, attach attempts rate-limited
    EXPECT_EQ(src.counters().attaches, 0u);
}

TEST(GazeSource, ThreadsLocatingWhileTheWriterPublishesAndRestarts) {
    // A real ring: one writer at ~1 kHz that is replaced half-way (a restarted fovead), and
    // three threads asking for the gaze as an app's render and simulation threads would.
    fovea::ring::WriterOptions w;
    w.instance = "openxr-threads-" + std::to_string(getpid());
    w.slot_count = 256;
    auto writer = std::make_unique<fovea::ring::RingWriter>(
        std::move(fovea::ring::RingWriter::create(w)).value());
    GazeSourceOptions o;
    o.instance = w.instance;
    o.retry_ns = kMs;
    GazeSource src(o);
    std::atomic<bool> stop{false};
    std::atomic<int> tracked{0};
    std::vector<std::thread> apps;
    for (int i = 0; i < 3; ++i)
        apps.emplace_back([&] {
            while (!stop) {
                const GazeEstimate e = src.at(monotonic_now_ns() + 10 * kMs);
                if (e.tracked()) ++tracked;
                EXPECT_TRUE(std::isfinite(e.direction[0]) && std::isfinite(e.direction[2]));
            }
        });
    for (int n = 0; n < 400; ++n) {
        if (n == 200) {
            writer.reset();  // the old generation closes; a new one follows
            writer = std::make_unique<fovea::ring::RingWriter>(
                std::move(fovea::ring::RingWriter::create(w)).value());
        }
        fovea_gaze_record r{};
        r.t_capture_ns = monotonic_now_ns();
        r.combined.valid = FOVEA_VALID;
        r.combined.deg_x = static_cast<float>(n % 20);
        writer->publish(r);
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    stop = true;
    for (auto& t : apps) t.join();
    EXPECT_GT(tracked.load(), 0);
    const GazeSource::Counters c = src.counters();
    EXPECT_GE(c.attaches, 1u);
    EXPECT_GE(c.restarts + c.attaches, 2u);  // followed the second writer
    EXPECT_GT(c.records, 300u);
}

TEST(GazeSource, FollowsAWriterThatReplacedAKilledOneAtTheNextLocate) {
    // A fovead killed with -9 leaves its ring open (never marked closed); the restarted fovead
    // unlinks it and publishes a new generation. The next locate must read the new gaze, not wait
    // up to 100 ms for the client library's own restart check while the gaze reads as stale.
    fovea::ring::WriterOptions w;
    w.instance = "openxr-killed-" + std::to_string(getpid());
    w.slot_count = 256;
    auto killed = std::move(fovea::ring::RingWriter::create(w)).value();
    auto publish = [](fovea::ring::RingWriter& writer, float deg) {
        fovea_gaze_record r{};
        r.t_capture_ns = monotonic_now_ns();
        r.combined.valid = FOVEA_VALID;
        r.combined.deg_x = deg;
        writer.publish(r);
        return r.t_capture_ns;
    };
    GazeSourceOptions o;
    o.instance = w.instance;
    GazeSource src(o);
    int64_t t = 0;
    for (int i = 0; i < 5; ++i) t = publish(killed, 1);
    ASSERT_TRUE(src.at(t).tracked());
    ASSERT_TRUE(src.at(t).tracked());  // nothing new: the library's 100 ms check starts now
    auto restarted = std::move(fovea::ring::RingWriter::create(w)).value();
    publish(restarted, 7);
    t = publish(restarted, 7);
    const GazeEstimate e = src.at(t);
    EXPECT_TRUE(e.tracked());
    EXPECT_EQ(e.t_newest_ns, t);
    EXPECT_EQ(src.counters().restarts, 1u);
}

}  // namespace
