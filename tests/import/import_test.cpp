// fovea::import on small texts written to pin one behaviour each, then on every real file of
// ../shared/data that the readers cover, with counts taken independently of the readers.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <msgpack.hpp>

#include "fovea/import/pupil_datum.hpp"
#include "fovea/import/reader.hpp"
#include "recordings.hpp"

namespace fovea::import {
namespace {

namespace fs = std::filesystem;

struct Read {
    SourceInfo info;
    std::vector<Sample> samples;
    std::vector<Marker> markers;
    std::vector<LabelledEvent> events;
    ReadStats stats;
};

Read read_all(Reader& r) {
    Read out;
    out.info = r.info();
    for (Item it = r.next(); it != Item::kEnd; it = r.next()) {
        if (it == Item::kSample) out.samples.push_back(r.sample());
        if (it == Item::kMarker) out.markers.push_back(r.marker());
        if (it == Item::kEvent) out.events.push_back(r.event());
    }
    out.stats = r.stats();
    return out;
}

Read read_text(const std::string& text, const Options& o = {}) {
    auto r = open_memory(text, "t", o);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    if (!r.ok()) return {};
    return read_all(**r);
}

bool has_issue(const ReadStats& s, const std::string& what) {
    for (const auto& i : s.issues)
        if (i.find(what) != std::string::npos) return true;
    return false;
}

const char* kLund =
    "# sampFreq=500 viewDist_m=0.67 screenDim_m=0.38,0.3 screenRes_px=1024,768 source=x\n"
    "t_us,pupil_h,pupil_v,x_px,y_px,label\n"
    "1000,24,21,512,384,1\n"
    "3000,24,21,0,0,5\n"
    "5000,24,21,256,192,2\n"
    "garbage,row\n"
    "4000,24,21,256,192,2\n"  // time going backwards: kept, stamp repaired
    "nan,24,21,256,192,4\n"
    "11000,24,21,1024,768,3\n";

TEST(ImportLund2013, HeaderGeometryLabelsLostTrackingAndRepairedStamps) {
    const Read r = read_text(kLund);
    EXPECT_EQ(r.info.format, Format::kLund2013);
    EXPECT_EQ(r.info.screen.width_px, 1024);
    EXPECT_DOUBLE_EQ(r.info.screen.width_m, 0.38);
    EXPECT_DOUBLE_EQ(r.info.screen.distance_m, 0.67);
    EXPECT_DOUBLE_EQ(r.info.header_rate_hz, 500);
    EXPECT_DOUBLE_EQ(r.info.measured_rate_hz, 500);
    ASSERT_EQ(r.samples.size(), 6u);
    EXPECT_EQ(r.stats.skipped, 1u);
    EXPECT_TRUE(has_issue(r.stats, "t:6: expected 6 fields, got 2"));
    EXPECT_DOUBLE_EQ(r.samples[0].raw.left.x, 0.5);
    EXPECT_FALSE(r.samples[1].raw.left.valid);  // 0,0 is lost tracking
    EXPECT_FALSE(r.samples[0].raw.right.valid);
    EXPECT_EQ(r.samples[1].raw.truth, gaze::Event::kBlink);
    EXPECT_EQ(r.samples[5].labels[0], gaze::Event::kPso);
    EXPECT_EQ(r.samples[4].label_codes[0], 4);
    // 4000 after 5000 and then NaN: previous + 2 ms each, flagged and counted.
    EXPECT_TRUE(r.samples[3].time_repaired);
    EXPECT_NEAR(r.samples[3].time_s, 0.007, 1e-12);
    EXPECT_NEAR(r.samples[4].time_s, 0.009, 1e-12);
    EXPECT_EQ(r.samples[4].raw.device_ticks, 9000u);
    EXPECT_EQ(r.stats.repaired_times, 2u);
    EXPECT_EQ(r.samples[5].raw.device_ticks, 11000u);
    EXPECT_EQ(r.samples[5].line, 9u);
}

TEST(ImportLund2013, BadHeadersAreErrorsNamingTheLine) {
    auto r = open_memory("# sampFreq=abc screenRes_px=1,1\nt_us,x_px,y_px\n", "f.csv");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "f.csv:1: sampFreq must be a rate in Hz");
    r = open_memory("# sampFreq=500 screenRes_px=1024,768\nt_us,x_px\n", "f.csv");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "f.csv:2: the column line needs t_us, x_px and y_px");
    r = open_memory("hello\n", "f.csv");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("f.csv: unknown format"), std::string::npos);
    EXPECT_FALSE(open("/nonexistent/file.csv").ok());
}

