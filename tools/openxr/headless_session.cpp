#include "headless_session.hpp"

#include <chrono>
#include <cstring>
#include <thread>

namespace fovea::xr {
namespace {

Error xr_error(XrInstance instance, const char* call, XrResult r) {
    return make_error(std::string(call) + " failed: " + result_name(instance, r),
                      static_cast<int>(r));
}

template <typename Fn>
Result<void> load(XrInstance instance, const char* name, Fn& out) {
    const XrResult r =
        xrGetInstanceProcAddr(instance, name, reinterpret_cast<PFN_xrVoidFunction*>(&out));
    if (XR_FAILED(r) || !out) return xr_error(instance, name, r);
    return {};
}

constexpr XrPosef kIdentity{{0, 0, 0, 1}, {0, 0, 0}};

}  // namespace

std::string result_name(XrInstance instance, XrResult r) {
    char buf[XR_MAX_RESULT_STRING_SIZE] = "";
    if (instance == XR_NULL_HANDLE || XR_FAILED(xrResultToString(instance, r, buf)))
        return "XrResult " + std::to_string(static_cast<int>(r));
    return buf;
}

bool Offer::has(const std::string& e) const {
    for (const auto& x : extensions)
        if (x == e) return true;
    return false;
}

Result<Offer> query_offer() {
    Offer o;
    uint32_t n = 0;
    XrResult r = xrEnumerateInstanceExtensionProperties(nullptr, 0, &n, nullptr);
    if (XR_FAILED(r)) return xr_error(XR_NULL_HANDLE, "xrEnumerateInstanceExtensionProperties", r);
    std::vector<XrExtensionProperties> ext(n, {XR_TYPE_EXTENSION_PROPERTIES});
    r = xrEnumerateInstanceExtensionProperties(nullptr, n, &n, ext.data());
    if (XR_FAILED(r)) return xr_error(XR_NULL_HANDLE, "xrEnumerateInstanceExtensionProperties", r);
    for (uint32_t i = 0; i < n; ++i) o.extensions.push_back(ext[i].extensionName);
    n = 0;
    if (XR_SUCCEEDED(xrEnumerateApiLayerProperties(0, &n, nullptr)) && n > 0) {
        std::vector<XrApiLayerProperties> layers(n, {XR_TYPE_API_LAYER_PROPERTIES});
        if (XR_SUCCEEDED(xrEnumerateApiLayerProperties(n, &n, layers.data())))
            for (uint32_t i = 0; i < n; ++i) o.api_layers.push_back(layers[i].layerName);
    }
    return o;
}

Result<std::unique_ptr<HeadlessSession>> HeadlessSession::create(const SessionOptions& options) {
    std::unique_ptr<HeadlessSession> s(new HeadlessSession());
    if (auto r = s->init(options); !r) return r.error();
    return s;
}

Result<void> HeadlessSession::init(const SessionOptions& options) {
    auto offer = query_offer();
    if (!offer) return offer.error();
    if (!offer->has(XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME))
        return make_error("the OpenXR runtime does not offer XR_KHR_vulkan_enable2");
    if (!offer->has(XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME))
        return make_error("the OpenXR runtime does not offer XR_KHR_convert_timespec_time");
    gaze_extension_ = options.eye_gaze && offer->has(XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
    std::vector<const char*> exts = {XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME,
                                     XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME};
    if (gaze_extension_) exts.push_back(XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);

    XrInstanceCreateInfo ci{XR_TYPE_INSTANCE_CREATE_INFO};
    std::strncpy(ci.applicationInfo.applicationName, options.app_name.c_str(),
                 XR_MAX_APPLICATION_NAME_SIZE - 1);
    std::strncpy(ci.applicationInfo.engineName, "fovea", XR_MAX_ENGINE_NAME_SIZE - 1);
    ci.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    ci.enabledExtensionCount = static_cast<uint32_t>(exts.size());
    ci.enabledExtensionNames = exts.data();
    XrResult r = xrCreateInstance(&ci, &instance_);
    if (XR_FAILED(r)) return xr_error(XR_NULL_HANDLE, "xrCreateInstance", r);
    XrInstanceProperties ip{XR_TYPE_INSTANCE_PROPERTIES};
    if (XR_SUCCEEDED(xrGetInstanceProperties(instance_, &ip))) runtime_name_ = ip.runtimeName;
    if (auto l = load(instance_, "xrConvertTimeToTimespecTimeKHR", to_timespec_); !l) return l;
    if (auto l = load(instance_, "xrConvertTimespecTimeToTimeKHR", from_timespec_); !l) return l;

    XrSystemGetInfo si{XR_TYPE_SYSTEM_GET_INFO};
    si.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    r = xrGetSystem(instance_, &si, &system_);
    if (XR_FAILED(r)) return xr_error(instance_, "xrGetSystem", r);
    XrSystemEyeGazeInteractionPropertiesEXT gaze_props{
        XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT};
    XrSystemProperties sp{XR_TYPE_SYSTEM_PROPERTIES, gaze_extension_ ? &gaze_props : nullptr};
    r = xrGetSystemProperties(instance_, system_, &sp);
    if (XR_FAILED(r)) return xr_error(instance_, "xrGetSystemProperties", r);
    supports_gaze_ = gaze_extension_ && gaze_props.supportsEyeGazeInteraction;

    if (auto v = init_vulkan(); !v) return v;
    XrGraphicsBindingVulkan2KHR binding{XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR};
    binding.instance = vk_instance_;
    binding.physicalDevice = vk_physical_;
    binding.device = vk_device_;
    binding.queueFamilyIndex = queue_family_;
    binding.queueIndex = 0;
    XrSessionCreateInfo sc{XR_TYPE_SESSION_CREATE_INFO, &binding};
    sc.systemId = system_;
    r = xrCreateSession(instance_, &sc, &session_);
    if (XR_FAILED(r)) return xr_error(instance_, "xrCreateSession", r);

    XrReferenceSpaceCreateInfo rs{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    rs.poseInReferenceSpace = kIdentity;
    rs.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    r = xrCreateReferenceSpace(session_, &rs, &view_space_);
    if (XR_FAILED(r)) return xr_error(instance_, "xrCreateReferenceSpace(VIEW)", r);
    rs.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
    r = xrCreateReferenceSpace(session_, &rs, &local_space_);
    if (XR_FAILED(r)) return xr_error(instance_, "xrCreateReferenceSpace(LOCAL)", r);
    return init_actions();
}

Result<void> HeadlessSession::init_vulkan() {
    PFN_xrGetVulkanGraphicsRequirements2KHR requirements = nullptr;
    PFN_xrCreateVulkanInstanceKHR create_instance = nullptr;
    PFN_xrGetVulkanGraphicsDevice2KHR get_device = nullptr;
    PFN_xrCreateVulkanDeviceKHR create_device = nullptr;
    for (auto l : {load(instance_, "xrGetVulkanGraphicsRequirements2KHR", requirements),
                   load(instance_, "xrCreateVulkanInstanceKHR", create_instance),
                   load(instance_, "xrGetVulkanGraphicsDevice2KHR", get_device),
                   load(instance_, "xrCreateVulkanDeviceKHR", create_device)})
        if (!l) return l;
    XrGraphicsRequirementsVulkan2KHR req{XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN2_KHR};
    XrResult r = requirements(instance_, system_, &req);
    if (XR_FAILED(r)) return xr_error(instance_, "xrGetVulkanGraphicsRequirements2KHR", r);

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "fovea openxr-check";
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo vci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    vci.pApplicationInfo = &app;
    XrVulkanInstanceCreateInfoKHR xci{XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR};
    xci.systemId = system_;
    xci.pfnGetInstanceProcAddr = vkGetInstanceProcAddr;
    xci.vulkanCreateInfo = &vci;
    VkResult vr = VK_SUCCESS;
    r = create_instance(instance_, &xci, &vk_instance_, &vr);
    if (XR_FAILED(r) || vr != VK_SUCCESS)
        return make_error("xrCreateVulkanInstanceKHR failed: " + result_name(instance_, r) +
                          ", VkResult " + std::to_string(vr));
    XrVulkanGraphicsDeviceGetInfoKHR gi{XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR};
    gi.systemId = system_;
    gi.vulkanInstance = vk_instance_;
    r = get_device(instance_, &gi, &vk_physical_);
    if (XR_FAILED(r)) return xr_error(instance_, "xrGetVulkanGraphicsDevice2KHR", r);

    uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(vk_physical_, &nq, nullptr);
    std::vector<VkQueueFamilyProperties> families(nq);
    vkGetPhysicalDeviceQueueFamilyProperties(vk_physical_, &nq, families.data());
    bool found = false;
    for (uint32_t i = 0; i < nq && !found; ++i)
        if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) {
            queue_family_ = i;
            found = true;
        }
    if (!found) return make_error("the runtime's Vulkan device has no graphics queue");
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = queue_family_;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    XrVulkanDeviceCreateInfoKHR xdi{XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR};
    xdi.systemId = system_;
    xdi.pfnGetInstanceProcAddr = vkGetInstanceProcAddr;
    xdi.vulkanPhysicalDevice = vk_physical_;
    xdi.vulkanCreateInfo = &dci;
    r = create_device(instance_, &xdi, &vk_device_, &vr);
    if (XR_FAILED(r) || vr != VK_SUCCESS)
        return make_error("xrCreateVulkanDeviceKHR failed: " + result_name(instance_, r) +
                          ", VkResult " + std::to_string(vr));
    return {};
}

Result<void> HeadlessSession::init_actions() {
    if (!gaze_extension_) return {};
    XrActionSetCreateInfo asi{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(asi.actionSetName, "gaze");
    std::strcpy(asi.localizedActionSetName, "Gaze");
    XrResult r = xrCreateActionSet(instance_, &asi, &action_set_);
    if (XR_FAILED(r)) return xr_error(instance_, "xrCreateActionSet", r);
    XrActionCreateInfo ai{XR_TYPE_ACTION_CREATE_INFO};
    std::strcpy(ai.actionName, "gaze_pose");
    std::strcpy(ai.localizedActionName, "Gaze pose");
    ai.actionType = XR_ACTION_TYPE_POSE_INPUT;
    r = xrCreateAction(action_set_, &ai, &gaze_action_);
    if (XR_FAILED(r)) return xr_error(instance_, "xrCreateAction", r);
    XrPath profile = XR_NULL_PATH, pose = XR_NULL_PATH;
    xrStringToPath(instance_, "/interaction_profiles/ext/eye_gaze_interaction", &profile);
    xrStringToPath(instance_, "/user/eyes_ext/input/gaze_ext/pose", &pose);
    XrActionSuggestedBinding b{gaze_action_, pose};
    XrInteractionProfileSuggestedBinding sb{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
    sb.interactionProfile = profile;
    sb.countSuggestedBindings = 1;
    sb.suggestedBindings = &b;
    r = xrSuggestInteractionProfileBindings(instance_, &sb);
    if (XR_FAILED(r)) return xr_error(instance_, "xrSuggestInteractionProfileBindings", r);
    XrSessionActionSetsAttachInfo at{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
    at.countActionSets = 1;
    at.actionSets = &action_set_;
    r = xrAttachSessionActionSets(session_, &at);
    if (XR_FAILED(r)) return xr_error(instance_, "xrAttachSessionActionSets", r);
    XrActionSpaceCreateInfo sci{XR_TYPE_ACTION_SPACE_CREATE_INFO};
    sci.action = gaze_action_;
    sci.poseInActionSpace = kIdentity;
    r = xrCreateActionSpace(session_, &sci, &gaze_space_);
    if (XR_FAILED(r)) return xr_error(instance_, "xrCreateActionSpace", r);
    return {};
}

HeadlessSession::~HeadlessSession() {
    if (session_ != XR_NULL_HANDLE) {
        if (running_) xrRequestExitSession(session_);
        xrDestroySession(session_);  // its spaces go with it
    }
    if (instance_ != XR_NULL_HANDLE) xrDestroyInstance(instance_);
    if (vk_device_ != VK_NULL_HANDLE) vkDestroyDevice(vk_device_, nullptr);
    if (vk_instance_ != VK_NULL_HANDLE) vkDestroyInstance(vk_instance_, nullptr);
}

Result<void> HeadlessSession::pump_events() {
    for (;;) {
        XrEventDataBuffer e{XR_TYPE_EVENT_DATA_BUFFER};
        const XrResult r = xrPollEvent(instance_, &e);
        if (r == XR_EVENT_UNAVAILABLE) return {};
        if (XR_FAILED(r)) return xr_error(instance_, "xrPollEvent", r);
        if (e.type == XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING)
            return make_error("the OpenXR instance is being lost");
        if (e.type != XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) continue;
        state_ = reinterpret_cast<XrEventDataSessionStateChanged&>(e).state;
        if (state_ == XR_SESSION_STATE_READY && !running_) {
            XrSessionBeginInfo bi{XR_TYPE_SESSION_BEGIN_INFO};
            bi.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
            const XrResult b = xrBeginSession(session_, &bi);
            if (XR_FAILED(b)) return xr_error(instance_, "xrBeginSession", b);
            running_ = true;
        } else if (state_ == XR_SESSION_STATE_STOPPING || state_ == XR_SESSION_STATE_EXITING ||
                   state_ == XR_SESSION_STATE_LOSS_PENDING) {
            return make_error("the OpenXR session is ending");
        }
    }
}

Result<void> HeadlessSession::wait_until_focused(int timeout_ms) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (std::chrono::steady_clock::now() < end) {
        if (auto r = pump_events(); !r) return r;
        if (state_ == XR_SESSION_STATE_FOCUSED) return {};
        if (running_) {  // frames must flow for the runtime to reach VISIBLE and FOCUSED
            auto f = begin_frame();
            if (!f) return f.error();
            if (auto e = end_frame(*f); !e) return e;
        } else {
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    }
    return make_error("the OpenXR session did not reach FOCUSED within " +
                      std::to_string(timeout_ms) + " ms");
}

Result<HeadlessSession::Frame> HeadlessSession::begin_frame() {
    if (auto r = pump_events(); !r) return r.error();
    XrFrameState fs{XR_TYPE_FRAME_STATE};
    XrFrameWaitInfo wi{XR_TYPE_FRAME_WAIT_INFO};
    XrResult r = xrWaitFrame(session_, &wi, &fs);
    if (XR_FAILED(r)) return xr_error(instance_, "xrWaitFrame", r);
    XrFrameBeginInfo bi{XR_TYPE_FRAME_BEGIN_INFO};
    r = xrBeginFrame(session_, &bi);
    if (XR_FAILED(r)) return xr_error(instance_, "xrBeginFrame", r);
    if (gaze_extension_) {
        XrActiveActionSet active{action_set_, XR_NULL_PATH};
        XrActionsSyncInfo sync{XR_TYPE_ACTIONS_SYNC_INFO};
        sync.countActiveActionSets = 1;
        sync.activeActionSets = &active;
        r = xrSyncActions(session_, &sync);
        if (XR_FAILED(r)) return xr_error(instance_, "xrSyncActions", r);
    }
    return Frame{fs.predictedDisplayTime, fs.predictedDisplayPeriod};
}

Result<void> HeadlessSession::end_frame(const Frame& f) {
    XrFrameEndInfo ei{XR_TYPE_FRAME_END_INFO};
    ei.displayTime = f.display_time;
    ei.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    const XrResult r = xrEndFrame(session_, &ei);
    if (XR_FAILED(r)) return xr_error(instance_, "xrEndFrame", r);
    return {};
}

bool HeadlessSession::gaze_action_active() {
    if (!gaze_extension_) return false;
    XrActionStateGetInfo gi{XR_TYPE_ACTION_STATE_GET_INFO};
    gi.action = gaze_action_;
    XrActionStatePose st{XR_TYPE_ACTION_STATE_POSE};
    return XR_SUCCEEDED(xrGetActionStatePose(session_, &gi, &st)) && st.isActive;
}

GazeLocation HeadlessSession::locate_gaze(XrSpace base, XrTime time) {
    GazeLocation g;
    if (gaze_space_ == XR_NULL_HANDLE) return g;
    XrEyeGazeSampleTimeEXT st{XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT};
    XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION, &st};
    if (XR_FAILED(xrLocateSpace(gaze_space_, base, time, &loc))) return g;
    g.flags = loc.locationFlags;
    g.pose = loc.pose;
    g.sample_time = st.time;
    return g;
}

XrSpaceLocation HeadlessSession::locate(XrSpace space, XrSpace base, XrTime time) {
    XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION};
    if (XR_FAILED(xrLocateSpace(space, base, time, &loc))) loc.locationFlags = 0;
    return loc;
}

int64_t HeadlessSession::to_monotonic_ns(XrTime t) const {
    timespec ts{};
    if (XR_FAILED(to_timespec_(instance_, t, &ts))) return 0;
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

XrTime HeadlessSession::to_xr_time(int64_t ns) const {
    const timespec ts{static_cast<time_t>(ns / 1'000'000'000),
                      static_cast<long>(ns % 1'000'000'000)};
    XrTime t = 0;
    if (XR_FAILED(from_timespec_(instance_, &ts, &t))) return 0;
    return t;
}

}  // namespace fovea::xr
