// xrLocateSpace with eye gaze action spaces on either side: the gaze pose at the app's XrTime
// (GazeSource, times through XR_KHR_convert_timespec_time) lives in the session's VIEW space,
// which the runtime locates; every other pair of spaces goes straight down.
#include "layer_state.hpp"
#include "xr_chain.hpp"

namespace fovea::openxr {
namespace {

constexpr XrSpaceLocationFlags kAllLocationBits =
    XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT |
    XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT;
constexpr XrSpaceLocationFlags kTrackedBits =
    XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT;

// The action space's gaze pose in the session's VIEW space at `time`.
GazePose gaze_pose(const SessionState& s, const ActionSpaceInfo& a, XrTime time) {
    GazePose g;
    const InstanceState& inst = *s.instance;
    if (!s.gaze_active || !inst.has_timespec || s.view_space == XR_NULL_HANDLE) return g;
    timespec ts{};
    if (XR_FAILED(inst.next.ConvertTimeToTimespecTimeKHR(inst.handle, time, &ts))) return g;
    const GazeEstimate e = s.gaze->at(int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec);
    if (!e.tracked()) return g;
    g.valid = true;
    g.pose = compose(Pose{look_rotation(e.direction), {0, 0, 0}}, a.pose_in_action);
    const timespec when{static_cast<time_t>(e.t_expressed_ns / 1'000'000'000),
                        static_cast<long>(e.t_expressed_ns % 1'000'000'000)};
    if (XR_FAILED(inst.next.ConvertTimespecTimeToTimeKHR(inst.handle, &when, &g.expressed)))
        g.expressed = 0;
    return g;
}

const ActionSpaceInfo* gaze_space(const Registry& reg, XrSpace space) {
    auto it = reg.action_spaces.find(space);
    if (it == reg.action_spaces.end()) return nullptr;
    const ActionSpaceInfo& a = it->second;
    return a.session->gaze_actions.count(a.action) ? &a : nullptr;
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL layer_locate_space(XrSpace space, XrSpace base, XrTime time,
                                                  XrSpaceLocation* location) {
    Registry& reg = registry();
    std::shared_lock lock(reg.mu);
    const ActionSpaceInfo* a = gaze_space(reg, space);
    const ActionSpaceInfo* b = gaze_space(reg, base);
    if (!a && !b) {
        // The loader allows one instance at a time: its runtime owns every space.
        if (reg.instances.empty()) return XR_ERROR_HANDLE_INVALID;
        const InstanceState& inst = *reg.instances.begin()->second;
        if (!location || inst.runtime_has_gaze)
            return inst.next.LocateSpace(space, base, time, location);
        auto* sample_time =
            find_in_chain<XrEyeGazeSampleTimeEXT>(location->next, XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT);
        if (!sample_time) return inst.next.LocateSpace(space, base, time, location);
        ChainCut cut(location, XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT);
        const XrResult r = inst.next.LocateSpace(space, base, time, location);
        sample_time->time = 0;  // not an eye gaze space: no sample time
        return r;
    }
    if (!location || location->type != XR_TYPE_SPACE_LOCATION) return XR_ERROR_VALIDATION_FAILURE;
    if (time <= 0) return XR_ERROR_TIME_INVALID;
    const SessionState& sess = *(a ? a : b)->session;
    if (a && b && a->session != b->session) return XR_ERROR_VALIDATION_FAILURE;

    GazePose ga, gb;
    XrSpace ra = space, rb = base;
    if (a) {
        ga = gaze_pose(sess, *a, time);
        ra = sess.view_space;
    }
    if (b) {
        gb = gaze_pose(sess, *b, time);
        rb = sess.view_space;
    }
    XrSpaceLocation inner{XR_TYPE_SPACE_LOCATION};
    if (ra == rb) {
        inner.locationFlags = kAllLocationBits;
        inner.pose.orientation.w = 1.0f;
    } else {
        const XrResult r = sess.instance->next.LocateSpace(ra, rb, time, &inner);
        if (XR_FAILED(r)) return r;
    }
    const bool valid = (!a || ga.valid) && (!b || gb.valid);
    XrSpaceLocationFlags flags = valid ? inner.locationFlags : 0;
    // The extension wants position and orientation both tracked or neither.
    if ((flags & kTrackedBits) != kTrackedBits) flags &= ~kTrackedBits;
    location->locationFlags = flags;
    if (valid) {
        const Pose result = compose(compose(inverse(b ? gb.pose : Pose{}), from_xr(inner.pose)),
                                    a ? ga.pose : Pose{});
        location->pose = to_xr(result);
    } else {
        location->pose = XrPosef{{0, 0, 0, 1}, {0, 0, 0}};
    }
    if (auto* v = find_in_chain<XrSpaceVelocity>(location->next, XR_TYPE_SPACE_VELOCITY))
        v->velocityFlags = 0;
    if (auto* t =
            find_in_chain<XrEyeGazeSampleTimeEXT>(location->next, XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT))
        t->time = !valid ? 0 : a ? ga.expressed : gb.expressed;
    return XR_SUCCESS;
}

}  // namespace fovea::openxr