TEST(ImportFoveaCsv, ColumnsByNameBothEyesAndEvents) {
    const Read r = read_text(
        "# fovea gaze recording v1 instance=t\n"
        "event,right_valid,right_y,right_x,left_valid,left_pupil_mm,left_y,left_x,t_capture_ns\n"
        "saccade,1,0.3,0.4,1,3.5,0.2,0.1,1000000000\n"
        "fixation,0,,,1,3.6,0.21,0.11,1004000000\n"
        "fixation,1,0.3,x,1,3.6,0.21,0.11,1008000000\n");
    EXPECT_TRUE(r.info.binocular);
    EXPECT_TRUE(r.info.has_pupil);
    EXPECT_EQ(r.info.clock.tick_hz, 1e9);
    ASSERT_EQ(r.samples.size(), 2u);
    EXPECT_EQ(r.samples[0].raw.device_ticks, 1'000'000'000u);
    EXPECT_DOUBLE_EQ(r.samples[0].raw.right.x, 0.4);
    EXPECT_DOUBLE_EQ(r.samples[0].raw.left.pupil_mm, 3.5);
    EXPECT_EQ(r.samples[0].raw.truth, gaze::Event::kSaccade);
    EXPECT_FALSE(r.samples[1].raw.right.valid);
    EXPECT_EQ(r.stats.skipped, 1u);
    EXPECT_TRUE(has_issue(r.stats, "t:5: eye fields are not numbers"));
}

TEST(ImportArff, MetadataLabelColumnsAndLostSamples) {
    const Read r = read_text(
        "% comment\n%@METADATA width_px 1280.0\n%@METADATA height_px 720.0\n"
        "%@METADATA width_mm 400.0\n%@METADATA height_mm 225.0\n%@METADATA distance_mm 450.0\n"
        "@RELATION gaze_labels\n\n@ATTRIBUTE time INTEGER\n@ATTRIBUTE x NUMERIC\n"
        "@ATTRIBUTE y NUMERIC\n@ATTRIBUTE confidence NUMERIC\n"
        "@ATTRIBUTE handlabeller1 INTEGER\n"
        "@ATTRIBUTE handlabeller_final {UNKNOWN,FIX,SACCADE,SP,NOISE}\n\n@DATA\n"
        "2000,640,360,1.0,1,FIX\n"
        "6000,0.0,0.0,0.0,4,NOISE\n"
        "10000,320,180,1.0,3,SP\n"
        "14000,320,180,1.0,2,BOGUS\n"
        "18000,320,180,1.0,2\n");
    EXPECT_EQ(r.info.format, Format::kArff);
    EXPECT_EQ(r.info.screen.width_px, 1280);
    EXPECT_DOUBLE_EQ(r.info.screen.distance_m, 0.45);
    ASSERT_EQ(r.info.label_columns.size(), 2u);
    EXPECT_EQ(r.info.label_columns[1], "handlabeller_final");
    EXPECT_DOUBLE_EQ(r.info.measured_rate_hz, 250);
    ASSERT_EQ(r.samples.size(), 3u);
    EXPECT_DOUBLE_EQ(r.samples[0].raw.left.x, 0.5);
    EXPECT_EQ(r.samples[0].labels[1], gaze::Event::kFixation);
    EXPECT_FALSE(r.samples[1].raw.left.valid);  // confidence 0
    EXPECT_EQ(r.samples[1].label_codes[0], 4);  // NOISE keeps its code
    EXPECT_EQ(r.samples[1].label_codes[1], 4);
    EXPECT_EQ(r.samples[2].labels[0], gaze::Event::kPursuit);
    EXPECT_EQ(r.samples[2].raw.device_ticks, 10000u);
    EXPECT_EQ(r.stats.skipped, 2u);
    EXPECT_TRUE(has_issue(r.stats, "t:20: a label is not one of"));
    EXPECT_TRUE(has_issue(r.stats, "t:21: expected 6 values, got 5"));
}

TEST(ImportArff, MetadataPixelSizesThatAreNotCountsAreIgnoredWithAnIssue) {
    // Found by fuzz_arff: 1.3e31 converted to int is undefined behaviour.
    const Read r = read_text(
        "%@METADATA width_px 1.27778e+31\n%@METADATA height_px -5\n"
        "@RELATION gaze_labels\n@ATTRIBUTE time INTEGER\n@ATTRIBUTE x NUMERIC\n"
        "@ATTRIBUTE y NUMERIC\n@DATA\n2000,640,360\n6000,641,361\n");
    EXPECT_EQ(r.info.screen.width_px, Screen{}.width_px);
    EXPECT_EQ(r.info.screen.height_px, Screen{}.height_px);
    EXPECT_TRUE(has_issue(r.stats, "t:1: @METADATA width_px is not a pixel count"));
    EXPECT_TRUE(has_issue(r.stats, "t:2: @METADATA height_px is not a pixel count"));
    EXPECT_EQ(r.samples.size(), 2u);
}

TEST(ImportArff, PixelsWithoutTheDisplaysSizeAreNoted) {
    // 360-degree GTA-VI files write zeros for the millimetres: no degrees come from those.
    const Read r = read_text(
        "%@METADATA width_px 1920\n%@METADATA height_px 1080\n%@METADATA width_mm 0.00\n"
        "%@METADATA height_mm 0.00\n%@METADATA distance_mm 0.00\n"
        "@RELATION gaze_labels\n@ATTRIBUTE time INTEGER\n@ATTRIBUTE x NUMERIC\n"
        "@ATTRIBUTE y NUMERIC\n@DATA\n2000,640,360\n6000,641,361\n");
    EXPECT_EQ(r.info.screen.width_px, 1920);
    EXPECT_TRUE(has_issue(r.stats, "no %@METADATA width_mm/height_mm/distance_mm above zero"));
    EXPECT_EQ(r.samples.size(), 2u);
}

TEST(ImportArff, A360DegreeRecordingIsRefusedNamingWhy) {
    auto r = open_memory(
        "@RELATION gaze_360\n%@METADATA width_px 3840\n%@METADATA height_px 1920\n"
        "@ATTRIBUTE time INTEGER\n@ATTRIBUTE x NUMERIC\n@ATTRIBUTE y NUMERIC\n"
        "@ATTRIBUTE x_head NUMERIC\n@ATTRIBUTE y_head NUMERIC\n"
        "@ATTRIBUTE angle_deg_head NUMERIC\n"
        "@ATTRIBUTE labeller_1 {unassigned,fixation,saccade,SP,noise,VOR,OKN}\n@DATA\n"
        "0,960.00,540.00,960.00,540.00,1.22,fixation\n",
        "v.arff");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("v.arff: @RELATION gaze_360"), std::string::npos)
        << r.error().message;
}

