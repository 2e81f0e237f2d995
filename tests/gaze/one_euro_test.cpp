#include "fovea/gaze/one_euro.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

namespace fovea::gaze {
namespace {

TEST(OneEuroFilter, MatchesAuthorsReferenceVector) {
    const std::string path = std::string(FOVEA_SHARED_DATA_DIR) + "/oneeuro/groundTruth.csv";
    std::ifstream in(path);
    if (!in) GTEST_SKIP() << "reference vector not found: " << path;
    std::string line;
    std::getline(in, line);  // header
    OneEuroFilter f({1.0, 0.1, 1.0, 120.0, 1e9});
    double max_err = 0.0;
    int n = 0;
    while (std::getline(in, line)) {
        std::stringstream ss(line);
        std::string c[4];
        for (auto& s : c) std::getline(ss, s, ',');
        const double t = std::stod(c[0]), noisy = std::stod(c[2]), expected = std::stod(c[3]);
        max_err = std::max(max_err, std::fabs(f.filter(noisy, t) - expected));
        ++n;
    }
    EXPECT_EQ(n, 1200);
    EXPECT_LT(max_err, 1e-4);
    RecordProperty("max_error", std::to_string(max_err));
    std::printf("1euro max |error| vs groundTruth.csv: %.3g over %d samples\n", max_err, n);
}

TEST(OneEuroFilter, NanPassesThroughWithoutPoisoningState) {
    OneEuroFilter f({1.0, 0.1, 1.0, 120.0, 0.5});
    f.filter(1.0, 0.0);
    f.filter(1.0, 0.01);
    EXPECT_TRUE(std::isnan(f.filter(std::nan(""), 0.02)));
    EXPECT_TRUE(std::isnan(f.filter(1.0, std::nan(""))));
    EXPECT_NEAR(f.filter(1.0, 0.03), 1.0, 1e-12);
}

TEST(OneEuroFilter, ZeroAndBackwardDtKeepLastRate) {
    OneEuroFilter f;
    f.filter(0.0, 1.0);
    const double a = f.filter(1.0, 1.0);  // dt = 0
    const double b = f.filter(1.0, 0.5);  // backwards
    EXPECT_TRUE(std::isfinite(a));
    EXPECT_TRUE(std::isfinite(b));
    EXPECT_GE(b, a);
}

TEST(OneEuroFilter, LongGapRestartsAtNewValue) {
    OneEuroFilter f({1.0, 0.0, 1.0, 120.0, 0.5});
    for (int i = 0; i < 100; ++i) f.filter(0.0, i * 0.01);
    EXPECT_DOUBLE_EQ(f.filter(5.0, 10.0), 5.0);
}

}  // namespace
}  // namespace fovea::gaze
