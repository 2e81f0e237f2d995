// The action-system half of XR_EXT_eye_gaze_interaction where the layer provides it: the
// /interaction_profiles/ext/eye_gaze_interaction profile's bindings, /user/eyes_ext as a
// subaction path (hidden from a runtime that does not know it), action state and action
// spaces of actions bound to /user/eyes_ext/input/gaze_ext/pose. Everything else goes down
// untouched.
#include <cstring>
#include <vector>

#include "layer_state.hpp"

namespace fovea::openxr {
namespace {

InstanceState* instance_of_set(Registry& reg, XrActionSet set) {
    auto it = reg.action_sets.find(set);
    return it == reg.action_sets.end() ? nullptr : reg.instance(it->second.instance);
}

XRAPI_ATTR XrResult XRAPI_CALL create_action_set(XrInstance instance,
                                                 const XrActionSetCreateInfo* info,
                                                 XrActionSet* set) {
    Registry& reg = registry();
    InstanceState* inst = nullptr;
    {
        std::shared_lock lock(reg.mu);
        inst = reg.instance(instance);
    }
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    const XrResult r = inst->next.CreateActionSet(instance, info, set);
    if (XR_SUCCEEDED(r)) {
        std::unique_lock lock(reg.mu);
        reg.action_sets[*set] = {instance, false};
    }
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL destroy_action_set(XrActionSet set) {
    Registry& reg = registry();
    std::unique_lock lock(reg.mu);
    InstanceState* inst = instance_of_set(reg, set);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    const XrResult r = inst->next.DestroyActionSet(set);
    if (XR_SUCCEEDED(r)) {
        std::erase_if(reg.actions, [&](const auto& kv) { return kv.second.set == set; });
        reg.action_sets.erase(set);
    }
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL create_action(XrActionSet set, const XrActionCreateInfo* info,
                                             XrAction* action) {
    Registry& reg = registry();
    InstanceState* inst = nullptr;
    {
        std::shared_lock lock(reg.mu);
        inst = instance_of_set(reg, set);
    }
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_ACTION_CREATE_INFO)
        return inst->next.CreateAction(set, info, action);
    ActionInfo a;
    a.instance = inst->handle;
    a.set = set;
    a.type = info->actionType;
    a.subaction_count = info->countSubactionPaths;
    std::vector<XrPath> paths;
    for (uint32_t i = 0; info->subactionPaths && i < info->countSubactionPaths; ++i) {
        if (info->subactionPaths[i] == inst->eyes_path)
            a.eyes_subaction = true;
        else
            paths.push_back(info->subactionPaths[i]);
    }
    XrActionCreateInfo down = *info;
    down.countSubactionPaths = static_cast<uint32_t>(paths.size());
    down.subactionPaths = paths.empty() ? nullptr : paths.data();
    const XrResult r = inst->next.CreateAction(set, &down, action);
    if (XR_SUCCEEDED(r)) {
        std::unique_lock lock(reg.mu);
        reg.actions[*action] = a;
    }
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL destroy_action(XrAction action) {
    Registry& reg = registry();
    std::unique_lock lock(reg.mu);
    auto it = reg.actions.find(action);
    if (it == reg.actions.end()) return XR_ERROR_HANDLE_INVALID;
    InstanceState* inst = reg.instance(it->second.instance);
    const XrResult r = inst->next.DestroyAction(action);
    if (XR_SUCCEEDED(r)) reg.actions.erase(it);
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL suggest_bindings(XrInstance instance,
                                                const XrInteractionProfileSuggestedBinding* s) {
    Registry& reg = registry();
    std::unique_lock lock(reg.mu);
    InstanceState* inst = reg.instance(instance);
    if (!inst) return XR_ERROR_HANDLE_INVALID;
    if (!s || s->interactionProfile != inst->profile_path) {
        lock.unlock();
        return inst->next.SuggestInteractionProfileBindings(instance, s);
    }
    if (s->type != XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING ||
        s->countSuggestedBindings == 0 || !s->suggestedBindings)
        return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < s->countSuggestedBindings; ++i) {
        const XrActionSuggestedBinding& b = s->suggestedBindings[i];
        auto it = reg.actions.find(b.action);
        if (it == reg.actions.end() || it->second.instance != instance)
            return XR_ERROR_HANDLE_INVALID;
        if (reg.action_sets[it->second.set].ever_attached)
            return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
        const ActionInfo& a = it->second;
        const bool gaze_path = b.binding == inst->gaze_pose_path || b.binding == inst->gaze_path;
        // The profile has one input, a pose; a subaction list must name /user/eyes_ext.
        if (!gaze_path || a.type != XR_ACTION_TYPE_POSE_INPUT ||
            (a.subaction_count > 0 && !a.eyes_subaction))
            return XR_ERROR_PATH_UNSUPPORTED;
    }
    // A new suggestion for a profile replaces the previous one.
    for (auto& [h, a] : reg.actions)
        if (a.instance == instance) a.gaze_suggested = false;
    for (uint32_t i = 0; i < s->countSuggestedBindings; ++i)
        reg.actions[s->suggestedBindings[i].action].gaze_suggested = true;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL attach_action_sets(XrSession session,
                                                  const XrSessionActionSetsAttachInfo* info) {
    Registry& reg = registry();
    SessionState* sess = nullptr;
    {
        std::shared_lock lock(reg.mu);
        sess = reg.session(session);
    }
    if (!sess) return XR_ERROR_HANDLE_INVALID;
    const XrResult r = sess->instance->next.AttachSessionActionSets(session, info);
    if (XR_FAILED(r)) return r;
    std::unique_lock lock(reg.mu);
    sess->attached = true;
    for (uint32_t i = 0; i < info->countActionSets; ++i) {
        const XrActionSet set = info->actionSets[i];
        reg.action_sets[set].ever_attached = true;
        for (const auto& [h, a] : reg.actions)
            if (a.set == set && a.gaze_suggested) sess->gaze_actions[h] = set;
    }
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL sync_actions(XrSession session, const XrActionsSyncInfo* info) {
    Registry& reg = registry();
    std::shared_lock lock(reg.mu);
    SessionState* sess = reg.session(session);
    if (!sess) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& inst = *sess->instance;
    if (!info || info->type != XR_TYPE_ACTIONS_SYNC_INFO || !info->activeActionSets ||
        sess->gaze_actions.empty()) {
        sess->gaze_active = false;
        return inst.next.SyncActions(session, info);
    }
    bool wants_gaze = false;
    std::vector<XrActiveActionSet> down;
    for (uint32_t i = 0; i < info->countActiveActionSets; ++i) {
        const XrActiveActionSet& a = info->activeActionSets[i];
        const bool eyes = a.subactionPath == inst.eyes_path;
        for (const auto& [action, set] : sess->gaze_actions)
            wants_gaze |= set == a.actionSet && (eyes || a.subactionPath == XR_NULL_PATH);
        if (!eyes) down.push_back(a);
    }
    // Only eye subactions asked for: the runtime needs at least one set to sync.
    if (down.empty())
        for (uint32_t i = 0; i < info->countActiveActionSets; ++i)
            down.push_back({info->activeActionSets[i].actionSet, XR_NULL_PATH});
    XrActionsSyncInfo d = *info;
    d.countActiveActionSets = static_cast<uint32_t>(down.size());
    d.activeActionSets = down.data();
    const XrResult r = inst.next.SyncActions(session, &d);
    // XR_SESSION_NOT_FOCUSED (a success code) leaves every action inactive.
    sess->gaze_active = r == XR_SUCCESS && wants_gaze;
    return r;
}

// The session, instance and action behind an action-state call; `eyes` when it names the
// /user/eyes_ext subaction path the runtime does not know.
struct StateCall {
    SessionState* session = nullptr;
    const ActionInfo* action = nullptr;
    bool eyes = false;
    bool gaze = false;  // the action is bound to the gaze pose in this session
};

StateCall state_call(Registry& reg, XrSession session, const XrActionStateGetInfo* info) {
    StateCall c;
    c.session = reg.session(session);
    if (!c.session || !info) return c;
    auto it = reg.actions.find(info->action);
    if (it != reg.actions.end()) c.action = &it->second;
    c.eyes = info->subactionPath != XR_NULL_PATH &&
             info->subactionPath == c.session->instance->eyes_path;
    c.gaze = c.session->gaze_actions.count(info->action) != 0;
    return c;
}

template <typename State, typename Fn>
XrResult get_state(XrSession session, const XrActionStateGetInfo* info, State* state,
                   Fn NextDispatch::*fn) {
    Registry& reg = registry();
    std::shared_lock lock(reg.mu);
    const StateCall c = state_call(reg, session, info);
    if (!c.session) return XR_ERROR_HANDLE_INVALID;
    const Fn next = c.session->instance->next.*fn;
    if (!c.eyes) return next(session, info, state);
    if (c.action && !c.action->eyes_subaction) return XR_ERROR_PATH_UNSUPPORTED;
    XrActionStateGetInfo down = *info;
    down.subactionPath = XR_NULL_PATH;  // the runtime still checks the handles and the type
    const XrResult r = next(session, &down, state);
    if (XR_FAILED(r)) return r;
    // The eye gaze profile has no input of these types.
    void* chain = state->next;
    *state = State{state->type};
    state->next = chain;
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL state_boolean(XrSession s, const XrActionStateGetInfo* i,
                                             XrActionStateBoolean* st) {
    return get_state(s, i, st, &NextDispatch::GetActionStateBoolean);
}
XRAPI_ATTR XrResult XRAPI_CALL state_float(XrSession s, const XrActionStateGetInfo* i,
                                           XrActionStateFloat* st) {
    return get_state(s, i, st, &NextDispatch::GetActionStateFloat);
}
XRAPI_ATTR XrResult XRAPI_CALL state_vector2f(XrSession s, const XrActionStateGetInfo* i,
                                              XrActionStateVector2f* st) {
    return get_state(s, i, st, &NextDispatch::GetActionStateVector2f);
}

XRAPI_ATTR XrResult XRAPI_CALL state_pose(XrSession session, const XrActionStateGetInfo* info,
                                          XrActionStatePose* state) {
    Registry& reg = registry();
    std::shared_lock lock(reg.mu);
    const StateCall c = state_call(reg, session, info);
    if (!c.session) return XR_ERROR_HANDLE_INVALID;
    const auto next = c.session->instance->next.GetActionStatePose;
    if (!c.eyes && !c.gaze) return next(session, info, state);
    if (c.eyes && c.action && !c.action->eyes_subaction) return XR_ERROR_PATH_UNSUPPORTED;
    XrActionStateGetInfo down = *info;
    if (c.eyes) down.subactionPath = XR_NULL_PATH;
    const XrResult r = next(session, &down, state);
    if (XR_FAILED(r)) return r;
    const bool active = c.gaze && c.session->gaze_active;
    state->isActive = c.eyes ? active : (state->isActive || active);
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL create_action_space(XrSession session,
                                                   const XrActionSpaceCreateInfo* info,
                                                   XrSpace* space) {
    Registry& reg = registry();
    SessionState* sess = nullptr;
    const ActionInfo* action = nullptr;
    {
        std::shared_lock lock(reg.mu);
        sess = reg.session(session);
        if (info) {
            auto it = reg.actions.find(info->action);
            if (it != reg.actions.end()) action = &it->second;
        }
    }
    if (!sess) return XR_ERROR_HANDLE_INVALID;
    const auto next = sess->instance->next.CreateActionSpace;
    if (!info || info->type != XR_TYPE_ACTION_SPACE_CREATE_INFO) return next(session, info, space);
    XrActionSpaceCreateInfo down = *info;
    if (info->subactionPath != XR_NULL_PATH && info->subactionPath == sess->instance->eyes_path) {
        if (action && !action->eyes_subaction) return XR_ERROR_PATH_UNSUPPORTED;
        down.subactionPath = XR_NULL_PATH;
    }
    const XrResult r = next(session, &down, space);
    if (XR_SUCCEEDED(r) && action && action->type == XR_ACTION_TYPE_POSE_INPUT) {
        std::unique_lock lock(reg.mu);
        reg.action_spaces[*space] = {sess, info->action, from_xr(info->poseInActionSpace)};
    }
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL destroy_space(XrSpace space) {
    Registry& reg = registry();
    PFN_xrDestroySpace next = nullptr;
    {
        std::unique_lock lock(reg.mu);
        auto it = reg.action_spaces.find(space);
        if (it != reg.action_spaces.end()) {
            next = it->second.session->instance->next.DestroySpace;
            reg.action_spaces.erase(it);
        } else if (!reg.instances.empty()) {
            // A space the layer never looked at: the loader allows one instance at a time.
            next = reg.instances.begin()->second->next.DestroySpace;
        }
    }
    return next ? next(space) : XR_ERROR_HANDLE_INVALID;
}

XRAPI_ATTR XrResult XRAPI_CALL
enumerate_bound_sources(XrSession session, const XrBoundSourcesForActionEnumerateInfo* info,
                        uint32_t capacity, uint32_t* count, XrPath* sources) {
    Registry& reg = registry();
    std::shared_lock lock(reg.mu);
    SessionState* sess = reg.session(session);
    if (!sess) return XR_ERROR_HANDLE_INVALID;
    const auto next = sess->instance->next.EnumerateBoundSourcesForAction;
    if (!info || !count || !sess->gaze_actions.count(info->action))
        return next(session, info, capacity, count, sources);
    uint32_t below = 0;
    XrResult r = next(session, info, 0, &below, nullptr);
    if (XR_FAILED(r)) return r;
    *count = below + 1;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < below + 1 || !sources) return XR_ERROR_SIZE_INSUFFICIENT;
    r = next(session, info, capacity - 1, &below, sources);
    if (XR_FAILED(r)) return r;
    sources[below] = sess->instance->gaze_pose_path;
    *count = below + 1;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL current_interaction_profile(XrSession session, XrPath user_path,
                                                           XrInteractionProfileState* profile) {
    Registry& reg = registry();
    std::shared_lock lock(reg.mu);
    SessionState* sess = reg.session(session);
    if (!sess) return XR_ERROR_HANDLE_INVALID;
    if (user_path == XR_NULL_PATH || user_path != sess->instance->eyes_path)
        return sess->instance->next.GetCurrentInteractionProfile(session, user_path, profile);
    if (!profile || profile->type != XR_TYPE_INTERACTION_PROFILE_STATE)
        return XR_ERROR_VALIDATION_FAILURE;
    if (!sess->attached) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    profile->interactionProfile =
        sess->gaze_actions.empty() ? XR_NULL_PATH : sess->instance->profile_path;
    return XR_SUCCESS;
}

// The two-call idiom for a string.
XrResult write_string(const std::string& s, uint32_t capacity, uint32_t* count, char* buffer) {
    *count = static_cast<uint32_t>(s.size() + 1);
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < s.size() + 1 || !buffer) return XR_ERROR_SIZE_INSUFFICIENT;
    std::memcpy(buffer, s.c_str(), s.size() + 1);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL localized_name(XrSession session,
                                              const XrInputSourceLocalizedNameGetInfo* info,
                                              uint32_t capacity, uint32_t* count, char* buffer) {
    Registry& reg = registry();
    std::shared_lock lock(reg.mu);
    SessionState* sess = reg.session(session);
    if (!sess) return XR_ERROR_HANDLE_INVALID;
    const InstanceState& inst = *sess->instance;
    if (!info || !count || info->type != XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO ||
        (info->sourcePath != inst.gaze_pose_path && info->sourcePath != inst.gaze_path))
        return inst.next.GetInputSourceLocalizedName(session, info, capacity, count, buffer);
    if (info->whichComponents == 0) return XR_ERROR_VALIDATION_FAILURE;
    if (!sess->attached) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    std::string name;
    const auto add = [&](XrInputSourceLocalizedNameFlags bit, const char* part) {
        if (!(info->whichComponents & bit)) return;
        name += (name.empty() ? "" : " ");
        name += part;
    };
    add(XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT, "Eyes");
    add(XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT, "Eye Gaze Interaction");
    add(XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT, "Gaze Pose");
    return write_string(name, capacity, count, buffer);
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL layer_locate_space(XrSpace space, XrSpace base, XrTime time,
                                                  XrSpaceLocation* location);

PFN_xrVoidFunction intercept(const char* name) {
    static const std::pair<const char*, PFN_xrVoidFunction> kTable[] = {
        {"xrCreateActionSet", reinterpret_cast<PFN_xrVoidFunction>(create_action_set)},
        {"xrDestroyActionSet", reinterpret_cast<PFN_xrVoidFunction>(destroy_action_set)},
        {"xrCreateAction", reinterpret_cast<PFN_xrVoidFunction>(create_action)},
        {"xrDestroyAction", reinterpret_cast<PFN_xrVoidFunction>(destroy_action)},
        {"xrSuggestInteractionProfileBindings",
         reinterpret_cast<PFN_xrVoidFunction>(suggest_bindings)},
        {"xrAttachSessionActionSets", reinterpret_cast<PFN_xrVoidFunction>(attach_action_sets)},
        {"xrSyncActions", reinterpret_cast<PFN_xrVoidFunction>(sync_actions)},
        {"xrGetActionStateBoolean", reinterpret_cast<PFN_xrVoidFunction>(state_boolean)},
        {"xrGetActionStateFloat", reinterpret_cast<PFN_xrVoidFunction>(state_float)},
        {"xrGetActionStateVector2f", reinterpret_cast<PFN_xrVoidFunction>(state_vector2f)},
        {"xrGetActionStatePose", reinterpret_cast<PFN_xrVoidFunction>(state_pose)},
        {"xrCreateActionSpace", reinterpret_cast<PFN_xrVoidFunction>(create_action_space)},
        {"xrDestroySpace", reinterpret_cast<PFN_xrVoidFunction>(destroy_space)},
        {"xrLocateSpace", reinterpret_cast<PFN_xrVoidFunction>(layer_locate_space)},
        {"xrEnumerateBoundSourcesForAction",
         reinterpret_cast<PFN_xrVoidFunction>(enumerate_bound_sources)},
        {"xrGetCurrentInteractionProfile",
         reinterpret_cast<PFN_xrVoidFunction>(current_interaction_profile)},
        {"xrGetInputSourceLocalizedName", reinterpret_cast<PFN_xrVoidFunction>(localized_name)},
    };
    for (const auto& [n, f] : kTable)
        if (!std::strcmp(name, n)) return f;
    return nullptr;
}

}  // namespace fovea::openxr