const char* kAscBinocular =
    "** CONVERTED FROM x.edf\n** SOURCE: EYELINK CL\n**\n"
    "MSG\t100 DISPLAY_COORDS = 0 0 1919 1079\n"
    "MSG\t150 !CAL Cal coeff:\n   4357.5  231.64 -84.095\n"
    "START\t1000 \tLEFT\tRIGHT\tSAMPLES\tEVENTS\n"
    "PUPIL\tDIAMETER\n"
    "EVENTS\tGAZE\tLEFT\tRIGHT\tRATE\t 500.00\tTRACKING\tCR\tFILTER\t2\n"
    "SAMPLES\tGAZE\tLEFT\tRIGHT\tRATE\t 500.00\tTRACKING\tCR\tFILTER\t2\n"
    "SFIX L   1000\n"
    "1000\t  960.0\t  540.0\t 3879.0\t  970.0\t  550.0\t 3785.0\t.....\n"
    "1002\t  961.0\t  541.0\t 3879.0\t  970.0\t  550.0\t 3785.0\t.C...\n"
    "MSG\t1003 -2 SYNCTIME\n"
    "1004\t   .\t   .\t    0.0\t  970.0\t  550.0\t 3785.0\tI...R\n"
    "EFIX L   1000\t1002\t4\t  960.5\t  540.5\t   3879\n"
    "ESACC R  1004\t1010\t8\t  970.0\t  550.0\t  1200.0\t  600.0\t   5.10\t    400\n"
    "EBLINK L 1004\t1006\t4\n"
    "INPUT\t1006\t127\n"
    "1006\t  bad\t  540.0\t 3879.0\t  970.0\t  550.0\t 3785.0\t.....\n"
    "END\t1010 \tSAMPLES\tEVENTS\tRES\t  45.90\t  46.06\n";

TEST(ImportEyelink, BinocularGazeSamplesFlagsMessagesAndParserEvents) {
    const Read r = read_text(kAscBinocular);
    EXPECT_EQ(r.info.format, Format::kEyelinkAsc);
    EXPECT_EQ(r.info.device, "EYELINK CL");
    EXPECT_TRUE(r.info.binocular);
    EXPECT_EQ(r.info.variant, "GAZE binocular");
    EXPECT_EQ(r.info.screen.width_px, 1920);
    EXPECT_DOUBLE_EQ(r.info.header_rate_hz, 500);
    ASSERT_EQ(r.samples.size(), 3u);  // the "4357.5 ..." continuation line is not a sample
    EXPECT_DOUBLE_EQ(r.samples[0].raw.left.x, 0.5);
    EXPECT_DOUBLE_EQ(r.samples[0].raw.left.y, 0.5);
    EXPECT_NEAR(r.samples[0].raw.right.x, 970.0 / 1920, 1e-12);
    EXPECT_EQ(r.samples[0].raw.device_ticks, 1'000'000u);
    EXPECT_DOUBLE_EQ(r.samples[0].pupil_raw[0], 3879.0);
    EXPECT_EQ(r.samples[1].flags, kLeftCrMissing);
    EXPECT_FALSE(r.samples[2].raw.left.valid);  // "." missing
    EXPECT_TRUE(r.samples[2].raw.right.valid);
    EXPECT_EQ(r.samples[2].flags, kInterpolated | kRightCrRecovering);
    EXPECT_EQ(r.stats.skipped, 1u);
    EXPECT_TRUE(has_issue(r.stats, "t:20: sample field 2 is not a number"));
    ASSERT_EQ(r.markers.size(), 4u);
    EXPECT_EQ(r.markers[0].text, "DISPLAY_COORDS = 0 0 1919 1079");
    EXPECT_EQ(r.markers[2].text, "SYNCTIME");
    EXPECT_DOUBLE_EQ(r.markers[2].time_s, 1.005);  // 1003 - (-2) ms
    EXPECT_EQ(r.markers[3].text, "INPUT 127");
    ASSERT_EQ(r.events.size(), 3u);
    EXPECT_EQ(r.events[0].type, gaze::Event::kFixation);
    EXPECT_EQ(r.events[0].eye, Eye::kLeft);
    EXPECT_NEAR(r.events[0].x, 960.5 / 1920, 1e-12);
    EXPECT_DOUBLE_EQ(r.events[0].pupil_raw, 3879);
    EXPECT_EQ(r.events[1].type, gaze::Event::kSaccade);
    EXPECT_EQ(r.events[1].eye, Eye::kRight);
    EXPECT_DOUBLE_EQ(r.events[1].amplitude_deg, 5.10);
    EXPECT_DOUBLE_EQ(r.events[1].peak_velocity_dps, 400);
    EXPECT_NEAR(r.events[1].end_x, 1200.0 / 1920, 1e-12);
    EXPECT_DOUBLE_EQ(r.events[1].start_s, 1.004);
    EXPECT_DOUBLE_EQ(r.events[1].end_s, 1.010);
    EXPECT_EQ(r.events[1].end_ticks, 1'010'000u);
    EXPECT_EQ(r.events[2].type, gaze::Event::kBlink);
}

