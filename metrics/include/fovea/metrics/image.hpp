// Owned 8-bit RGB images for the metrics and their PNG input (stb_image, Debian's libstb-dev).
// Thread-safe: no shared state.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "fovea/metrics/flip.hpp"
#include "fovea/result.hpp"

namespace fovea::metrics {

struct Rgb8Image {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgb;  // 3 interleaved sRGB-encoded channels, row-major, top-left origin
    Rgb8View view() const { return {width, height, rgb}; }
};

// Any PNG stb_image decodes (grey, grey+alpha, RGB, RGBA; 8 or 16 bits), as 8-bit RGB: grey is
// replicated, alpha dropped (not composited), 16-bit rounded to 8. Errors name the file and why.
Result<Rgb8Image> load_png(const std::string& path);
// The same from bytes in memory (`what` names them in errors).
Result<Rgb8Image> decode_png(const uint8_t* data, size_t size, const std::string& what);
// 8-bit RGB PNG; false when the file cannot be written.
bool write_png(const std::string& path, const Rgb8View& image);
// A FLIP (or any [0, 1]) map as a grey PNG, 0 black, 1 white; non-finite values red.
Rgb8Image map_to_grey(std::span<const float> map, uint32_t width, uint32_t height);

}  // namespace fovea::metrics
