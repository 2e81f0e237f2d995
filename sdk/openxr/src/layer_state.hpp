// What the layer knows about the app's OpenXR objects: one InstanceState per XrInstance, one
// SessionState per XrSession, and the actions, action sets and spaces it must recognise, each
// in a small map keyed by handle (no state shared between instances). The maps live in one
// Registry guarded by a shared mutex: lookups (every xrLocateSpace) take it shared, creation and
// destruction exclusive.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <shared_mutex>
#include <string>

#include "gaze_source.hpp"
#include "pose_math.hpp"
#include "xr_includes.hpp"

namespace fovea::openxr {

// The next layer's (or the runtime's) functions the layer calls or hands out.
struct NextDispatch {
    PFN_xrGetInstanceProcAddr GetInstanceProcAddr = nullptr;
    PFN_xrDestroyInstance DestroyInstance = nullptr;
    PFN_xrGetInstanceProperties GetInstanceProperties = nullptr;
    PFN_xrGetSystemProperties GetSystemProperties = nullptr;
    PFN_xrPollEvent PollEvent = nullptr;
    PFN_xrStringToPath StringToPath = nullptr;
    PFN_xrCreateSession CreateSession = nullptr;
    PFN_xrDestroySession DestroySession = nullptr;
    PFN_xrCreateReferenceSpace CreateReferenceSpace = nullptr;
    PFN_xrCreateActionSpace CreateActionSpace = nullptr;
    PFN_xrDestroySpace DestroySpace = nullptr;
    PFN_xrLocateSpace LocateSpace = nullptr;
    PFN_xrCreateActionSet CreateActionSet = nullptr;
    PFN_xrDestroyActionSet DestroyActionSet = nullptr;
    PFN_xrCreateAction CreateAction = nullptr;
    PFN_xrDestroyAction DestroyAction = nullptr;
    PFN_xrSuggestInteractionProfileBindings SuggestInteractionProfileBindings = nullptr;
    PFN_xrAttachSessionActionSets AttachSessionActionSets = nullptr;
    PFN_xrGetCurrentInteractionProfile GetCurrentInteractionProfile = nullptr;
    PFN_xrSyncActions SyncActions = nullptr;
    PFN_xrGetActionStateBoolean GetActionStateBoolean = nullptr;
    PFN_xrGetActionStateFloat GetActionStateFloat = nullptr;
    PFN_xrGetActionStateVector2f GetActionStateVector2f = nullptr;
    PFN_xrGetActionStatePose GetActionStatePose = nullptr;
    PFN_xrEnumerateBoundSourcesForAction EnumerateBoundSourcesForAction = nullptr;
    PFN_xrGetInputSourceLocalizedName GetInputSourceLocalizedName = nullptr;
    PFN_xrConvertTimeToTimespecTimeKHR ConvertTimeToTimespecTimeKHR = nullptr;
    PFN_xrConvertTimespecTimeToTimeKHR ConvertTimespecTimeToTimeKHR = nullptr;
};

struct ActionInfo {
    XrInstance instance = XR_NULL_HANDLE;
    XrActionSet set = XR_NULL_HANDLE;
    XrActionType type = XR_ACTION_TYPE_POSE_INPUT;
    uint32_t subaction_count = 0;  // as the app created it
    bool eyes_subaction = false;   // /user/eyes_ext among them (hidden from the runtime)
    bool gaze_suggested = false;   // bound to /user/eyes_ext/input/gaze_ext/pose
};

struct ActionSetInfo {
    XrInstance instance = XR_NULL_HANDLE;
    bool ever_attached = false;  // suggestions are refused from then on
};

struct InstanceState {
    XrInstance handle = XR_NULL_HANDLE;
    NextDispatch next;
    bool provides_gaze = false;            // the layer implements XR_EXT_eye_gaze_interaction
    bool runtime_has_gaze = false;         // ...and the runtime below has its own
    bool has_timespec = false;             // XR_KHR_convert_timespec_time is enabled below us
    XrPath eyes_path = XR_NULL_PATH;       // /user/eyes_ext
    XrPath gaze_pose_path = XR_NULL_PATH;  // /user/eyes_ext/input/gaze_ext/pose
    XrPath gaze_path = XR_NULL_PATH;       // /user/eyes_ext/input/gaze_ext
    XrPath profile_path = XR_NULL_PATH;    // /interaction_profiles/ext/eye_gaze_interaction
    GazeSourceOptions gaze_options;
};

struct SessionState {
    XrSession handle = XR_NULL_HANDLE;
    InstanceState* instance = nullptr;
    XrSpace view_space = XR_NULL_HANDLE;  // created by the layer: gaze poses live in it
    bool attached = false;
    std::map<XrAction, XrActionSet> gaze_actions;  // attached actions bound to the gaze pose
    std::atomic<bool> gaze_active{false};          // the last xrSyncActions activated them, focused
    std::atomic<XrSessionState> state{XR_SESSION_STATE_UNKNOWN};
    std::unique_ptr<GazeSource> gaze;
};

struct ActionSpaceInfo {
    SessionState* session = nullptr;
    XrAction action = XR_NULL_HANDLE;
    Pose pose_in_action;
};

class Registry {
public:
    std::shared_mutex mu;
    std::map<XrInstance, std::unique_ptr<InstanceState>> instances;
    std::map<XrSession, std::unique_ptr<SessionState>> sessions;
    std::map<XrActionSet, ActionSetInfo> action_sets;
    std::map<XrAction, ActionInfo> actions;
    std::map<XrSpace, ActionSpaceInfo> action_spaces;

    InstanceState* instance(XrInstance h) {
        auto it = instances.find(h);
        return it == instances.end() ? nullptr : it->second.get();
    }
    SessionState* session(XrSession h) {
        auto it = sessions.find(h);
        return it == sessions.end() ? nullptr : it->second.get();
    }
};

Registry& registry();

// The gaze pose of an action space at an XrTime, in the session's view space.
struct GazePose {
    bool valid = false;
    Pose pose;
    XrTime expressed = 0;  // XrEyeGazeSampleTimeEXT::time; 0 when unknown
};

// Layer entry points handed out by xrGetInstanceProcAddr (layer_*.cpp).
PFN_xrVoidFunction intercept(const char* name);
void remove_session(Registry& r, XrSession s);

}  // namespace fovea::openxr