TEST(ImportEyelink, MonocularHrefUsesTheDisplayGeometryAndPupilArea) {
    Options o;
    o.display = gaze::DisplayGeometry{};
    o.display->width_m = 0.6;
    o.display->distance_m = 0.6;
    const Read r = read_text(
        "** CONVERTED FROM x.edf\n"
        "START\t7451288 \tRIGHT\tSAMPLES\tEVENTS\nPUPIL\tAREA\n"
        "SAMPLES\tHREF\tRIGHT\tRATE\t1000.00\tTRACKING\tCR\tFILTER\t2\n"
        "7451288\t-3606.0\t-1638.0\t  829.0\t...\n"
        "7451289\t    0.0\t    0.0\t  827.0\t...\n"
        "7451290\t    0.0\t    0.0\t  82",  // cut off
        o);
    EXPECT_FALSE(r.info.binocular);
    EXPECT_EQ(r.info.variant, "HREF right");
    EXPECT_EQ(r.info.pupil_unit, "area (EyeLink a.u.)");
    ASSERT_EQ(r.samples.size(), 2u);
    EXPECT_FALSE(r.samples[0].raw.left.valid);
    // A plane 15000 units away: x/15000 = tan(angle); the display maps the angle back.
    EXPECT_NEAR(r.samples[0].raw.right.x, 0.5 - 3606.0 / 15000 * 0.6 / 0.6, 1e-9);
    EXPECT_DOUBLE_EQ(r.samples[1].raw.right.x, 0.5);
    EXPECT_TRUE(r.stats.truncated);
    EXPECT_TRUE(has_issue(r.stats, "t:7: last line has no line end"));
}

// ---- Pupil ----------------------------------------------------------------------------------

// A datum as Pupil Capture packs it: string keys, eye ids 0/1 as integer keys, base_data
// pupil datums as ExtType 13 wrapping their own msgpack.
std::string pupil_pupil(int id, double t, double mm) {
    msgpack::sbuffer b;
    msgpack::packer<msgpack::sbuffer> p(b);
    p.pack_map(5);
    p.pack("topic"), p.pack("pupil." + std::to_string(id));
    p.pack("id"), p.pack(id);
    p.pack("timestamp"), p.pack(t);
    p.pack("confidence"), p.pack(0.99);
    p.pack("diameter_3d"), p.pack(mm);
    return std::string(b.data(), b.size());
}

std::string pupil_gaze(const std::string& topic, double t, double conf, double x, double y) {
    msgpack::sbuffer b;
    msgpack::packer<msgpack::sbuffer> p(b);
    const bool bino = topic.find("01.") != std::string::npos;
    p.pack_map(7);
    p.pack("topic"), p.pack(topic);
    p.pack("timestamp"), p.pack(t);
    p.pack("confidence"), p.pack(conf);
    p.pack("norm_pos"), p.pack(std::vector<double>{x, y});
    if (bino) {
        p.pack("eye_centers_3d");
        p.pack_map(2);
        p.pack(0), p.pack(std::vector<double>{20, 14, -22});
        p.pack(1), p.pack(std::vector<double>{-40, 16, -19});
        p.pack("gaze_normals_3d");
        p.pack_map(2);
        p.pack(0), p.pack(std::vector<double>{-0.1, -0.1, 0.99});
        p.pack(1), p.pack(std::vector<double>{-0.07, -0.1, 0.99});
    } else {
        p.pack("eye_center_3d"), p.pack(std::vector<double>{20, 14, -22});
        p.pack("gaze_normal_3d"), p.pack(std::vector<double>{-0.1, -0.1, 0.99});
    }
    const std::vector<int> ids = bino                                     ? std::vector<int>{0, 1}
                                 : topic.find(".1.") != std::string::npos ? std::vector<int>{1}
                                                                          : std::vector<int>{0};
    p.pack("base_data");
    p.pack_array(static_cast<uint32_t>(ids.size()));
    for (int id : ids) {
        const std::string inner = pupil_pupil(id, t, 5.0 + id);
        p.pack_ext(inner.size(), 13);
        p.pack_ext_body(inner.data(), inner.size());
    }
    return std::string(b.data(), b.size());
}

