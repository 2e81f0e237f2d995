// `fovea flip` through the real binary: NVIDIA's vector pair gives NVIDIA's numbers (the tool's
// default ppd), and bad input gets one clear line and exit status 1.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

namespace {

struct CliRun {
    int status;
    std::string out, err;
};

CliRun run(const std::string& args) {
    const auto err_path = std::filesystem::temp_directory_path() /
                          ("fovea_flip_cli_" + std::to_string(::getpid()) + ".err");
    const std::string cmd =
        std::string(FOVEA_BINARY_DIR) + "/tools/fovea flip " + args + " 2>" + err_path.string();
    FILE* p = popen(cmd.c_str(), "r");
    CliRun r{-1, {}, {}};
    if (!p) return r;
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof(buf), p)) r.out.append(buf, n);
    r.status = WEXITSTATUS(pclose(p));
    std::ifstream e(err_path);
    r.err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
    std::filesystem::remove(err_path);
    return r;
}

const std::string kDir = std::string(FOVEA_SHARED_DATA_DIR) + "/flip/";

TEST(FlipCli, JsonHasTheToolsPooledValuesAtItsDefaultPpd) {
    if (!std::filesystem::exists(kDir + "vectors.json")) GTEST_SKIP() << "no FLIP vectors";
    const CliRun r = run(kDir + "ref.png " + kDir + "test_block2x2.png --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    // vectors.json, pair block2x2 at the tool's default ppd (67.0206).
    EXPECT_NEAR(j["mean"].get<double>(), 0.065036, 1e-4);
    EXPECT_NEAR(j["weighted_median"].get<double>(), 0.090759, 1e-4);
    EXPECT_GT(j["max"].get<double>(), j["weighted_median"].get<double>());
    EXPECT_NEAR(j["ppd"].get<double>(), 67.0206, 1e-4);
    EXPECT_EQ(j["resolution"], nlohmann::json({960, 540}));
}

TEST(FlipCli, PpdOptionChangesTheObserver) {
    if (!std::filesystem::exists(kDir + "vectors.json")) GTEST_SKIP() << "no FLIP vectors";
    const CliRun r = run(kDir + "ref.png " + kDir + "test_block2x2.png --ppd 30 --json");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NEAR(nlohmann::json::parse(r.out)["mean"].get<double>(), 0.141305, 1e-4);
}

TEST(FlipCli, BadInputGetsOneClearLine) {
    const CliRun missing = run("/nonexistent/a.png /nonexistent/b.png");
    EXPECT_EQ(missing.status, 1);
    EXPECT_NE(missing.err.find("/nonexistent/a.png: cannot open"), std::string::npos)
        << missing.err;
    EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;

    const auto garbage = std::filesystem::temp_directory_path() /
                         ("fovea_flip_garbage_" + std::to_string(::getpid()) + ".png");
    std::ofstream(garbage) << "not a png";
    const CliRun bad = run(garbage.string() + " " + garbage.string());
    EXPECT_EQ(bad.status, 1);
    EXPECT_NE(bad.err.find("not a readable PNG"), std::string::npos) << bad.err;
    std::filesystem::remove(garbage);

    if (std::filesystem::exists(kDir + "ref.png")) {
        // A 1x1 PNG against the 960x540 reference.
        const auto tiny = std::filesystem::temp_directory_path() /
                          ("fovea_flip_tiny_" + std::to_string(::getpid()) + ".png");
        const unsigned char png[] = {
            0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
            0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00,
            0x00, 0x90, 0x77, 0x53, 0xde, 0x00, 0x00, 0x00, 0x0c, 0x49, 0x44, 0x41, 0x54, 0x78,
            0x9c, 0x63, 0xf8, 0xcf, 0xc0, 0x00, 0x00, 0x03, 0x01, 0x01, 0x00, 0xc9, 0xfe, 0x92,
            0xef, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
        std::ofstream(tiny, std::ios::binary)
            .write(reinterpret_cast<const char*>(png), sizeof(png));
        const CliRun sizes = run(kDir + "ref.png " + tiny.string());
        EXPECT_EQ(sizes.status, 1);
        EXPECT_NE(sizes.err.find("image sizes differ"), std::string::npos) << sizes.err;
        std::filesystem::remove(tiny);
    }
    const CliRun ppd = run(kDir + "ref.png " + kDir + "ref.png --ppd -3");
    EXPECT_NE(ppd.status, 0);
}

}  // namespace
