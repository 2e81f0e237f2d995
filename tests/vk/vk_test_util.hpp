// Shared fixtures for the GPU tests: one headless device per test binary (pipeline creation on
// lavapipe is slow, so tests share it), validation as FOVEA_VK_VALIDATION says
// (../support/vk_test_device.hpp), skipping cleanly without Vulkan.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "../support/vk_test_device.hpp"
#include "fovea/vk/device.hpp"
#include "fovea/vk/foveator.hpp"

namespace fovea::vk::test {

inline TestDevice& shared_test_device() {
    static TestDevice device = make_test_device(/*prefer_software=*/false);
    return device;
}

#define FOVEA_REQUIRE_DEVICE()                                                          \
    FOVEA_ASSERT_TEST_DEVICE(::fovea::vk::test::shared_test_device());                  \
    ::fovea::vk::Device* device = ::fovea::vk::test::shared_test_device().device.get(); \
    const uint64_t validation_errors_before = device->validation_errors()

#define FOVEA_EXPECT_NO_VALIDATION_ERRORS() \
    FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(*device, validation_errors_before)

inline float half_to_float(uint16_t h) {
    const uint32_t s = (h >> 15) & 1, e = (h >> 10) & 31, m = h & 1023;
    float v;
    if (e == 0)
        v = std::ldexp(static_cast<float>(m), -24);
    else if (e == 31)
        v = m ? NAN : INFINITY;
    else
        v = std::ldexp(static_cast<float>(m | 1024), static_cast<int>(e) - 25);
    return s ? -v : v;
}

inline uint16_t float_to_half(float f) {
    uint32_t x;
    std::memcpy(&x, &f, 4);
    const uint32_t s = (x >> 16) & 0x8000;
    int e = static_cast<int>((x >> 23) & 0xff) - 127 + 15;
    uint32_t m = x & 0x7fffff;
    if (e <= 0) return static_cast<uint16_t>(s);
    if (e >= 31) return static_cast<uint16_t>(s | 0x7c00);
    return static_cast<uint16_t>(s | (static_cast<uint32_t>(e) << 10) | ((m + 0x1000) >> 13));
}

}  // namespace fovea::vk::test