std::string pldata_record(const std::string& topic, const std::string& datum) {
    msgpack::sbuffer b;
    msgpack::packer<msgpack::sbuffer> p(b);
    p.pack_array(2);
    p.pack(topic);
    p.pack_bin(datum.size());
    p.pack_bin_body(datum.data(), datum.size());
    return std::string(b.data(), b.size());
}

TEST(PupilDatum, BinocularThreeDWithIntegerEyeKeysAndExtTypeBaseData) {
    auto d = decode_pupil_datum(pupil_gaze("gaze.3d.01.", 12.5, 0.9, 0.25, 0.75));
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(d->topic, "gaze.3d.01.");
    EXPECT_TRUE(d->has_3d[0] && d->has_3d[1]);
    EXPECT_DOUBLE_EQ(d->eye_center_mm[1][0], -40);
    EXPECT_DOUBLE_EQ(d->gaze_normal[0][2], 0.99);
    EXPECT_EQ(d->base_data, 2);
    EXPECT_DOUBLE_EQ(d->diameter_mm[0], 5.0);
    EXPECT_DOUBLE_EQ(d->diameter_mm[1], 6.0);
    gaze::RawSample s;
    ASSERT_TRUE(pupil_sample(*d, 0.6, s));
    EXPECT_EQ(s.device_ticks, 12'500'000'000u);
    EXPECT_TRUE(s.left.valid && s.right.valid);
    EXPECT_DOUBLE_EQ(s.left.x, 0.25);
    EXPECT_DOUBLE_EQ(s.left.y, 0.25);         // origin bottom-left -> top-left
    EXPECT_DOUBLE_EQ(s.right.pupil_mm, 5.0);  // eye0 is the right eye
    EXPECT_DOUBLE_EQ(s.left.pupil_mm, 6.0);
}

TEST(PupilDatum, MonocularAndLowConfidence) {
    auto d = decode_pupil_datum(pupil_gaze("gaze.3d.1.", 1.0, 0.5, 0.5, 0.5));
    ASSERT_TRUE(d.ok());
    EXPECT_FALSE(d->has_3d[0]);
    EXPECT_TRUE(d->has_3d[1]);  // eye_center_3d of the topic's eye
    gaze::RawSample s;
    ASSERT_TRUE(pupil_sample(*d, 0.6, s));
    EXPECT_FALSE(s.left.valid);              // confidence 0.5 < 0.6
    EXPECT_DOUBLE_EQ(s.left.pupil_mm, 6.0);  // the pupil size is still known
    EXPECT_FALSE(s.right.valid);
    ASSERT_TRUE(pupil_sample(*d, 0.4, s));
    EXPECT_TRUE(s.left.valid);
    EXPECT_FALSE(s.right.valid);
    EXPECT_FALSE(decode_pupil_datum("\x93\x01").ok());
    EXPECT_FALSE(decode_pupil_datum("").ok());
}

TEST(ImportPldata, ResyncsOverGarbageReordersAndReportsACutRecord) {
    std::string bytes;
    for (int i = 0; i < 10; ++i) {
        // every third datum stored one step late, as Pupil's mapper does
        const int k = i % 3 == 1 ? i + 1 : i % 3 == 2 ? i - 1 : i;
        bytes += pldata_record("gaze", pupil_gaze("gaze.3d.01.", 100 + k * 0.004, 0.9, 0.5, 0.5));
        if (i == 4) bytes += "\x92\xc1garbage";  // 0xc1 is never used in msgpack
    }
    const std::string cut = pldata_record("gaze", pupil_gaze("gaze.3d.0.", 200, 0.9, 0.5, 0.5));
    bytes += cut.substr(0, cut.size() / 2);
    const Read r = read_text(bytes);
    EXPECT_EQ(r.info.format, Format::kPupilFolder);
    ASSERT_EQ(r.samples.size(), 10u);
    for (std::size_t i = 1; i < r.samples.size(); ++i)
        EXPECT_GT(r.samples[i].time_s, r.samples[i - 1].time_s);
    EXPECT_NEAR(r.info.measured_rate_hz, 250, 0.01);
    EXPECT_EQ(r.stats.skipped, 1u);  // the resync
    EXPECT_TRUE(r.stats.truncated);
    EXPECT_TRUE(has_issue(r.stats, "last record cut off"));
}

// A recording folder with gaze.pldata (3 datums) and a gaze_timestamps.npy of `version` and
// `shape` holding their 3 time stamps.
Read read_gaze_folder_with_npy(uint8_t version, const std::string& shape = "(3,)") {
    // Per process: ctest runs the tests that call this side by side (-j2).
    const fs::path dir =
        fs::temp_directory_path() / ("fovea_import_npy." + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::string pldata, values;
    for (int i = 0; i < 3; ++i) {
        const double t = 100 + i * 0.004;
        pldata += pldata_record("gaze", pupil_gaze("gaze.3d.01.", t, 0.9, 0.5, 0.5));
        char le[8];
        std::memcpy(le, &t, 8);  // little-endian host
        values.append(le, 8);
    }
    std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': " + shape + ", }";
    header.resize(117, ' ');
    header += '\n';
    std::string npy = std::string("\x93NUMPY", 6) + static_cast<char>(version) + '\0';
    npy += static_cast<char>(header.size() & 0xff);
    npy += static_cast<char>(header.size() >> 8);
    std::ofstream(dir / "gaze.pldata", std::ios::binary) << pldata;
    std::ofstream(dir / "gaze_timestamps.npy", std::ios::binary) << npy + header + values;
    auto r = open(dir.string());
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    Read out = r.ok() ? read_all(**r) : Read{};
    fs::remove_all(dir);
    return out;
}

// Found by fuzz_npy: the version byte was read as a signed char, so 0x80..0xff passed as
// version 1 and the header was taken from the wrong bytes.
TEST(ImportPldata, NpyOfAnUnknownVersionIsRefusedAndTheDatumStampsKept) {
    const Read good = read_gaze_folder_with_npy(1);
    EXPECT_EQ(good.samples.size(), 3u);
    EXPECT_FALSE(has_issue(good.stats, ".npy"));
    const Read bad = read_gaze_folder_with_npy(0xa5);
    EXPECT_TRUE(has_issue(bad.stats, "gaze_timestamps.npy: unsupported .npy version 165"));
    ASSERT_EQ(bad.samples.size(), 3u);  // the datums' own time stamps
    EXPECT_DOUBLE_EQ(bad.samples[2].time_s, 100.008);
}

// Found reading NpyDoubles for fuzz_npy (no invariant there catches a misread length): the
// shape's length went through strtoull, so "(-5,)" wrapped to 2^64 - 5, and only the first
// dimension was looked at, so a 2-D array read as its first row.
TEST(ImportPldata, NpyShapeMustBeOneNonNegativeLength) {
    for (const char* shape : {"(3,)", "(3, )", "(3)"}) {
        const Read r = read_gaze_folder_with_npy(1, shape);
        EXPECT_FALSE(has_issue(r.stats, ".npy")) << shape;
        EXPECT_EQ(r.samples.size(), 3u) << shape;
    }
    for (const char* shape : {"(-5,)", "(+3,)", "( 3,)", "(3, 1)", "(1, 3)", "()", "(3,,)"}) {
        const Read r = read_gaze_folder_with_npy(1, shape);
        EXPECT_TRUE(has_issue(r.stats, "gaze_timestamps.npy: .npy array is not one-dimensional"))
            << shape;
        EXPECT_EQ(r.samples.size(), 3u) << shape;  // the datums' own time stamps
    }
}

TEST(ImportPupilCsv, LslRelayEyesFromFiniteColumnsAndReorder) {
    const Read r = read_text(
        "timestamp,confidence,norm_pos_x,norm_pos_y,eye_center0_3d_x,eye_center1_3d_x,"
        "diameter0_3d,diameter1_3d\n"
        "10.000,0.9,0.4,0.3,1,2,4.4,4.7\n"
        "10.008,0.9,0.4,0.3,nan,2,nan,4.7\n"
        "10.004,0.3,0.4,0.3,1,nan,4.5,nan\n");
    EXPECT_EQ(r.info.format, Format::kPupilCsv);
    EXPECT_EQ(r.info.variant, "LSL relay recording");
    ASSERT_EQ(r.samples.size(), 3u);
    EXPECT_DOUBLE_EQ(r.samples[1].time_s, 10.004);  // reordered
    EXPECT_FALSE(r.samples[1].raw.right.valid);     // confidence 0.3
    EXPECT_DOUBLE_EQ(r.samples[1].raw.right.pupil_mm, 4.5);
    EXPECT_FALSE(r.samples[2].raw.right.valid);  // eye0's columns are nan: eye1 only
    EXPECT_TRUE(r.samples[2].raw.left.valid);
    EXPECT_DOUBLE_EQ(r.samples[0].raw.left.y, 0.7);
}

TEST(ImportPupilCsv, PlayerBlinksAndFixationsBecomeEvents) {
    Read r = read_text(
        "id,start_timestamp,duration,end_timestamp,start_frame_index,index,end_frame_index,"
        "confidence,filter_response,base_data\n5,3.5,0.375,3.875,1,2,3,0.4,0.5 0.6,3.5 3.6\n");
    ASSERT_EQ(r.events.size(), 1u);
    EXPECT_EQ(r.events[0].type, gaze::Event::kBlink);
    EXPECT_DOUBLE_EQ(r.events[0].end_s, 3.875);
    r = read_text(
        "id,start_timestamp,duration,start_frame_index,end_frame_index,norm_pos_x,norm_pos_y,"
        "dispersion,confidence,method,base_data\n65,7.0,200.0,1,2,0.5,0.25,1.3,0.99,3d gaze,7.0\n");
    ASSERT_EQ(r.events.size(), 1u);
    EXPECT_EQ(r.events[0].type, gaze::Event::kFixation);
    EXPECT_DOUBLE_EQ(r.events[0].end_s, 7.2);  // duration in ms
    EXPECT_DOUBLE_EQ(r.events[0].y, 0.75);
}

// ---- Tobii ----------------------------------------------------------------------------------

TEST(ImportTobii, ProSdkFieldsValidityAndACutLastLine) {
    const Read r = read_text(
        "right_pupil_validity;right_gaze_point_on_display_area;system_time_stamp;"
        "left_pupil_validity;right_pupil_diameter;left_pupil_diameter;left_gaze_point_validity;"
        "right_gaze_point_validity;left_gaze_point_on_display_area;device_time_stamp\n"
        "1;(0.13, 0.63);1.56e+15;1;2.97;3.38;1;1;(0.11, 0.64);491999899\n"
        "0;(nan, nan);1.56e+15;1;nan;3.38;1;0;(0.11, 0.64);492011002\n"
        "1;(0.13, 0.63);1.56e+15;1;2.97;3.38;1;1;(0.11");
    EXPECT_EQ(r.info.format, Format::kTobiiCsv);
    ASSERT_EQ(r.samples.size(), 2u);
    EXPECT_EQ(r.samples[0].raw.device_ticks, 491999899u);
    EXPECT_DOUBLE_EQ(r.samples[0].raw.right.x, 0.13);
    EXPECT_DOUBLE_EQ(r.samples[0].raw.left.pupil_mm, 3.38);
    EXPECT_FALSE(r.samples[1].raw.right.valid);
    EXPECT_TRUE(r.samples[1].raw.left.valid);
    EXPECT_TRUE(r.stats.truncated);
    EXPECT_TRUE(has_issue(r.stats, "t:4: last line has no line end"));
}

// Written from Tobii Studio's documented column names: no real gaze export is in ../shared.
TEST(ImportTobii, StudioGazeExportColumnsPreambleResolutionAndEventType) {
    const Read r = read_text(
        "System Properties:\nOperating System:\t Windows\n\nData properties:\n"
        "Recording resolution:\t 1280 x 1024\n\n"
        "RecordingTimestamp\tGazePointLeftX (ADCSpx)\tGazePointLeftY (ADCSpx)\tValidityLeft\t"
        "PupilLeft\tGazePointRightX (ADCSpx)\tGazePointRightY (ADCSpx)\tValidityRight\t"
        "PupilRight\tGazeEventType\n"
        "100\t640\t512\t0\t3.1\t650\t520\t4\t\tFixation\n"
        "117\t640\t512\t1\t3.1\t650\t520\t0\t3.2\tSaccade\n");
    EXPECT_EQ(r.info.format, Format::kTobiiTsv);
    EXPECT_EQ(r.info.variant, "gaze data export");
    EXPECT_EQ(r.info.screen.width_px, 1280);
    ASSERT_EQ(r.samples.size(), 2u);
    EXPECT_DOUBLE_EQ(r.samples[0].raw.left.x, 0.5);
    EXPECT_FALSE(r.samples[0].raw.right.valid);  // validity 4: eye not found
    EXPECT_DOUBLE_EQ(r.samples[0].time_s, 0.1);
    EXPECT_EQ(r.samples[0].labels[0], gaze::Event::kFixation);
    EXPECT_EQ(r.samples[1].labels[0], gaze::Event::kSaccade);
    EXPECT_DOUBLE_EQ(r.samples[1].raw.right.pupil_mm, 3.2);
}

TEST(ImportTobii, AShortGazeRowIsKeptWithItsEyesInvalidForWantOfValidity) {
    // Found by fuzz_tobii_tsv: the row's validity and pupil columns were read past its end.
    const Read r = read_text(
        "RecordingTimestamp\tGazePointLeftX (ADCSpx)\tGazePointLeftY (ADCSpx)\t"
        "GazePointRightX (ADCSpx)\tGazePointRightY (ADCSpx)\tValidityLeft\tPupilLeft\t"
        "ValidityRight\tPupilRight\tRecording resolution width\tRecording resolution height\n"
        "100\t640\t512\t650\t520\t0\t3.1\t0\t3.2\t1280\t1024\n"
        "117\t640\t512\t650\t520\n");
    ASSERT_EQ(r.samples.size(), 2u);
    EXPECT_DOUBLE_EQ(r.samples[0].raw.right.pupil_mm, 3.2);
    EXPECT_FALSE(r.samples[1].raw.left.valid);  // no validity code: not trusted
    EXPECT_EQ(r.samples[1].raw.left.pupil_mm, 0.0);
}

// ---- every real file ------------------------------------------------------------------------

using test::kData;

TEST(ImportRealFiles, EveryLund2013FileRowForRow) {
    const fs::path dir = kData / "lund2013";
    if (!fs::exists(dir)) GTEST_SKIP() << "no " << dir;
    int files = 0;
    uint64_t samples = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().extension() != ".csv") continue;
        std::ifstream in(e.path());
        std::string line;
        uint64_t rows = 0;
        for (int i = 0; std::getline(in, line); ++i)
            if (i >= 2 && !line.empty()) ++rows;
        auto r = open(e.path().string());
        ASSERT_TRUE(r.ok()) << r.error().message;
        const Read got = read_all(**r);
        EXPECT_EQ(got.samples.size(), rows) << e.path();
        EXPECT_EQ(got.stats.skipped, 0u) << e.path();
        const double rate = got.info.rate_hz();
        EXPECT_TRUE(std::fabs(rate - 500) < 1 || std::fabs(rate - 200) < 1) << e.path() << rate;
        ++files;
        samples += got.samples.size();
    }
    EXPECT_EQ(files, 69);  // 34 recordings x 2 coders + one correction
    std::printf("lund2013: %d files, %llu samples\n", files,
                static_cast<unsigned long long>(samples));
}

