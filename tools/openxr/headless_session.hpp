// A headless OpenXR client: instance, system, a Vulkan device the runtime picks
// (XR_KHR_vulkan_enable2), a session that submits empty frames, VIEW and LOCAL spaces and, when
// the extension is offered, an eye gaze pose action (XR_EXT_eye_gaze_interaction) bound and
// attached the way the extension's own sample does it. For `fovea openxr-check` and the layer's
// benchmark. One thread; create, run frames and destroy on it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <time.h>

#include <vulkan/vulkan.h>
#define XR_USE_GRAPHICS_API_VULKAN 1
#define XR_USE_TIMESPEC 1
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include "fovea/result.hpp"

namespace fovea::xr {

struct SessionOptions {
    std::string app_name = "fovea openxr-check";
    bool eye_gaze = true;  // enable XR_EXT_eye_gaze_interaction when it is offered
};

// What the loader offered the app (runtime plus enabled implicit/env layers).
struct Offer {
    std::vector<std::string> extensions;
    std::vector<std::string> api_layers;
    bool has(const std::string& extension) const;
};
Result<Offer> query_offer();

struct GazeLocation {
    XrSpaceLocationFlags flags = 0;
    XrPosef pose{{0, 0, 0, 1}, {0, 0, 0}};
    XrTime sample_time = 0;  // XrEyeGazeSampleTimeEXT
    bool valid() const {
        return (flags & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT) &&
               (flags & XR_SPACE_LOCATION_POSITION_VALID_BIT);
    }
};

class HeadlessSession {
public:
    static Result<std::unique_ptr<HeadlessSession>> create(const SessionOptions& options);
    ~HeadlessSession();
    HeadlessSession(const HeadlessSession&) = delete;
    HeadlessSession& operator=(const HeadlessSession&) = delete;

    const std::string& runtime_name() const { return runtime_name_; }
    bool eye_gaze() const { return gaze_space_ != XR_NULL_HANDLE; }
    bool supports_eye_gaze_interaction() const { return supports_gaze_; }

    // Pump events until the session is FOCUSED (begins it when READY). False on timeout or when
    // the session ends.
    Result<void> wait_until_focused(int timeout_ms);

    struct Frame {
        XrTime display_time = 0;
        XrDuration period = 0;
    };
    // xrWaitFrame, xrBeginFrame, xrSyncActions; then the caller locates; then end_frame().
    Result<Frame> begin_frame();
    Result<void> end_frame(const Frame& f);
    bool gaze_action_active();  // xrGetActionStatePose's isActive after the last sync

    GazeLocation locate_gaze(XrSpace base, XrTime time);
    XrSpaceLocation locate(XrSpace space, XrSpace base, XrTime time);
    XrSpace view_space() const { return view_space_; }
    XrSpace local_space() const { return local_space_; }
    XrSpace gaze_space() const { return gaze_space_; }

    // XR_KHR_convert_timespec_time against CLOCK_MONOTONIC.
    int64_t to_monotonic_ns(XrTime t) const;
    XrTime to_xr_time(int64_t monotonic_ns) const;

private:
    HeadlessSession() = default;
    Result<void> init(const SessionOptions& options);
    Result<void> init_vulkan();
    Result<void> init_actions();
    Result<void> pump_events();

    XrInstance instance_ = XR_NULL_HANDLE;
    XrSystemId system_ = XR_NULL_SYSTEM_ID;
    XrSession session_ = XR_NULL_HANDLE;
    XrSessionState state_ = XR_SESSION_STATE_UNKNOWN;
    bool running_ = false;
    XrSpace view_space_ = XR_NULL_HANDLE, local_space_ = XR_NULL_HANDLE;
    XrActionSet action_set_ = XR_NULL_HANDLE;
    XrAction gaze_action_ = XR_NULL_HANDLE;
    XrSpace gaze_space_ = XR_NULL_HANDLE;
    bool gaze_extension_ = false, supports_gaze_ = false;
    std::string runtime_name_;
    VkInstance vk_instance_ = VK_NULL_HANDLE;
    VkPhysicalDevice vk_physical_ = VK_NULL_HANDLE;
    VkDevice vk_device_ = VK_NULL_HANDLE;
    uint32_t queue_family_ = 0;
    PFN_xrConvertTimeToTimespecTimeKHR to_timespec_ = nullptr;
    PFN_xrConvertTimespecTimeToTimeKHR from_timespec_ = nullptr;
};

// "XR_ERROR_..." for a result code.
std::string result_name(XrInstance instance, XrResult r);

}  // namespace fovea::xr
