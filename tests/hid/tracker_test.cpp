// Eye and Head Trackers (page 0x12): several descriptors written from the spec (different report
// IDs, field orders, sizes, units, with and without head tracker); reports packed at offsets the
// test computes itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "hid/hid_driver.hpp"
#include "hid/session.hpp"
#include "hid/tracker.hpp"
#include "tracker_descriptors.hpp"

using namespace fovea::drivers::hid;
using fovea::test::DescriptorBuilder;
using fovea::test::kConstVarAbs;
using fovea::test::kDataVarAbs;
using fovea::test::kMax32;
using fovea::test::kMin32;
using fovea::test::kNullState;
using fovea::test::ReportBuilder;

namespace {

uint64_t u32(int64_t v) { return static_cast<uint64_t>(v) & 0xFFFFFFFFull; }

// Descriptor A: the layout of the Windows reference eye tracker, written from HUTRR74: report ID
// 0x10 Tracking Data (reference_tracking_data: 3 padding bytes, a 64-bit timestamp declared as 8
// one-byte fields, gaze point and both eye positions as 32-bit signed micrometres); Capabilities
// 0x11, Configuration 0x12 and Status 0x13 feature reports.
DescriptorBuilder descriptor_a() {
    DescriptorBuilder d;
    d.usage_page(0x12).usage(0x01).collection(1);
    fovea::test::reference_tracking_data(d);
    d.usage(0x11).collection(2).report_id(0x11);
    d.report_size(8).report_count(1).logical_min(1).logical_max(4).usage(0x100).feature(
        kConstVarAbs);  // quality @0
    d.report_count(5).report_size(32).logical_min(0).logical_max(kMax32);
    d.usage(0x101).usage(0x102).usage(0x103).usage(0x104).usage(0x105).feature(kConstVarAbs);
    d.end_collection();  // 8, 40, 72, 104, 136
    d.usage(0x12).collection(2).report_id(0x12);
    d.report_size(8).report_count(1).feature(kConstVarAbs);  // padding @0
    d.report_size(16)
        .logical_min(0)
        .logical_max(0xFFFF)
        .usage(0x200)
        .feature(kConstVarAbs)
        .usage(0x201)
        .feature(kConstVarAbs);  // 8, 24
    d.report_size(32).logical_min(0).logical_max(kMax32).usage(0x202).feature(kConstVarAbs);  // 40
    d.report_size(16).logical_min(0).logical_max(0xFFFF).usage(0x203).feature(kConstVarAbs);  // 72
    d.report_size(32)
        .report_count(2)
        .logical_min(0)
        .logical_max(kMax32)
        .usage(0x204)
        .usage(0x205)
        .feature(kConstVarAbs);  // 88, 120
    d.end_collection();
    d.usage(0x13).collection(2).report_id(0x13);
    d.report_size(8).report_count(1).feature(kConstVarAbs);             // pad @0
    d.logical_min(0).logical_max(4).usage(0x301).feature(kDataVarAbs);  // 8
    d.report_size(16).logical_min(0).logical_max(0x7FFF).usage(0x300).feature(kDataVarAbs);  // 16
    d.end_collection();
    d.end_collection();
    return d;
}

TEST(HidTracker, ReferenceLayoutDecodesGazeEyesTimestampAndFeatures) {
    auto session = TrackerSession::create(descriptor_a().bytes);
    ASSERT_TRUE(session.ok()) << session.error().message;
    const auto& layout = session->layout();
    EXPECT_TRUE(layout.eye_tracker);
    EXPECT_FALSE(layout.head_tracker);
    ASSERT_EQ(layout.tracking.size(), 1u);
    EXPECT_EQ(layout.tracking[0].report_id, 0x10);
    EXPECT_EQ(layout.tracking[0].wire_bytes, 44u);
    std::vector<uint8_t> ids = layout.features.report_ids;
    std::sort(ids.begin(), ids.end());
    EXPECT_EQ(ids, (std::vector<uint8_t>{0x11, 0x12, 0x13}));

    ReportBuilder caps(23, 0x11);
    caps.put(0, 8, 1)
        .put(8, 32, 450000)
        .put(40, 32, 650000)
        .put(72, 32, 950000)
        .put(104, 32, 600000)
        .put(136, 32, 340000);
    EXPECT_EQ(session->apply_feature(caps.data), 6);
    ReportBuilder conf(19, 0x12);
    conf.put(8, 16, 0x10AC)
        .put(24, 16, 0xA0C2)
        .put(40, 32, 123456)
        .put(72, 16, 0x2013)
        .put(88, 32, 531000)
        .put(120, 32, 299000);
    EXPECT_EQ(session->apply_feature(conf.data), 6);
    ReportBuilder status(4, 0x13);
    status.put(8, 8, 4).put(16, 16, 90);
    EXPECT_EQ(session->apply_feature(status.data), 2);
    const TrackerInfo& info = session->info();
    EXPECT_EQ(info.tracker_quality, 1u);
    EXPECT_DOUBLE_EQ(*info.optimum_tracking_distance_um, 650000);
    EXPECT_DOUBLE_EQ(*info.max_screen_height_um, 340000);
    EXPECT_EQ(info.display_manufacturer_id, 0x10ACu);
    EXPECT_EQ(info.display_serial_number, 123456u);
    EXPECT_DOUBLE_EQ(*info.calibrated_screen_width_um, 531000);
    EXPECT_DOUBLE_EQ(*info.sampling_frequency_hz, 90);
    EXPECT_EQ(info.configuration_status, ConfigurationStatus::kUserCalibrationNeeded);
    EXPECT_STREQ(to_string(info.configuration_status), "user calibration needed");

    ReportBuilder rep(43, 0x10);
    const uint64_t stamp = 0x0102030405060708ull;
    rep.put(24, 64, stamp).put(88, 32, 265500).put(120, 32, 74750);
    rep.put(152, 32, u32(-32000)).put(184, 32, 1000).put(216, 32, 600000);
    rep.put(248, 32, 32000).put(280, 32, 1000).put(312, 32, 600000);
    fovea::gaze::RawSample s;
    fovea::drivers::HeadPose pose;
    const auto out = session->on_report(rep.data, 42, 7, s, pose);
    ASSERT_EQ(out.status, DecodeStatus::kOk);
    EXPECT_TRUE(out.gaze);
    EXPECT_FALSE(out.head);
    EXPECT_EQ(s.device_ticks, stamp);
    EXPECT_EQ(s.t_receive_ns, 42);
    EXPECT_EQ(s.device_id, 7u);
    EXPECT_DOUBLE_EQ(s.left.x, 0.5);
    EXPECT_DOUBLE_EQ(s.left.y, 0.25);
    EXPECT_TRUE(s.left.valid && s.right.valid);
    EXPECT_EQ(session->clock().counter_bits, 64);
    EXPECT_DOUBLE_EQ(session->clock().tick_hz, 1e6);

    TrackingSample t;
    ASSERT_EQ(decode_tracking(session->descriptor(), layout, rep.data, t), DecodeStatus::kOk);
    EXPECT_DOUBLE_EQ((*t.left_eye_um)[0], -32000);
    EXPECT_DOUBLE_EQ((*t.right_eye_um)[2], 600000);
}

TEST(HidTracker, ShortReportIsDroppedAndUnknownReportIgnored) {
    auto session = TrackerSession::create(descriptor_a().bytes, 531000, 299000);
    ASSERT_TRUE(session.ok());
    fovea::gaze::RawSample s;
    fovea::drivers::HeadPose pose;
    std::vector<uint8_t> short_rep(20, 0);
    short_rep[0] = 0x10;
    EXPECT_EQ(session->on_report(short_rep, 0, 0, s, pose).status, DecodeStatus::kTooShort);
    std::vector<uint8_t> other(44, 0);
    other[0] = 0x33;
    EXPECT_EQ(session->on_report(other, 0, 0, s, pose).status, DecodeStatus::kUnknownReport);
    EXPECT_EQ(session->on_report({}, 0, 0, s, pose).status, DecodeStatus::kTooShort);
    // Longer than declared (kernel padding): decoded from the declared prefix.
    std::vector<uint8_t> padded(64, 0);
    padded[0] = 0x10;
    EXPECT_EQ(session->on_report(padded, 0, 0, s, pose).status, DecodeStatus::kOk);
}

// Descriptor B: report ID 5, gaze first as 16-bit signed centimetres x 10^-2, then a 32-bit
// timestamp in seconds x 10^-4; Status report 7 with sampling frequency before configuration
// status; no Configuration report (screen size from the fallback).
DescriptorBuilder descriptor_b() {
    DescriptorBuilder d;
    d.usage_page(0x12).usage(0x01).collection(1);
    d.usage(0x10).collection(2).report_id(5);
    d.usage(0x24)
        .collection(0)
        .logical_min(-32768)
        .logical_max(32767)
        .report_size(16)
        .report_count(2)
        .unit(0x11)
        .unit_exponent(-2)
        .usage(0x21)
        .usage(0x22)
        .input(kDataVarAbs)
        .end_collection();  // X 0, Y 16
    d.unit(0x1001)
        .unit_exponent(-4)
        .logical_min(0)
        .logical_max(kMax32)
        .report_size(32)
        .report_count(1)
        .usage(0x20)
        .input(kDataVarAbs);  // 32
    d.end_collection();
    d.usage(0x13)
        .collection(2)
        .report_id(7)
        .unit(0)
        .unit_exponent(0)
        .logical_min(0)
        .logical_max(255)
        .report_size(8)
        .report_count(1)
        .usage(0x300)
        .feature(kDataVarAbs)
        .usage(0x301)
        .feature(kDataVarAbs)
        .end_collection();
    d.end_collection();
    return d;
}

TEST(HidTracker, CentimetreUnitsAndOtherFieldOrderAreHonoured) {
    auto session = TrackerSession::create(descriptor_b().bytes, 531000, 299000);
    ASSERT_TRUE(session.ok()) << session.error().message;
    ASSERT_EQ(session->layout().tracking.size(), 1u);
    EXPECT_EQ(session->layout().tracking[0].report_id, 5);
    EXPECT_EQ(session->layout().tracking[0].wire_bytes, 9u);
    ReportBuilder status(2, 7);
    status.put(0, 8, 120).put(8, 8, 1);
    EXPECT_EQ(session->apply_feature(status.data), 2);
    EXPECT_EQ(session->info().configuration_status, ConfigurationStatus::kReady);
    EXPECT_DOUBLE_EQ(*session->info().sampling_frequency_hz, 120);

    ReportBuilder rep(8, 5);
    rep.put(0, 16, 2655).put(16, 16, static_cast<uint16_t>(-1000)).put(32, 32, 987654);
    TrackingSample t;
    ASSERT_EQ(decode_tracking(session->descriptor(), session->layout(), rep.data, t),
              DecodeStatus::kOk);
    EXPECT_NEAR((*t.gaze_um)[0], 265500, 1e-6);  // 26.55 cm
    EXPECT_NEAR((*t.gaze_um)[1], -100000, 1e-6);
    EXPECT_EQ(*t.timestamp, 987654u);
    EXPECT_EQ(session->clock().counter_bits, 32);
    EXPECT_NEAR(session->clock().tick_hz, 1e4, 1e-6);
    fovea::gaze::RawSample s;
    fovea::drivers::HeadPose pose;
    ASSERT_TRUE(session->on_report(rep.data, 0, 0, s, pose).gaze);
    EXPECT_NEAR(s.left.x, 0.5, 1e-12);
    EXPECT_NEAR(s.left.y, -100000.0 / 299000.0, 1e-12);  // above the screen: reported as is
}

// Descriptor C (unnumbered_packed_descriptor): no report IDs, 12-bit gaze with a physical range
// (0..4094 -> 0..530000 um) and a null state, 4 bits of padding, a 20-bit timestamp; calibrated
// size in an unnumbered feature.
DescriptorBuilder descriptor_c() { return fovea::test::unnumbered_packed_descriptor(); }

TEST(HidTracker, UnnumberedPackedFieldsWithPhysicalRangeAndNullValues) {
    auto session = TrackerSession::create(descriptor_c().bytes);
    ASSERT_TRUE(session.ok()) << session.error().message;
    EXPECT_FALSE(session->layout().numbered);
    EXPECT_EQ(session->layout().tracking.at(0).wire_bytes, 6u);
    ReportBuilder conf(8);
    conf.put(0, 32, 530000).put(32, 32, 300000);
    EXPECT_EQ(session->apply_feature(conf.data), 2);

    ReportBuilder rep(6);
    rep.put(0, 12, 2047).put(12, 12, 1000).put(28, 20, 0xABCDE);
    fovea::gaze::RawSample s;
    fovea::drivers::HeadPose pose;
    ASSERT_EQ(session->on_report(rep.data, 0, 0, s, pose).status, DecodeStatus::kOk);
    EXPECT_NEAR(s.left.x, 2047.0 / 4094.0, 1e-12);
    EXPECT_NEAR(s.left.y, 1000.0 * 530000.0 / 4094.0 / 300000.0, 1e-12);
    EXPECT_TRUE(s.left.valid);
    EXPECT_EQ(s.device_ticks, 0xABCDEu);
    EXPECT_EQ(session->clock().counter_bits, 20);

    ReportBuilder lost(6);
    lost.put(0, 12, 4095).put(12, 12, 4095).put(28, 20, 5);  // out of range: HID null
    ASSERT_TRUE(session->on_report(lost.data, 0, 0, s, pose).gaze);
    EXPECT_FALSE(s.left.valid);
    EXPECT_FALSE(s.right.valid);
    EXPECT_EQ(s.device_ticks, 5u);
}

// Descriptor D: a mouse (report 1) first, then an eye tracker named by an extended usage while
// the Usage Page is still Generic Desktop (report 2, with Push/Pop and a long item), then a head
// tracker (report 3) with head position, head direction point and rotations in milliradians.
DescriptorBuilder descriptor_d() {
    DescriptorBuilder d;
    d.usage_page(0x01).usage(0x02).collection(1).report_id(1);
    d.usage_page(0x09)
        .usage_min(1)
        .usage_max(3)
        .logical_min(0)
        .logical_max(1)
        .report_size(1)
        .report_count(3)
        .input(kDataVarAbs)
        .report_count(5)
        .input(kConstVarAbs);
    d.usage_page(0x01);
    fovea::test::mouse_xy(d);
    d.end_collection();
    d.usage_ext(0x12, 0x01).collection(1);
    d.usage_ext(0x12, 0x10).collection(2).report_id(2).usage_page(0x12);
    d.push()
        .logical_min(0)
        .logical_max(0xFFFF)
        .report_size(16)
        .report_count(1)
        .usage(0x20)
        .input(kDataVarAbs)
        .pop();  // 0
    d.long_item(0xF1, {0xDE, 0xAD});
    d.logical_min(-1000000).logical_max(1000000).report_size(24).report_count(2);
    fovea::test::gaze_point(d);  // 16, 40
    d.end_collection().end_collection();
    d.usage(0x02).collection(1).usage(0x10).collection(2).report_id(3);
    d.logical_min(0)
        .sized(0x24, 0xFFFFFFFF, 4)
        .report_size(32)
        .report_count(1)
        .usage(0x20)
        .input(kDataVarAbs);  // 0
    d.logical_min(kMin32).logical_max(kMax32).report_count(3);
    fovea::test::xyz_point(d, 0x27);     // 32, 64, 96
    fovea::test::xyz_point(d, 0x28);     // 128, 160, 192
    fovea::test::head_rotation_mrad(d);  // 224, 240, 256
    d.end_collection().end_collection();
    return d;
}

TEST(HidTracker, EyeAndHeadTrackersInOneDeviceWithAMouse) {
    int gaze_count = 0, head_count = 0;
    auto session = TrackerSession::create(descriptor_d().bytes, 600000, 340000);
    ASSERT_TRUE(session.ok()) << session.error().message;
    const auto& layout = session->layout();
    EXPECT_TRUE(layout.eye_tracker && layout.head_tracker);
    ASSERT_EQ(layout.tracking.size(), 2u);
    fovea::gaze::RawSample s;
    fovea::drivers::HeadPose pose;

    ReportBuilder mouse(3, 1);
    EXPECT_EQ(session->on_report(mouse.data, 0, 0, s, pose).status, DecodeStatus::kUnknownReport);

    ReportBuilder eye(8, 2);
    eye.put(0, 16, 777).put(16, 24, 300000).put(40, 24, 170000);
    auto out = session->on_report(eye.data, 0, 0, s, pose);
    ASSERT_EQ(out.status, DecodeStatus::kOk);
    gaze_count += out.gaze;
    head_count += out.head;
    EXPECT_EQ(s.device_ticks, 777u);
    EXPECT_DOUBLE_EQ(s.right.x, 0.5);
    EXPECT_DOUBLE_EQ(s.right.y, 0.5);

    ReportBuilder head(34, 3);
    head.put(0, 32, 0xFFFFFFF0u);
    head.put(32, 32, 10000).put(64, 32, u32(-20000)).put(96, 32, 650000);
    head.put(128, 32, 10000).put(160, 32, u32(-20000)).put(192, 32, 0);  // straight ahead (-z)
    head.put(224, 16, 0).put(240, 16, 1571).put(256, 16, 0);
    out = session->on_report(head.data, 99, 3, s, pose);
    ASSERT_EQ(out.status, DecodeStatus::kOk);
    gaze_count += out.gaze;
    head_count += out.head;
    EXPECT_EQ(gaze_count, 1);
    EXPECT_EQ(head_count, 1);
    EXPECT_EQ(pose.device_ticks, 0xFFFFFFF0u);
    EXPECT_EQ(pose.t_receive_ns, 99);
    EXPECT_NEAR(pose.position_m[0], 0.01, 1e-12);
    EXPECT_NEAR(pose.position_m[1], -0.02, 1e-12);
    EXPECT_NEAR(pose.position_m[2], 0.65, 1e-12);
    ASSERT_TRUE(pose.direction_valid);
    EXPECT_NEAR(pose.direction[2], -1.0, 1e-12);
    ASSERT_TRUE(pose.rotation_valid);
    // 1.571 rad about Y: q = (0, sin(a/2), 0, cos(a/2)).
    EXPECT_NEAR(pose.rotation_quat[1], std::sin(0.7855), 1e-9);
    EXPECT_NEAR(pose.rotation_quat[3], std::cos(0.7855), 1e-9);
    EXPECT_NEAR(pose.rotation_quat[0], 0.0, 1e-12);
}

TEST(HidTracker, FieldOrderAndReportIdDoNotMatter) {
    // Every order of the four Tracking Data blocks, each with its own report ID; the test adds
    // up the offsets itself.
    std::array<int, 4> order{0, 1, 2, 3};  // 0 timestamp, 1 gaze, 2 left eye, 3 right eye
    uint8_t report_id = 1;
    int permutations = 0;
    do {
        DescriptorBuilder d;
        d.usage_page(0x12).usage(0x01).collection(1).usage(0x10).collection(2).report_id(report_id);
        uint32_t offsets[4] = {};
        uint32_t bit = 0;
        for (int block : order) {
            offsets[block] = bit;
            if (block == 0) {
                d.logical_min(0)
                    .logical_max(0xFFFF)
                    .report_size(16)
                    .report_count(1)
                    .usage(0x20)
                    .input(kDataVarAbs);
                bit += 16;
                continue;
            }
            const uint16_t point = block == 1 ? 0x24 : block == 2 ? 0x25 : 0x26;
            const uint32_t axes = block == 1 ? 2 : 3;
            d.logical_min(kMin32)
                .logical_max(kMax32)
                .report_size(32)
                .report_count(axes)
                .usage(point)
                .collection(0)
                .usage(0x21)
                .usage(0x22);
            if (axes == 3) d.usage(0x23);
            d.input(kDataVarAbs).end_collection();
            bit += 32 * axes;
        }
        d.end_collection().end_collection();
        auto session = TrackerSession::create(d.bytes, 500000, 250000);
        ASSERT_TRUE(session.ok()) << session.error().message;
        ReportBuilder rep(bit / 8, report_id);
        rep.put(offsets[0], 16, 4242);
        rep.put(offsets[1], 32, 125000).put(offsets[1] + 32, 32, 200000);
        rep.put(offsets[2], 32, u32(-31000)).put(offsets[2] + 64, 32, 610000);
        rep.put(offsets[3], 32, 33000).put(offsets[3] + 64, 32, 620000);
        TrackingSample t;
        ASSERT_EQ(decode_tracking(session->descriptor(), session->layout(), rep.data, t),
                  DecodeStatus::kOk);
        EXPECT_EQ(t.timestamp, 4242u);
        EXPECT_DOUBLE_EQ((*t.gaze_um)[0], 125000);
        EXPECT_DOUBLE_EQ((*t.gaze_um)[1], 200000);
        EXPECT_DOUBLE_EQ((*t.left_eye_um)[0], -31000);
        EXPECT_DOUBLE_EQ((*t.left_eye_um)[2], 610000);
        EXPECT_DOUBLE_EQ((*t.right_eye_um)[0], 33000);
        EXPECT_DOUBLE_EQ((*t.right_eye_um)[2], 620000);
        ++report_id;
        ++permutations;
    } while (std::next_permutation(order.begin(), order.end()));
    EXPECT_EQ(permutations, 24);
}

TEST(HidTracker, NullEyePositionMarksThatEyeInvalid) {
    DescriptorBuilder d;
    d.usage_page(0x12).usage(0x01).collection(1).usage(0x10).collection(2).report_id(9);
    d.logical_min(0).logical_max(1000000).report_size(32).report_count(2);
    fovea::test::gaze_point(d, kDataVarAbs | kNullState);
    d.report_count(3);
    fovea::test::xyz_point(d, 0x25, kDataVarAbs | kNullState);
    fovea::test::xyz_point(d, 0x26, kDataVarAbs | kNullState);
    d.end_collection().end_collection();
    auto session = TrackerSession::create(d.bytes, 500000, 300000);
    ASSERT_TRUE(session.ok());
    ReportBuilder rep(32, 9);
    rep.put(0, 32, 250000).put(32, 32, 150000);
    rep.put(64, 32, 0xFFFFFFFF).put(96, 32, 0xFFFFFFFF).put(128, 32, 0xFFFFFFFF);  // left lost
    rep.put(160, 32, 30000).put(192, 32, 0).put(224, 32, 600000);
    fovea::gaze::RawSample s;
    fovea::drivers::HeadPose pose;
    ASSERT_TRUE(session->on_report(rep.data, 0, 0, s, pose).gaze);
    EXPECT_FALSE(s.left.valid);
    EXPECT_TRUE(s.right.valid);
    EXPECT_DOUBLE_EQ(s.right.x, 0.5);
}

TEST(HidTracker, DescriptorsWithoutATrackerAreRejectedClearly) {
    DescriptorBuilder mouse;
    mouse.usage_page(0x01)
        .usage(0x02)
        .collection(1)
        .usage(0x30)
        .report_size(8)
        .report_count(1)
        .input(kDataVarAbs)
        .end_collection();
    auto s = TrackerSession::create(mouse.bytes);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("no Eye Tracker"), std::string::npos);
    DescriptorBuilder empty_tracker;
    empty_tracker.usage_page(0x12)
        .usage(0x01)
        .collection(1)
        .usage(0x400)
        .report_size(8)
        .report_count(1)
        .feature(kDataVarAbs)
        .end_collection();
    s = TrackerSession::create(empty_tracker.bytes);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("no Tracking Data"), std::string::npos);
}