TEST(ImportRealFiles, GazeComArffAndSpToolArff) {
    for (const fs::path& p : {kData / "labelled/gazecom/GGM_holsten_gate.input.arff",
                              kData / "recordings/eyelink/sp_tool/arff_data_example.arff"}) {
        if (!fs::exists(p)) GTEST_SKIP() << "no " << p;
        const test::Count c = test::arff_count(p);
        auto r = open(p.string());
        ASSERT_TRUE(r.ok()) << r.error().message;
        const Read got = read_all(**r);
        ASSERT_EQ(got.samples.size(), c.rows) << p;
        EXPECT_DOUBLE_EQ(got.samples.front().time_s, c.first * 1e-6);
        EXPECT_DOUBLE_EQ(got.samples.back().time_s, c.last * 1e-6);
        EXPECT_EQ(got.info.screen.width_px, 1280);
        EXPECT_DOUBLE_EQ(got.info.screen.distance_m, 0.45);
        EXPECT_EQ(got.stats.skipped, 0u);
        std::printf("%s: %zu samples, %.0f Hz, %zu label columns\n", p.filename().c_str(),
                    got.samples.size(), got.info.rate_hz(), got.info.label_columns.size());
    }
}

TEST(ImportRealFiles, EveryFileUnderRecordingsIsARecordingOrSaysWhyNot) {
    const fs::path rec = kData / "recordings";
    if (!fs::exists(rec)) GTEST_SKIP() << "no " << rec;
    const test::Recordings all = test::recordings();
    for (const auto& e : fs::recursive_directory_iterator(rec)) {
        if (!e.is_regular_file()) continue;
        bool covered = all.not_recordings.count(e.path()) != 0;
        for (const auto& u : all.units) covered |= u.path == e.path();
        EXPECT_TRUE(covered) << e.path() << ": a new file? add it to tests/import/recordings.hpp";
    }
}

