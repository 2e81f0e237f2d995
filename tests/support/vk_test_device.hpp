// The one way GPU tests get a Vulkan device: validation on exactly when the build says
// (-DFOVEA_VK_VALIDATION, compiled in as FOVEA_TEST_VALIDATION by fovea_add_gtest). No Vulkan
// device is a skip; validation asked for but not installed is a failure, never a silent pass.
// With validation off, FOVEA_EXPECT_NO_VALIDATION_ERRORS skips the test after its other checks,
// so ctest lists it as skipped ("validation not checked") instead of passed.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "fovea/vk/device.hpp"

#ifndef FOVEA_TEST_VALIDATION
#error "FOVEA_TEST_VALIDATION must be defined (fovea_add_gtest does, from FOVEA_VK_VALIDATION)"
#endif

namespace fovea::vk::test {

inline constexpr bool kValidation = FOVEA_TEST_VALIDATION;
inline constexpr const char* kValidationOff =
    "FOVEA_VK_VALIDATION=OFF: Vulkan validation errors NOT checked";

struct TestDevice {
    std::unique_ptr<Device> device;  // null when skip or fail says why
    std::string skip;                // no Vulkan device at all
    std::string fail;                // validation requested and unavailable
};

// A device from `o` as given (a test with its own log or options; set o.validation from
// kValidation), sorted into device / skip / fail.
inline TestDevice make_test_device(const DeviceOptions& o) {
    TestDevice t;
    auto d = Device::create_headless(o);
    if (d) {
        t.device = std::make_unique<Device>(std::move(*d));
    } else if (d.error().code == static_cast<int>(VK_ERROR_LAYER_NOT_PRESENT) ||
               d.error().code == static_cast<int>(VK_ERROR_EXTENSION_NOT_PRESENT)) {
        t.fail = d.error().message;
    } else {
        t.skip = "no Vulkan device (install mesa-vulkan-drivers): " + d.error().message;
    }
    return t;
}

// Validation as the build says; warnings and errors go to stderr (validation messages included).
inline TestDevice make_test_device(bool prefer_software = true) {
    DeviceOptions o;
    o.validation = kValidation;
    o.prefer_software = prefer_software;
    o.log = [](LogLevel level, const std::string& msg) {
        if (level >= LogLevel::kWarning) std::fprintf(stderr, "[vk] %s\n", msg.c_str());
    };
    return make_test_device(o);
}

}  // namespace fovea::vk::test

// In a test body or SetUp: fails or skips unless `t` (a TestDevice) has a device.
#define FOVEA_ASSERT_TEST_DEVICE(t)                                          \
    do {                                                                     \
        if (!(t).fail.empty()) GTEST_FAIL() << (t).fail;                     \
        if (!(t).device) GTEST_SKIP() << (t).skip;                           \
        if (!::fovea::vk::test::kValidation)                                 \
            std::fprintf(stderr, "%s\n", ::fovea::vk::test::kValidationOff); \
    } while (0)

// At the end of a test: no validation error since `before`; with validation off, a loud skip.
#define FOVEA_EXPECT_NO_VALIDATION_ERRORS_SINCE(device, before)                                \
    do {                                                                                       \
        if (!(device).validation_enabled()) GTEST_SKIP() << ::fovea::vk::test::kValidationOff; \
        EXPECT_EQ((device).validation_errors(), (before)) << "Vulkan validation errors";       \
    } while (0)