TEST(HidTracker, GazeNormalizationNeedsAPositiveScreenSize) {
    const auto n = gaze_to_normalized({265500, 149500}, 531000, 299000);
    EXPECT_DOUBLE_EQ(n[0], 0.5);
    EXPECT_DOUBLE_EQ(n[1], 0.5);
    EXPECT_TRUE(std::isnan(gaze_to_normalized({1, 1}, 0, 299000)[0]));
    EXPECT_TRUE(std::isnan(gaze_to_normalized({1, 1}, 531000, -1)[1]));
    auto session = TrackerSession::create(descriptor_b().bytes);  // no size anywhere
    ASSERT_TRUE(session.ok());
    ReportBuilder rep(8, 5);
    rep.put(0, 16, 100).put(16, 16, 100);
    fovea::gaze::RawSample s;
    fovea::drivers::HeadPose pose;
    ASSERT_TRUE(session->on_report(rep.data, 0, 0, s, pose).gaze);
    EXPECT_FALSE(s.left.valid);
}

TEST(HidTracker, HeadPoseRotationFollowsZyxOrder) {
    TrackingSample t;
    t.rotation_deg = std::array<double, 3>{90, 0, 0};
    auto p = to_head_pose(t);
    EXPECT_NEAR(p.rotation_quat[0], std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(p.rotation_quat[3], std::sqrt(0.5), 1e-12);
    t.rotation_deg = std::array<double, 3>{0, 0, 180};
    p = to_head_pose(t);
    EXPECT_NEAR(p.rotation_quat[2], 1.0, 1e-12);
    EXPECT_FALSE(p.position_valid);
    EXPECT_FALSE(p.direction_valid);
}

}  // namespace