TEST(ImportRealFiles, CountsAndFirstLastStampsOfEveryRecording) {
    if (!fs::exists(kData / "recordings")) GTEST_SKIP() << "no " << kData / "recordings";
    for (const auto& u : test::recordings().units) {
        auto r = open(u.path.string());
        ASSERT_TRUE(r.ok()) << r.error().message;
        const Read got = read_all(**r);
        for (const auto& want : u.expect) {
            std::vector<double> t;
            if (want.kind == Item::kSample)
                for (const auto& s : got.samples) t.push_back(s.time_s);
            if (want.kind == Item::kMarker)
                for (const auto& m : got.markers) t.push_back(m.time_s);
            if (want.kind == Item::kEvent)
                for (const auto& e : got.events) t.push_back(e.start_s);
            ASSERT_EQ(t.size(), want.count.rows) << u.path << " item kind " << int(want.kind);
            if (t.empty() || !std::isfinite(want.count.first)) continue;
            EXPECT_NEAR(*std::min_element(t.begin(), t.end()), want.count.first * want.scale, 1e-9)
                << u.path;
            EXPECT_NEAR(*std::max_element(t.begin(), t.end()), want.count.last * want.scale, 1e-9)
                << u.path;
        }
        EXPECT_EQ(got.stats.skipped, got.stats.truncated ? 1u : 0u) << u.path;  // only a cut line
        if (got.info.format == Format::kEyelinkAsc) {
            EXPECT_GT(got.info.screen.width_px, 0) << u.path;
            uint64_t with_amplitude = 0;
            for (const auto& e : got.events)
                with_amplitude += e.type == gaze::Event::kSaccade && e.amplitude_deg > 0;
            EXPECT_GT(with_amplitude, 0u) << u.path;
        }
        std::printf("%s: %s (%s), %zu samples (%llu invalid), %zu markers, %zu events, %.1f Hz\n",
                    u.path.filename().c_str(), format_name(got.info.format),
                    got.info.variant.c_str(), got.samples.size(),
                    static_cast<unsigned long long>(got.stats.invalid_samples), got.markers.size(),
                    got.events.size(), got.info.rate_hz());
        for (const auto& i : got.stats.issues) std::printf("  %s\n", i.c_str());
    }
}

}  // namespace
}  // namespace fovea::import
