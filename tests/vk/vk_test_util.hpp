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
#include "fovea/half.hpp"
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

}  // namespace fovea::vk::test
