#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#if !defined(__clang__)  // GCC spelling; clang has no -Wshadow=local
#pragma GCC diagnostic ignored "-Wshadow=local"
#endif
#endif
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>

#include "fovea/metrics/image.hpp"

namespace fovea::metrics {

Result<Rgb8Image> decode_png(const uint8_t* data, size_t size, const std::string& what) {
    if (size > size_t(std::numeric_limits<int>::max()))
        return make_error(what + ": too large for a PNG");
    int w = 0, h = 0, channels = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
        stbi_load_from_memory(data, int(size), &w, &h, &channels, 3), stbi_image_free);
    if (!pixels) return make_error(what + ": not a readable PNG (" + stbi_failure_reason() + ")");
    Rgb8Image img;
    img.width = uint32_t(w);
    img.height = uint32_t(h);
    img.rgb.assign(pixels.get(), pixels.get() + size_t(w) * size_t(h) * 3);
    return img;
}

Result<Rgb8Image> load_png(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return make_error(path + ": cannot open");
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    if (in.bad()) return make_error(path + ": read error");
    return decode_png(bytes.data(), bytes.size(), path);
}

bool write_png(const std::string& path, const Rgb8View& image) {
    return stbi_write_png(path.c_str(), int(image.width), int(image.height), 3, image.rgb.data(),
                          int(image.width * 3)) != 0;
}

Rgb8Image map_to_grey(std::span<const float> map, uint32_t width, uint32_t height) {
    Rgb8Image img{width, height, std::vector<uint8_t>(size_t(width) * height * 3)};
    for (size_t i = 0; i < size_t(width) * height && i < map.size(); ++i) {
        const float v = map[i];
        uint8_t* p = &img.rgb[3 * i];
        if (!std::isfinite(v)) {
            p[0] = 255;
            p[1] = p[2] = 0;
        } else {
            p[0] = p[1] = p[2] = uint8_t(std::clamp(v, 0.f, 1.f) * 255.f + 0.5f);
        }
    }
    return img;
}

}  // namespace fovea::metrics
