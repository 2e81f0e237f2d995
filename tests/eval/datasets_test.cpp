// The dataset loaders on small generated folders in each dataset's own layout, and bad input:
// one clear error or note, never a crash.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "fovea/eval/dataset.hpp"

namespace fovea::eval {
namespace {

namespace fs = std::filesystem;
using gaze::Event;

class TempDir {
public:
    TempDir()
        : path_(fs::temp_directory_path() /
                ("fovea_eval_ds_" + std::to_string(::getpid()) + "_" + std::to_string(next_++))) {
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() { fs::remove_all(path_); }
    const fs::path& path() const { return path_; }
    void write(const fs::path& rel, const std::string& text) const {
        fs::create_directories((path_ / rel).parent_path());
        std::FILE* f = std::fopen((path_ / rel).c_str(), "w");
        ASSERT_NE(f, nullptr);
        std::fputs(text.c_str(), f);
        std::fclose(f);
    }

private:
    static inline int next_ = 0;
    fs::path path_;
};

void write_hooge(const TempDir& t, const fs::path& root) {
    std::string et = "time\tx\ty\tv\n";
    for (int i = 0; i < 30; ++i) {
        char row[96];
        if (i == 12) {
            std::snprintf(row, sizeof row, "%.3f\tNaN\tNaN\tNaN\n", i * 10.0 / 3.0);
        } else {
            std::snprintf(row, sizeof row, "%.3f\t%.1f\t540.0\t100\n", i * 10.0 / 3.0, 960.0 + i);
        }
        et += row;
    }
    t.write(root / "data/ETdata/adult_1.txt", et);
    t.write(root / "data/ETdata/infant_2.txt", et);
    // Coder AA: fixations [0, 20] ms and [40, 63.33] ms in adult_1; BB did not code adult_1.
    t.write(root / "data/coderSettings/AA.txt",
            "Trial\tdatum\tFixStart\tFixEnd\tFixDur\n"
            "adult_1\t07-Nov-2016 15:17:26\t0.00\t20.00\t20\n"
            "adult_1\t07-Nov-2016 15:17:26\t40.00\t63.33\t23\n"
            "adult_1\t07-Nov-2016 15:17:26\tbad\t1\t1\n"
            "infant_2\t07-Nov-2016 15:17:26\t0.00\t96.67\t97\n"
            "other_trial\t07-Nov-2016 15:17:26\t0.00\t10.00\t10\n");
    t.write(root / "data/coderSettings/BB.txt",
            "Trial\tdatum\tFixStart\tFixEnd\tFixDur\n"
            "infant_2\t07-Nov-2016 15:17:26\t10.00\t96.67\t87\n");
}

TEST(Hooge2018, CodersFixationIntervalsBecomePerSampleLabels) {
    TempDir t;
    write_hooge(t, "hooge");
    auto d = load_hooge2018((t.path() / "hooge").string());
    ASSERT_TRUE(d.ok()) << d.error().message;
    ASSERT_EQ(d->recordings.size(), 2u);
    const Recording& a = d->recordings[0];
    EXPECT_EQ(a.name, "adult_1");
    EXPECT_EQ(a.stimulus, "adult");
    EXPECT_NEAR(a.rate_hz, 300.0, 0.5);
    ASSERT_EQ(a.coders.size(), 1u);  // BB did not code adult_1
    const auto& aa = a.coders.at("AA");
    // Samples every 3.333 ms: 0..6 (0-20 ms) and 12..19 (40-63.33 ms) are fixation.
    for (int i = 0; i < 30; ++i) {
        const bool fix = i <= 6 || (i >= 12 && i <= 19);
        EXPECT_EQ(aa[i] == Event::kFixation, fix) << i;
    }
    EXPECT_FALSE(a.samples[12].left.valid);  // NaN row: lost, kept in time
    EXPECT_TRUE(a.samples[13].left.valid);
    const Degrees g = degrees(a, 0);
    EXPECT_NEAR(g.x, 0.0, 1e-9);  // x = 960 px is the centre of the 1920-px screen
    EXPECT_EQ(d->recordings[1].coders.size(), 2u);
    EXPECT_EQ(d->scheme, std::vector<Event>{Event::kFixation});
    bool noted = false;
    for (const auto& n : d->notes) noted = noted || n.find("AA.txt: 1 unparsable") != n.npos;
    EXPECT_TRUE(noted);
}

TEST(Uneye, MatricesInDegreesRoundTripThroughTheVirtualDisplay) {
    TempDir t;
    std::string x, y, l;
    for (int row = 0; row < 2; ++row) {
        for (int i = 0; i < 40; ++i) {
            const char* sep = i ? "," : "";
            x += sep + std::to_string(3.5 + 0.01 * i);
            y += sep + std::to_string(-2.0 - 0.02 * row);
            l += sep + std::string(i >= 20 && i < 28 ? "1" : "0");
        }
        x += "\n";
        y += "\n";
        l += "\n";
    }
    t.write("u/set_500hz_X_A.csv", x);
    t.write("u/set_500hz_Y_A.csv", y);
    t.write("u/set_500hz_Labels_A.csv", l);
    auto d = load_uneye((t.path() / "u").string());
    ASSERT_TRUE(d.ok()) << d.error().message;
    ASSERT_EQ(d->recordings.size(), 2u);
    const Recording& r = d->recordings[1];
    EXPECT_EQ(r.rate_hz, 500.0);
    EXPECT_NEAR(seconds(r, 10), 0.020, 1e-9);
    const Degrees g = degrees(r, 5);
    EXPECT_NEAR(g.x, 3.55, 1e-9);
    EXPECT_NEAR(g.y, -2.02, 1e-9);
    EXPECT_EQ(r.coders.at("expert")[20], Event::kSaccade);
    EXPECT_EQ(r.coders.at("expert")[28], Event::kFixation);
}

TEST(Uneye, AMalformedMatrixIsNamedWithItsLine) {
    TempDir t;
    t.write("u/s_500hz_X_A.csv", "1,2\n3,x\n");
    t.write("u/s_500hz_Y_A.csv", "1,2\n3,4\n");
    t.write("u/s_500hz_Labels_A.csv", "0,0\n0,1\n");
    auto d = load_uneye((t.path() / "u").string());
    EXPECT_FALSE(d.ok());
    auto all = load_datasets(t.path().string());
    EXPECT_FALSE(all.ok());  // the only dataset was unreadable: nothing to score
}

void write_lund(const TempDir& t, const fs::path& dir) {
    for (const char* coder : {"MN", "RA"}) {
        std::string s =
            "# sampFreq=500 viewDist_m=0.67 screenDim_m=0.38,0.3 screenRes_px=1024,768\n"
            "t_us,pupil_h,pupil_v,x_px,y_px,label\n";
        const int n = coder[0] == 'M' ? 20 : 22;  // the coders' files differ in length
        for (int i = 0; i < n; ++i) {
            char row[96];
            const bool lost = i == 5;
            std::snprintf(row, sizeof row, "%s,20,20,%.1f,%.1f,%d\n",
                          i == 3 ? "nan" : std::to_string(i * 2000).c_str(), lost ? 0.0 : 512.0,
                          lost ? 0.0 : 384.0, i < 10 ? 1 : 2);
            s += row;
        }
        s += "garbage\n";
        t.write(dir / (std::string("img__SUB1_x_labelled_") + coder + ".csv"), s);
    }
}

TEST(Lund2013, CoderFilesAlignFromTheStartAndLostSamplesAreZeroZero) {
    TempDir t;
    write_lund(t, "lund");
    auto d = load_lund2013((t.path() / "lund").string());
    ASSERT_TRUE(d.ok()) << d.error().message;
    ASSERT_EQ(d->recordings.size(), 1u);
    const Recording& r = d->recordings[0];
    EXPECT_EQ(r.name, "SUB1_x_labelled");
    EXPECT_EQ(r.subject, "SUB1");
    EXPECT_EQ(r.samples.size(), 20u);
    EXPECT_EQ(r.coders.at("RA").size(), 20u);
    EXPECT_FALSE(r.samples[5].left.valid);
    EXPECT_NEAR(seconds(r, 4), 0.008, 1e-9);  // the NaN stamp at 3 got the nominal period
    EXPECT_NEAR(degrees(r, 0).x, 0.0, 1e-9);
    EXPECT_EQ(d->notes.size(), 2u);  // one unparsable row per file
}

TEST(LoadDatasets, FindsEveryDatasetUnderARootInNameOrder) {
    TempDir t;
    write_lund(t, "lund2013");
    write_hooge(t, "labelled/hooge2018");
    auto all = load_datasets(t.path().string());
    ASSERT_TRUE(all.ok()) << all.error().message;
    ASSERT_EQ(all->datasets.size(), 2u);
    EXPECT_EQ(all->datasets[0].name, "hooge2018");
    EXPECT_EQ(all->datasets[1].name, "lund2013");
    EXPECT_FALSE(load_datasets((t.path() / "nope").string()).ok());
    EXPECT_FALSE(load_lund2013((t.path() / "labelled").string()).ok());
}

TEST(LoadDatasets, FindsASetKeptInSplitFoldersDeepBelowTheRootAsOne) {
    TempDir t;
    write_lund(t, "labelled/otherlab/ground_truth/train");
    write_lund(t, "labelled/otherlab/ground_truth/test/more");
    auto all = load_datasets(t.path().string());
    ASSERT_TRUE(all.ok()) << all.error().message;
    ASSERT_EQ(all->datasets.size(), 1u);
    EXPECT_EQ(all->datasets[0].name, "lund2013");
    EXPECT_EQ(all->datasets[0].recordings.size(), 2u);
}

TEST(Lund2013, BadHeaderIsANoteNamingTheFile) {
    TempDir t;
    t.write("l/img__A_labelled_MN.csv", "t_us,x\n1,2\n");
    auto d = load_lund2013((t.path() / "l").string());
    EXPECT_FALSE(d.ok());
    EXPECT_NE(d.error().message.find("no labelled CSV"), std::string::npos);
}

// 20 samples at 250 Hz: fixation, then pursuit, NOISE at the end (two coder columns).
std::string labelled_arff() {
    std::string a =
        "%@METADATA width_px 1280.0\n%@METADATA height_px 720.0\n%@METADATA width_mm 400.0\n"
        "%@METADATA height_mm 225.0\n%@METADATA distance_mm 450.0\n@RELATION gaze_labels\n"
        "@ATTRIBUTE time INTEGER\n@ATTRIBUTE x NUMERIC\n@ATTRIBUTE y NUMERIC\n"
        "@ATTRIBUTE confidence NUMERIC\n@ATTRIBUTE handlabeller1 INTEGER\n"
        "@ATTRIBUTE handlabeller_final {UNKNOWN,FIX,SACCADE,SP,NOISE}\n@DATA\n";
    for (int i = 0; i < 20; ++i) {
        a += std::to_string(2000 + 4000 * i) + ",640.0,360.0,1.0," + (i < 10 ? "1" : "3") + "," +
             (i < 10   ? "FIX"
              : i < 18 ? "SP"
                       : "NOISE") +
             "\n";
    }
    return a;
}

const char* kUnlabelledArff =
    "@RELATION gaze\n@ATTRIBUTE time INTEGER\n@ATTRIBUTE x NUMERIC\n@ATTRIBUTE y "
    "NUMERIC\n@ATTRIBUTE confidence NUMERIC\n@DATA\n1000,1,2,1.0\n";

TEST(Arff, LabelColumnsAreCodersAndUnlabelledFilesAreIgnored) {
    TempDir t;
    t.write("g/clip_a.arff", labelled_arff());
    t.write("g/unlabelled.arff", kUnlabelledArff);
    auto d = load_arff((t.path() / "g").string());
    ASSERT_TRUE(d.ok()) << d.error().message;
    ASSERT_EQ(d->recordings.size(), 1u);
    const Recording& r = d->recordings[0];
    EXPECT_NEAR(r.rate_hz, 250.0, 0.1);
    EXPECT_EQ(r.display.width_px, 1280);
    EXPECT_NEAR(r.display.distance_m, 0.45, 1e-9);
    EXPECT_NEAR(degrees(r, 0).x, 0.0, 1e-9);
    ASSERT_EQ(r.coders.size(), 2u);
    EXPECT_EQ(r.coders.at("handlabeller1")[12], Event::kPursuit);
    EXPECT_EQ(r.coders.at("handlabeller_final")[12], Event::kPursuit);
    EXPECT_EQ(r.coders.at("handlabeller_final")[19], Event::kUnknown);  // NOISE: no event
}

TEST(LoadDatasets, AFolderThatIsNoDatasetItselfIsStillSearchedBelow) {
    // Gaze without labels beside the labelled set's own folder (a recording's raw export).
    TempDir t;
    t.write("set/raw.arff", kUnlabelledArff);
    t.write("set/ground_truth/clip_a.arff", labelled_arff());
    auto all = load_datasets(t.path().string());
    ASSERT_TRUE(all.ok()) << all.error().message;
    ASSERT_EQ(all->datasets.size(), 1u);
    EXPECT_EQ(all->datasets[0].recordings.size(), 1u);
    ASSERT_EQ(all->notes.size(), 1u);  // and the folder that was not one says so
    EXPECT_NE(all->notes[0].find("no labelled ARFF file"), std::string::npos) << all->notes[0];
}

TEST(Asc, ParserEventsBecomeOneCoderPerEye) {
    TempDir t;
    std::string asc =
        "** CONVERTED FROM x.edf\nMSG\t100 DISPLAY_COORDS = 0 0 1919 1079\n"
        "START\t1000 \tLEFT\tRIGHT\tSAMPLES\tEVENTS\nPUPIL\tAREA\n"
        "SAMPLES\tGAZE\tLEFT\tRIGHT\tRATE\t 500.00\tTRACKING\tCR\tFILTER\t2\n";
    for (int i = 0; i < 30; ++i) {
        asc += std::to_string(1000 + 2 * i) + "\t  960.0\t  540.0\t 3879.0\t  970.0\t  550.0\t" +
               " 3785.0\t.....\n";
    }
    asc +=
        "EFIX L   1000\t1020\t22\t  960.5\t  540.5\t   3879\n"
        "ESACC L  1022\t1030\t10\t  960.0\t  540.0\t  1200.0\t  600.0\t   5.10\t    400\n"
        "EBLINK L 1024\t1026\t4\n"
        "ESACC R  1040\t1046\t8\t  970.0\t  550.0\t  1200.0\t  600.0\t   5.10\t    400\n"
        "END\t1058 \tSAMPLES\tEVENTS\tRES\t  45.90\t  46.06\n";
    t.write("src/rec.asc", asc);
    auto d = load_asc_dir((t.path() / "src").string());
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_FALSE(d->human);
    EXPECT_EQ(d->pso_without_label, Event::kFixation);
    const Recording& r = d->recordings.at(0);
    EXPECT_EQ(r.stimulus, "src");
    EXPECT_TRUE(r.binocular);
    const auto& left = r.coders.at("eyelink-left");
    const auto& right = r.coders.at("eyelink-right");
    EXPECT_EQ(left[0], Event::kFixation);
    EXPECT_EQ(left[10], Event::kFixation);
    // The saccade EyeLink wraps around a blink is the lid's: blink from end to end.
    EXPECT_EQ(left[11], Event::kBlink);
    EXPECT_EQ(left[12], Event::kBlink);
    EXPECT_EQ(left[15], Event::kBlink);
    EXPECT_EQ(left[16], Event::kUnknown);
    EXPECT_EQ(right[20], Event::kSaccade);
    EXPECT_EQ(right[0], Event::kUnknown);
    TempDir none;
    none.write("x/empty.asc",
               "START\t1000 \tLEFT\tSAMPLES\tEVENTS\n"
               "SAMPLES\tGAZE\tLEFT\tRATE\t 500.00\tTRACKING\tCR\tFILTER\t2\n");
    EXPECT_FALSE(load_asc_dir((none.path() / "x").string()).ok());
}

// A folder none of whose files is usable says why the first one was not, even when an earlier
// note (a malformed row of that same file) came first.
TEST(Asc, AFolderWithNoUsableFileSaysWhyTheFirstFailed) {
    TempDir t;
    std::string asc =
        "** CONVERTED FROM x.edf\nMSG\t100 DISPLAY_COORDS = 0 0 1919 1079\n"
        "START\t1000 \tLEFT\tSAMPLES\tEVENTS\n"
        "SAMPLES\tGAZE\tLEFT\tRATE\t 500.00\tTRACKING\tCR\tFILTER\t2\n";
    for (int i = 0; i < 20; ++i)
        asc += std::to_string(1000 + 2 * i) + (i == 3 ? "\t  bad" : "\t  960.0") +
               "\t  540.0\t 3879.0\t.....\n";
    t.write("x/rec.asc", asc + "END\t1040 \tSAMPLES\tEVENTS\tRES\t  45.90\t  46.06\n");
    auto d = load_asc_dir((t.path() / "x").string());
    ASSERT_FALSE(d.ok());
    EXPECT_NE(d.error().message.find("rec.asc: no EFIX/ESACC/EBLINK events"), std::string::npos)
        << d.error().message;
    t.write("g/v.arff",
            "@RELATION gaze_360\n@ATTRIBUTE time INTEGER\n@ATTRIBUTE x NUMERIC\n"
            "@ATTRIBUTE y NUMERIC\n@ATTRIBUTE l {fixation,saccade}\n@DATA\n0,1,2,fixation\n");
    auto a = load_arff((t.path() / "g").string());
    ASSERT_FALSE(a.ok());
    EXPECT_NE(a.error().message.find("@RELATION gaze_360"), std::string::npos) << a.error().message;
}

// --decimate: every factor-th sample and label from the first, labels staying aligned with
// their samples; the rate follows; a factor of 0 or 1 leaves the recording as it is.
TEST(Decimate, KeepsEveryNthSampleWithItsLabelsAndDividesTheRate) {
    Recording r;
    r.rate_hz = 500.0;
    std::vector<gaze::Event> labels;
    for (int i = 0; i < 10; ++i) {
        gaze::RawSample s;
        s.device_ticks = static_cast<uint64_t>(i) * 2000;
        r.samples.push_back(s);
        labels.push_back(i % 2 ? gaze::Event::kSaccade : gaze::Event::kFixation);
    }
    r.coders["a"] = labels;
    r.coders["b"] = std::vector<gaze::Event>(10, gaze::Event::kPursuit);
    Recording same = r;
    decimate(same, 1);
    decimate(same, 0);
    EXPECT_EQ(same.samples.size(), 10u);
    EXPECT_EQ(same.rate_hz, 500.0);
    decimate(r, 3);
    ASSERT_EQ(r.samples.size(), 4u);  // 0, 3, 6, 9
    EXPECT_EQ(r.rate_hz, 500.0 / 3.0);
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(r.samples[i].device_ticks, i * 3 * 2000);
        EXPECT_EQ(r.coders["a"][i], i % 2 ? gaze::Event::kSaccade : gaze::Event::kFixation);
    }
    EXPECT_EQ(r.coders["b"].size(), 4u);
}

// --upsample: factor - 1 samples between each pair, time and position interpolated, labels and
// an invalid eye from the nearer original sample; originals kept; the rate multiplies.
TEST(Upsample, InterpolatesBetweenSamplesAndTakesTheNearerLabels) {
    Recording r;
    r.rate_hz = 250.0;
    for (int i = 0; i < 3; ++i) {
        gaze::RawSample s;
        s.device_ticks = static_cast<uint64_t>(i) * 4000;
        s.left = {0.1 * i, 0.5, 3.0, true};
        s.right = {0.2 * i, 0.5, 3.0, i != 2};  // the right eye lost at the last sample
        r.samples.push_back(s);
    }
    r.coders["a"] = {gaze::Event::kFixation, gaze::Event::kSaccade, gaze::Event::kPso};
    Recording same = r;
    upsample(same, 1);
    upsample(same, 0);
    EXPECT_EQ(same.samples.size(), 3u);
    EXPECT_EQ(same.rate_hz, 250.0);
    upsample(r, 4);
    ASSERT_EQ(r.samples.size(), 9u);
    ASSERT_EQ(r.coders["a"].size(), 9u);
    EXPECT_EQ(r.rate_hz, 1000.0);
    for (size_t i = 0; i < 9; ++i) {
        EXPECT_EQ(r.samples[i].device_ticks, i * 1000) << i;
        EXPECT_NEAR(r.samples[i].left.x, 0.025 * static_cast<double>(i), 1e-12) << i;
        EXPECT_TRUE(r.samples[i].left.valid) << i;
    }
    // Labels: 0-1 from sample 0, 2-5 from sample 1 (2 and 6 are halfway: the later one), ...
    const gaze::Event F = gaze::Event::kFixation, S = gaze::Event::kSaccade, P = gaze::Event::kPso;
    EXPECT_EQ(r.coders["a"], (std::vector<gaze::Event>{F, F, S, S, S, S, P, P, P}));
    // Between a valid and an invalid right eye: the nearer sample's eye, not interpolated.
    EXPECT_TRUE(r.samples[5].right.valid);
    EXPECT_DOUBLE_EQ(r.samples[5].right.x, 0.2);
    EXPECT_FALSE(r.samples[6].right.valid);
    EXPECT_FALSE(r.samples[8].right.valid);
}

// --add-noise-deg: Gaussian offsets of the given SD per axis in degrees, the same to both
// eyes, none to invalid samples; the same seed gives the same noise; SD 0 changes nothing.
TEST(AddWhiteNoise, OffsetsInDegreesHaveTheSdAndBothEyesShareThem) {
    Recording r;
    r.display.width_px = 1920;
    r.display.height_px = 1080;
    for (int i = 0; i < 20000; ++i) {
        gaze::RawSample s;
        s.left = {0.5, 0.5, 0.0, true};
        s.right = {0.5, 0.5, 0.0, i % 10 != 0};
        r.samples.push_back(s);
    }
    Recording same = r, again = r;
    add_white_noise(same, 0.0, 1);
    EXPECT_EQ(same.samples[7].left.x, 0.5);
    add_white_noise(r, 0.1, 7);
    add_white_noise(again, 0.1, 7);
    double sum2 = 0.0;
    size_t n = 0;
    for (size_t i = 0; i < r.samples.size(); ++i) {
        const auto& s = r.samples[i];
        EXPECT_EQ(s.left.x, again.samples[i].left.x);
        double x, y, cx, cy;
        r.display.to_degrees(s.left.x, s.left.y, x, y);
        r.display.to_degrees(0.5, 0.5, cx, cy);
        sum2 += (x - cx) * (x - cx) + (y - cy) * (y - cy);
        n += 2;
        if (s.right.valid) {
            EXPECT_DOUBLE_EQ(s.right.x, s.left.x);
        } else {
            EXPECT_EQ(s.right.x, 0.5);
        }
    }
    EXPECT_NEAR(std::sqrt(sum2 / static_cast<double>(n)), 0.1, 0.005);
}

}  // namespace
}  // namespace fovea::eval
