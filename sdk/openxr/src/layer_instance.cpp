// The loader-facing half of XR_APILAYER_FOVEA_eye_gaze: negotiation, instance creation (adding
// XR_KHR_convert_timespec_time below us, removing XR_EXT_eye_gaze_interaction where the layer
// provides it), xrGetInstanceProcAddr, system properties, sessions and their state events.
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "layer_config.hpp"
#include "layer_log.hpp"
#include "layer_state.hpp"
#include "loader_interface.hpp"
#include "xr_chain.hpp"

namespace fovea::openxr {

constexpr const char* kLayerName = "XR_APILAYER_FOVEA_eye_gaze";

Registry& registry() {
    static Registry r;
    return r;
}

namespace {

bool has_extension(const std::vector<XrExtensionProperties>& list, const char* name) {
    return std::any_of(list.begin(), list.end(), [&](const XrExtensionProperties& p) {
        return !strcmp(p.extensionName, name);
    });
}

// The extensions `gipa` offers, or an empty list if it cannot be asked.
std::vector<XrExtensionProperties> extensions_below(PFN_xrGetInstanceProcAddr gipa) {
    PFN_xrEnumerateInstanceExtensionProperties enumerate = nullptr;
    if (XR_FAILED(gipa(XR_NULL_HANDLE, "xrEnumerateInstanceExtensionProperties",
                       reinterpret_cast<PFN_xrVoidFunction*>(&enumerate))) ||
        !enumerate)
        return {};
    uint32_t n = 0;
    if (XR_FAILED(enumerate(nullptr, 0, &n, nullptr))) return {};
    std::vector<XrExtensionProperties> list(n, {XR_TYPE_EXTENSION_PROPERTIES});
    if (XR_FAILED(enumerate(nullptr, n, &n, list.data()))) return {};
    list.resize(n);
    return list;
}

template <typename Fn>
void load(PFN_xrGetInstanceProcAddr gipa, XrInstance inst, const char* name, Fn& out) {
    out = nullptr;
    gipa(inst, name, reinterpret_cast<PFN_xrVoidFunction*>(&out));
}

void load_dispatch(PFN_xrGetInstanceProcAddr gipa, XrInstance i, NextDispatch& d) {
    d.GetInstanceProcAddr = gipa;
    load(gipa, i, "xrDestroyInstance", d.DestroyInstance);
    load(gipa, i, "xrGetInstanceProperties", d.GetInstanceProperties);
    load(gipa, i, "xrGetSystemProperties", d.GetSystemProperties);
    load(gipa, i, "xrPollEvent", d.PollEvent);
    load(gipa, i, "xrStringToPath", d.StringToPath);
    load(gipa, i, "xrCreateSession", d.CreateSession);
    load(gipa, i, "xrDestroySession", d.DestroySession);
    load(gipa, i, "xrCreateReferenceSpace", d.CreateReferenceSpace);
    load(gipa, i, "xrCreateActionSpace", d.CreateActionSpace);
    load(gipa, i, "xrDestroySpace", d.DestroySpace);
    load(gipa, i, "xrLocateSpace", d.LocateSpace);
    load(gipa, i, "xrCreateActionSet", d.CreateActionSet);
    load(gipa, i, "xrDestroyActionSet", d.DestroyActionSet);
    load(gipa, i, "xrCreateAction", d.CreateAction);
    load(gipa, i, "xrDestroyAction", d.DestroyAction);
    load(gipa, i, "xrSuggestInteractionProfileBindings", d.SuggestInteractionProfileBindings);
    load(gipa, i, "xrAttachSessionActionSets", d.AttachSessionActionSets);
    load(gipa, i, "xrGetCurrentInteractionProfile", d.GetCurrentInteractionProfile);
    load(gipa, i, "xrSyncActions", d.SyncActions);
    load(gipa, i, "xrGetActionStateBoolean", d.GetActionStateBoolean);
    load(gipa, i, "xrGetActionStateFloat", d.GetActionStateFloat);
    load(gipa, i, "xrGetActionStateVector2f", d.GetActionStateVector2f);
    load(gipa, i, "xrGetActionStatePose", d.GetActionStatePose);
    load(gipa, i, "xrEnumerateBoundSourcesForAction", d.EnumerateBoundSourcesForAction);
    load(gipa, i, "xrGetInputSourceLocalizedName", d.GetInputSourceLocalizedName);
    load(gipa, i, "xrConvertTimeToTimespecTimeKHR", d.ConvertTimeToTimespecTimeKHR);
    load(gipa, i, "xrConvertTimespecTimeToTimeKHR", d.ConvertTimespecTimeToTimeKHR);
}

XrPath to_path(const InstanceState& s, const char* text) {
    XrPath p = XR_NULL_PATH;
    if (s.next.StringToPath) s.next.StringToPath(s.handle, text, &p);
    return p;
}

XRAPI_ATTR XrResult XRAPI_CALL layer_gipa(XrInstance instance, const char* name,
                                          PFN_xrVoidFunction* function);

XRAPI_ATTR XrResult XRAPI_CALL layer_create_instance(const XrInstanceCreateInfo* info,
                                                     const XrApiLayerCreateInfo* layer_info,
                                                     XrInstance* instance) {
    if (!info || !layer_info || !instance || !layer_info->nextInfo ||
        layer_info->structType != XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO ||
        layer_info->nextInfo->structType != XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO ||
        strcmp(layer_info->nextInfo->layerName, kLayerName) != 0)
        return XR_ERROR_INITIALIZATION_FAILED;
    const PFN_xrGetInstanceProcAddr next_gipa = layer_info->nextInfo->nextGetInstanceProcAddr;
    const PFN_xrCreateApiLayerInstance next_create =
        layer_info->nextInfo->nextCreateApiLayerInstance;
    XrApiLayerCreateInfo down_info = *layer_info;
    down_info.nextInfo = layer_info->nextInfo->next;

    const LayerConfig config = read_layer_config();
    // Ask the runtime itself: the last link of the chain is the loader's terminator, which hands
    // instance-less queries to the runtime (a validation layer between would flag the null
    // instance as an error of ours).
    const XrApiLayerNextInfo* last = layer_info->nextInfo;
    while (last->next) last = last->next;
    const std::vector<XrExtensionProperties> below =
        extensions_below(last->nextGetInstanceProcAddr);
    const bool runtime_gaze = has_extension(below, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
    const bool runtime_timespec = has_extension(below, XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME);
    bool app_gaze = false, app_timespec = false;
    for (uint32_t i = 0; i < info->enabledExtensionCount; ++i) {
        app_gaze |=
            !strcmp(info->enabledExtensionNames[i], XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
        app_timespec |=
            !strcmp(info->enabledExtensionNames[i], XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME);
    }
    const bool provide = app_gaze && (!runtime_gaze || config.replace_runtime_gaze);

    // Without the app asking for eye gaze the layer changes nothing below it.
    std::vector<const char*> names;
    for (uint32_t i = 0; i < info->enabledExtensionCount; ++i)
        if (!provide ||
            strcmp(info->enabledExtensionNames[i], XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME) != 0)
            names.push_back(info->enabledExtensionNames[i]);
    // A layer below may not answer the enumeration: then try the extension and do without it
    // if the runtime refuses.
    const bool unknown_below = below.empty();
    const bool add_timespec = provide && !app_timespec && (runtime_timespec || unknown_below);
    if (add_timespec) names.push_back(XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME);
    XrInstanceCreateInfo down = *info;
    down.enabledExtensionCount = static_cast<uint32_t>(names.size());
    down.enabledExtensionNames = names.data();

    XrResult r = next_create(&down, &down_info, instance);
    bool timespec = add_timespec || app_timespec;
    if (r == XR_ERROR_EXTENSION_NOT_PRESENT && add_timespec && unknown_below) {
        --down.enabledExtensionCount;
        timespec = false;
        r = next_create(&down, &down_info, instance);
    }
    if (XR_FAILED(r)) return r;

    auto state = std::make_unique<InstanceState>();
    state->handle = *instance;
    state->provides_gaze = provide;
    state->runtime_has_gaze = runtime_gaze;
    state->has_timespec = provide && timespec;
    state->gaze_options = config.gaze;
    load_dispatch(next_gipa, *instance, state->next);
    if (provide) {
        state->eyes_path = to_path(*state, "/user/eyes_ext");
        state->gaze_path = to_path(*state, "/user/eyes_ext/input/gaze_ext");
        state->gaze_pose_path = to_path(*state, "/user/eyes_ext/input/gaze_ext/pose");
        state->profile_path = to_path(*state, "/interaction_profiles/ext/eye_gaze_interaction");
        state->has_timespec = state->has_timespec && state->next.ConvertTimeToTimespecTimeKHR &&
                              state->next.ConvertTimespecTimeToTimeKHR;
        XrInstanceProperties props{XR_TYPE_INSTANCE_PROPERTIES};
        if (state->next.GetInstanceProperties) state->next.GetInstanceProperties(*instance, &props);
        if (!state->has_timespec)
            log_info(
                "runtime '%s' lacks XR_KHR_convert_timespec_time: fovead's timestamps cannot "
                "be mapped to XrTime, eye gaze poses stay invalid",
                props.runtimeName);
        else
            log_info(
                "providing XR_EXT_eye_gaze_interaction from fovead instance '%s' (runtime "
                "'%s' %s)%s%s",
                config.gaze.instance.c_str(), props.runtimeName,
                runtime_gaze ? "has its own, replaced: FOVEA_OPENXR_GAZE=replace" : "has none",
                config.problems.empty() ? "" : "; ignored: ", config.problems.c_str());
    }
    std::unique_lock lock(registry().mu);
    registry().instances[*instance] = std::move(state);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL layer_destroy_instance(XrInstance instance) {
    PFN_xrDestroyInstance destroy = nullptr;
    {
        Registry& reg = registry();
        std::unique_lock lock(reg.mu);
        InstanceState* s = reg.instance(instance);
        if (!s) return XR_ERROR_HANDLE_INVALID;
        destroy = s->next.DestroyInstance;
        std::vector<XrSession> sessions;
        for (auto& [h, ss] : reg.sessions)
            if (ss->instance == s) sessions.push_back(h);
        for (XrSession h : sessions) remove_session(reg, h);
        std::erase_if(reg.actions, [&](const auto& kv) { return kv.second.instance == instance; });
        std::erase_if(reg.action_sets,
                      [&](const auto& kv) { return kv.second.instance == instance; });
        reg.instances.erase(instance);
    }
    return destroy(instance);
}

XRAPI_ATTR XrResult XRAPI_CALL layer_get_system_properties(XrInstance instance, XrSystemId system,
                                                           XrSystemProperties* props) {
    NextDispatch next;
    bool own = false;
    {
        std::shared_lock lock(registry().mu);
        InstanceState* s = registry().instance(instance);
        if (!s) return XR_ERROR_HANDLE_INVALID;
        next = s->next;
        own = s->provides_gaze && !s->runtime_has_gaze;
    }
    if (!props) return next.GetSystemProperties(instance, system, props);
    auto* gaze = find_in_chain<XrSystemEyeGazeInteractionPropertiesEXT>(
        props->next, XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT);
    XrResult r;
    if (own && gaze) {
        ChainCut cut(props, XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT);
        r = next.GetSystemProperties(instance, system, props);
    } else {
        r = next.GetSystemProperties(instance, system, props);
    }
    // The layer can serve gaze whenever fovead runs; whether it does right now shows in the
    // pose's tracking flags, as for a headset's tracker that is not yet calibrated.
    if (XR_SUCCEEDED(r) && gaze) gaze->supportsEyeGazeInteraction = XR_TRUE;
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layer_create_session(XrInstance instance,
                                                    const XrSessionCreateInfo* info,
                                                    XrSession* session) {
    InstanceState* inst = nullptr;
    {
        std::shared_lock lock(registry().mu);
        inst = registry().instance(instance);
    }
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    const XrResult r = inst->next.CreateSession(instance, info, session);
    if (XR_FAILED(r)) return r;
    auto s = std::make_unique<SessionState>();
    s->handle = *session;
    s->instance = inst;
    XrReferenceSpaceCreateInfo view{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    view.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    view.poseInReferenceSpace.orientation.w = 1.0f;
    if (XR_FAILED(inst->next.CreateReferenceSpace(*session, &view, &s->view_space))) {
        log_info("could not create a VIEW space in the session: eye gaze poses stay invalid");
        s->view_space = XR_NULL_HANDLE;
    }
    s->gaze = std::make_unique<GazeSource>(inst->gaze_options);
    std::unique_lock lock(registry().mu);
    registry().sessions[*session] = std::move(s);
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layer_destroy_session(XrSession session) {
    PFN_xrDestroySession destroy = nullptr;
    {
        Registry& reg = registry();
        std::unique_lock lock(reg.mu);
        SessionState* s = reg.session(session);
        if (!s) return XR_ERROR_HANDLE_INVALID;
        destroy = s->instance->next.DestroySession;
        remove_session(reg, session);
    }
    return destroy(session);  // the runtime destroys the session's spaces, ours included
}

XRAPI_ATTR XrResult XRAPI_CALL layer_poll_event(XrInstance instance, XrEventDataBuffer* event) {
    PFN_xrPollEvent poll = nullptr;
    {
        std::shared_lock lock(registry().mu);
        InstanceState* s = registry().instance(instance);
        if (!s) return XR_ERROR_HANDLE_INVALID;
        poll = s->next.PollEvent;
    }
    const XrResult r = poll(instance, event);
    if (r == XR_SUCCESS && event->type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
        const auto* e = reinterpret_cast<const XrEventDataSessionStateChanged*>(event);
        std::shared_lock lock(registry().mu);
        if (SessionState* s = registry().session(e->session)) s->state = e->state;
    }
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layer_gipa(XrInstance instance, const char* name,
                                          PFN_xrVoidFunction* function) {
    if (!name || !function) return XR_ERROR_VALIDATION_FAILURE;
    *function = nullptr;
    if (!strcmp(name, "xrGetInstanceProcAddr")) {
        *function = reinterpret_cast<PFN_xrVoidFunction>(layer_gipa);
        return XR_SUCCESS;
    }
    InstanceState* s = nullptr;
    {
        std::shared_lock lock(registry().mu);
        s = registry().instance(instance);
    }
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!strcmp(name, "xrDestroyInstance")) {
        *function = reinterpret_cast<PFN_xrVoidFunction>(layer_destroy_instance);
        return XR_SUCCESS;
    }
    if (s->provides_gaze) {
        static const std::pair<const char*, PFN_xrVoidFunction> kOwn[] = {
            {"xrGetSystemProperties",
             reinterpret_cast<PFN_xrVoidFunction>(layer_get_system_properties)},
            {"xrCreateSession", reinterpret_cast<PFN_xrVoidFunction>(layer_create_session)},
            {"xrDestroySession", reinterpret_cast<PFN_xrVoidFunction>(layer_destroy_session)},
            {"xrPollEvent", reinterpret_cast<PFN_xrVoidFunction>(layer_poll_event)},
        };
        for (const auto& [n, f] : kOwn)
            if (!strcmp(name, n)) {
                *function = f;
                return XR_SUCCESS;
            }
        if ((*function = intercept(name))) return XR_SUCCESS;
    }
    return s->next.GetInstanceProcAddr(instance, name, function);
}

}  // namespace

void remove_session(Registry& reg, XrSession h) {
    std::erase_if(reg.action_spaces,
                  [&](const auto& kv) { return kv.second.session->handle == h; });
    reg.sessions.erase(h);
}

}  // namespace fovea::openxr

extern "C" __attribute__((visibility("default"))) XrResult XRAPI_CALL
xrNegotiateLoaderApiLayerInterface(const XrNegotiateLoaderInfo* loader, const char* layer_name,
                                   XrNegotiateApiLayerRequest* request) {
    using namespace fovea::openxr;
    if (!loader || !request || loader->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
        loader->structVersion != kLoaderInfoStructVersion ||
        loader->structSize != sizeof(XrNegotiateLoaderInfo) ||
        request->structType != XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST ||
        request->structVersion != kApiLayerInfoStructVersion ||
        request->structSize != sizeof(XrNegotiateApiLayerRequest) ||
        loader->minInterfaceVersion > kLoaderApiLayerInterfaceVersion ||
        loader->maxInterfaceVersion < kLoaderApiLayerInterfaceVersion ||
        XR_VERSION_MAJOR(loader->maxApiVersion) < 1 || XR_VERSION_MAJOR(loader->minApiVersion) > 1)
        return XR_ERROR_INITIALIZATION_FAILED;
    if (layer_name && strcmp(layer_name, kLayerName) != 0) return XR_ERROR_INITIALIZATION_FAILED;
    request->layerInterfaceVersion = kLoaderApiLayerInterfaceVersion;
    request->layerApiVersion = XR_CURRENT_API_VERSION;
    request->getInstanceProcAddr = layer_gipa;
    request->createApiLayerInstance = layer_create_instance;
    return XR_SUCCESS;
}
