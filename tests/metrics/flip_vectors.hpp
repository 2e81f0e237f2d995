// NVIDIA's LDR-FLIP test vectors (../shared/data/flip/, README there): 7 image pairs at 3 ppd
// values with mean, pooled values, 5 pixels and a 31 x 18 grid of map samples per case, computed
// by the authors' Python v1.3 code. Loaded once per test binary.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fovea/metrics/image.hpp"

namespace fovea::metrics::testing {

struct FlipCase {
    std::string pair, test_file, ppd_label;
    double ppd = 0, mean = 0, weighted_median = 0, weighted_q1 = 0, weighted_q3 = 0, max = 0;
    struct Pixel {
        uint32_t x, y;
        double flip;
    };
    std::vector<Pixel> pixels;  // the 5 listed pixels and the grid samples
    size_t listed_pixels = 0;   // the first this many are the 5 listed ones
};

struct FlipVectors {
    std::string dir;
    std::vector<FlipCase> cases;
    std::map<std::string, Rgb8Image> images;  // by file name
    const Rgb8Image& image(const std::string& file) const { return images.at(file); }
};

inline std::string flip_vector_dir() { return std::string(FOVEA_SHARED_DATA_DIR) + "/flip"; }

// README (e): out[:, x] = ref[:, x - 1] for x >= 1, column 0 kept.
inline Rgb8Image shift_right_1px(const Rgb8Image& ref) {
    Rgb8Image out = ref;
    for (uint32_t y = 0; y < ref.height; ++y)
        for (uint32_t x = 1; x < ref.width; ++x)
            for (int k = 0; k < 3; ++k)
                out.rgb[(size_t(y) * ref.width + x) * 3 + k] =
                    ref.rgb[(size_t(y) * ref.width + x - 1) * 3 + k];
    return out;
}

// Empty `cases` when the data is absent (tests skip).
inline const FlipVectors& flip_vectors() {
    static const FlipVectors v = [] {
        FlipVectors out;
        out.dir = flip_vector_dir();
        std::ifstream vf(out.dir + "/vectors.json"), gf(out.dir + "/grid_samples.json");
        if (!vf || !gf) return out;
        const nlohmann::json j = nlohmann::json::parse(vf), g = nlohmann::json::parse(gf);
        const std::vector<uint32_t> gx = g["grid_x"], gy = g["grid_y"];
        for (const auto& p : j["pairs"]) {
            FlipCase c;
            c.pair = p["pair"];
            c.test_file = p["test"];
            c.ppd_label = p["ppd_label"];
            c.ppd = p["ppd"];
            c.mean = p["mean"];
            c.weighted_median = p["weighted_median"];
            c.weighted_q1 = p["weighted_quartile1"];
            c.weighted_q3 = p["weighted_quartile3"];
            c.max = p["max"];
            for (const auto& px : p["pixels"]) c.pixels.push_back({px["x"], px["y"], px["flip"]});
            c.listed_pixels = c.pixels.size();
            for (const auto& m : g["maps"])
                if (m["pair"] == c.pair && m["ppd_label"] == c.ppd_label)
                    for (size_t r = 0; r < gy.size(); ++r)
                        for (size_t k = 0; k < gx.size(); ++k)
                            c.pixels.push_back({gx[k], gy[r], m["values"][r][k]});
            out.cases.push_back(std::move(c));
        }
        for (const std::string f : {"ref.png"})
            if (auto img = load_png(out.dir + "/" + f)) out.images[f] = std::move(*img);
        for (const auto& c : out.cases)
            if (!out.images.count(c.test_file))
                if (auto img = load_png(out.dir + "/" + c.test_file))
                    out.images[c.test_file] = std::move(*img);
        // The shared folder lacks test_shift1px.png; its README defines it exactly from ref.png.
        if (!out.images.count("test_shift1px.png") && out.images.count("ref.png"))
            out.images["test_shift1px.png"] = shift_right_1px(out.images.at("ref.png"));
        return out;
    }();
    return v;
}

// The tolerances: means within 1e-4, the listed pixels (and the grid) within 1e-3.
inline constexpr double kMeanTolerance = 1e-4;
inline constexpr double kPixelTolerance = 1e-3;

}  // namespace fovea::metrics::testing
