#include "hid/tracker.hpp"

#include <cmath>
#include <limits>

namespace fovea::drivers::hid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 57.29577951308232;

int nibble(uint32_t unit, int i) {
    const int n = static_cast<int>((unit >> (4 * i)) & 0xF);
    return n >= 8 ? n - 16 : n;
}

// HID unit codes (HID 1.11 §6.2.2.7): nibble 0 is the system, nibble 1 the length exponent,
// nibble 3 the time exponent. to_physical() already applied 10^unit_exponent.
constexpr int kSystemSiLinear = 1, kSystemSiRotation = 2, kSystemEnglishLinear = 3,
              kSystemEnglishRotation = 4;

bool only_nibble(uint32_t unit, int index, int exponent) {
    for (int i = 1; i < 8; ++i)
        if (nibble(unit, i) != (i == index ? exponent : 0)) return false;
    return true;
}

// Physical value -> micrometres. Without a unit HUTRR74 positions are micrometres.
double length_scale_um(const Field& f) {
    if (f.unit == 0) return 1.0;
    if (only_nibble(f.unit, 1, 1)) {
        if ((f.unit & 0xF) == kSystemSiLinear) return 1e4;         // centimetre
        if ((f.unit & 0xF) == kSystemEnglishLinear) return 25400;  // inch
    }
    return 1.0;  // a unit we do not know: trust the spec's default
}

// Physical value -> degrees. Without a unit rotations are taken as degrees.
double angle_scale_deg(const Field& f) {
    if (f.unit == 0) return 1.0;
    if (only_nibble(f.unit, 1, 1)) {
        if ((f.unit & 0xF) == kSystemSiRotation) return kRadToDeg;
        if ((f.unit & 0xF) == kSystemEnglishRotation) return 1.0;
    }
    return 1.0;
}

double timestamp_tick_hz(const Field& f) {
    const int system = static_cast<int>(f.unit & 0xF);
    if (system != 0 && only_nibble(f.unit, 3, 1)) return std::pow(10.0, -f.unit_exponent);
    return 1e6;
}

bool usable(const Field& f) {
    return f.is_variable() && f.bit_size > 0 && f.bit_size <= 64 &&
           usage_page(f.usage) == usage::kPage;
}

int axis_of(uint16_t id) {
    switch (id) {
        case usage::kPositionX: return 0;
        case usage::kPositionY: return 1;
        case usage::kPositionZ: return 2;
        default: return -1;
    }
}

// The channel a position axis belongs to, from the nearest enclosing point collection.
int position_channel(const ReportDescriptor& desc, const Field& f) {
    const int axis = axis_of(usage_id(f.usage));
    if (axis < 0) return -1;
    for (int c = f.collection; c >= 0; c = desc.collections[static_cast<std::size_t>(c)].parent) {
        const uint32_t cu = desc.collections[static_cast<std::size_t>(c)].usage;
        if (usage_page(cu) != usage::kPage) continue;
        switch (usage_id(cu)) {
            case usage::kGazePoint: return axis < 2 ? kGazeX + axis : -1;
            case usage::kLeftEyePosition: return kLeftEyeX + axis;
            case usage::kRightEyePosition: return kRightEyeX + axis;
            case usage::kHeadPosition: return kHeadX + axis;
            case usage::kHeadDirectionPoint: return kHeadDirX + axis;
            default: break;
        }
    }
    return -1;
}

bool fits(const Field& f, std::span<const uint8_t> payload) {
    return uint64_t{f.bit_offset} + f.bit_size <= uint64_t{payload.size()} * 8;
}

}  // namespace

const char* to_string(ConfigurationStatus s) {
    switch (s) {
        case ConfigurationStatus::kReady: return "ready";
        case ConfigurationStatus::kConfiguring: return "configuring";
        case ConfigurationStatus::kScreenSetupNeeded: return "screen setup needed";
        case ConfigurationStatus::kUserCalibrationNeeded: return "user calibration needed";
        default: return "unknown";
    }
}

Result<TrackerLayout> locate_tracker(const ReportDescriptor& desc) {
    TrackerLayout out;
    out.numbered = desc.numbered;
    const uint32_t eye_app = make_usage(usage::kPage, usage::kEyeTracker);
    const uint32_t head_app = make_usage(usage::kPage, usage::kHeadTracker);
    for (const auto& c : desc.collections) {
        if (c.type != 1) continue;
        out.eye_tracker |= c.usage == eye_app;
        out.head_tracker |= c.usage == head_app;
    }
    if (!out.eye_tracker && !out.head_tracker)
        return make_error(
            "no Eye Tracker (0x12:0x01) or Head Tracker (0x12:0x02) application "
            "collection in the report descriptor");

    auto layout_for = [&](uint8_t id, bool head) -> TrackingReportLayout& {
        for (auto& t : out.tracking)
            if (t.report_id == id) return t;
        TrackingReportLayout t;
        t.report_id = id;
        t.head_tracker = head;
        t.channel.fill(-1);
        t.scale.fill(1.0);
        if (const Report* r = desc.find_report(ReportType::kInput, id))
            t.wire_bytes = r->wire_bytes(desc.numbered);
        out.tracking.push_back(t);
        return out.tracking.back();
    };

    for (std::size_t i = 0; i < desc.fields.size(); ++i) {
        const Field& f = desc.fields[i];
        if (!usable(f)) continue;
        const bool in_eye = desc.within(f.collection, eye_app);
        const bool in_head = desc.within(f.collection, head_app);
        if (!in_eye && !in_head) continue;
        const int index = static_cast<int>(i);
        const uint16_t id = usage_id(f.usage);
        if (f.type == ReportType::kInput) {
            int channel = -1;
            double scale = 1.0;
            if (id == usage::kSensorTimestamp) {
                auto& t = layout_for(f.report_id, in_head && !in_eye);
                if (t.timestamp.empty()) t.timestamp_tick_hz = timestamp_tick_hz(f);
                t.timestamp.push_back(index);
                continue;
            }
            if (id >= usage::kRotationX && id <= usage::kRotationZ) {
                channel = kRotX + (id - usage::kRotationX);
                scale = angle_scale_deg(f);
            } else {
                channel = position_channel(desc, f);
                scale = length_scale_um(f);
            }
            if (channel < 0) continue;
            auto& t = layout_for(f.report_id, in_head && !in_eye);
            if (t.channel[static_cast<std::size_t>(channel)] >= 0) continue;  // first one wins
            t.channel[static_cast<std::size_t>(channel)] = index;
            t.scale[static_cast<std::size_t>(channel)] = scale;
        } else if (f.type == ReportType::kFeature) {
            const bool known =
                (id >= usage::kTrackerQuality && id <= usage::kMaximumScreenPlaneHeight) ||
                (id >= usage::kDisplayManufacturerId && id <= usage::kCalibratedScreenHeight) ||
                id == usage::kSamplingFrequency || id == usage::kConfigurationStatus;
            if (!known) continue;
            const bool distance =
                (id >= usage::kMinimumTrackingDistance && id <= usage::kMaximumScreenPlaneHeight) ||
                id == usage::kCalibratedScreenWidth || id == usage::kCalibratedScreenHeight;
            out.features.items.push_back({id, index, distance ? length_scale_um(f) : 1.0});
            bool seen = false;
            for (uint8_t r : out.features.report_ids) seen |= r == f.report_id;
            if (!seen) out.features.report_ids.push_back(f.report_id);
        }
    }
    if (out.tracking.empty())
        return make_error(
            "no Tracking Data input fields (timestamp, gaze point, eye or head "
            "position, rotation) on usage page 0x12");
    for (const auto& t : out.tracking)
        out.max_input_bytes = std::max(out.max_input_bytes, t.wire_bytes);
    return out;
}

DecodeStatus decode_tracking(const ReportDescriptor& desc, const TrackerLayout& layout,
                             std::span<const uint8_t> report, TrackingSample& out) {
    uint8_t id = 0;
    std::span<const uint8_t> payload = report;
    if (layout.numbered) {
        if (report.empty()) return DecodeStatus::kTooShort;
        id = report[0];
        payload = report.subspan(1);
    }
    const TrackingReportLayout* t = nullptr;
    for (const auto& candidate : layout.tracking)
        if (candidate.report_id == id) t = &candidate;
    if (t == nullptr) return DecodeStatus::kUnknownReport;
    if (report.size() < t->wire_bytes) return DecodeStatus::kTooShort;

    out = TrackingSample{};
    out.report_id = id;
    out.head_tracker = t->head_tracker;
    if (!t->timestamp.empty()) {
        uint64_t stamp = 0;
        uint32_t shift = 0;
        for (int fi : t->timestamp) {
            const Field& f = desc.fields[static_cast<std::size_t>(fi)];
            if (shift >= 64 || !fits(f, payload)) break;
            stamp |= extract_bits(payload, f.bit_offset, f.bit_size) << shift;
            shift += f.bit_size;
        }
        out.timestamp = stamp;
    }
    std::array<double, kChannelCount> v;
    for (int c = 0; c < kChannelCount; ++c) {
        v[static_cast<std::size_t>(c)] = kNaN;
        const int fi = t->channel[static_cast<std::size_t>(c)];
        if (fi < 0) continue;
        const Field& f = desc.fields[static_cast<std::size_t>(fi)];
        if (!fits(f, payload)) continue;
        const int64_t logical = to_logical(f, extract_bits(payload, f.bit_offset, f.bit_size));
        if (!in_logical_range(f, logical)) continue;  // HID null: no data for this channel
        v[static_cast<std::size_t>(c)] =
            to_physical(f, logical) * t->scale[static_cast<std::size_t>(c)];
    }
    auto has = [&](int c) { return t->channel[static_cast<std::size_t>(c)] >= 0; };
    auto ok = [&](int c) { return !std::isnan(v[static_cast<std::size_t>(c)]); };
    // A point needs X and Y; Z is optional but, when declared, must not be null.
    auto point3 = [&](int x) -> std::optional<std::array<double, 3>> {
        if (!ok(x) || !ok(x + 1) || (has(x + 2) && !ok(x + 2))) return std::nullopt;
        return std::array<double, 3>{v[static_cast<std::size_t>(x)],
                                     v[static_cast<std::size_t>(x + 1)],
                                     v[static_cast<std::size_t>(x + 2)]};
    };
    if (ok(kGazeX) && ok(kGazeY)) out.gaze_um = std::array<double, 2>{v[kGazeX], v[kGazeY]};
    out.left_eye_um = point3(kLeftEyeX);
    out.right_eye_um = point3(kRightEyeX);
    out.head_position_um = point3(kHeadX);
    out.head_direction_point_um = point3(kHeadDirX);
    if (has(kRotX) || has(kRotY) || has(kRotZ)) {
        bool all = true;
        std::array<double, 3> r{0, 0, 0};
        for (int a = 0; a < 3; ++a) {
            if (!has(kRotX + a)) continue;
            if (!ok(kRotX + a))
                all = false;
            else
                r[static_cast<std::size_t>(a)] = v[static_cast<std::size_t>(kRotX + a)];
        }
        if (all) out.rotation_deg = r;
    }
    return DecodeStatus::kOk;
}

int decode_feature(const ReportDescriptor& desc, const TrackerLayout& layout,
                   std::span<const uint8_t> report, TrackerInfo& info) {
    uint8_t id = 0;
    std::span<const uint8_t> payload = report;
    if (layout.numbered) {
        if (report.empty()) return 0;
        id = report[0];
        payload = report.subspan(1);
    }
    int taken = 0;
    for (const auto& item : layout.features.items) {
        const Field& f = desc.fields[static_cast<std::size_t>(item.field)];
        if (f.report_id != id || !fits(f, payload)) continue;
        const int64_t logical = to_logical(f, extract_bits(payload, f.bit_offset, f.bit_size));
        if (!in_logical_range(f, logical)) continue;
        const double value = to_physical(f, logical) * item.scale;
        const auto as_u32 = static_cast<uint32_t>(logical);
        switch (item.usage) {
            case usage::kTrackerQuality: info.tracker_quality = as_u32; break;
            case usage::kMinimumTrackingDistance: info.min_tracking_distance_um = value; break;
            case usage::kOptimumTrackingDistance: info.optimum_tracking_distance_um = value; break;
            case usage::kMaximumTrackingDistance: info.max_tracking_distance_um = value; break;
            case usage::kMaximumScreenPlaneWidth: info.max_screen_width_um = value; break;
            case usage::kMaximumScreenPlaneHeight: info.max_screen_height_um = value; break;
            case usage::kDisplayManufacturerId: info.display_manufacturer_id = as_u32; break;
            case usage::kDisplayProductId: info.display_product_id = as_u32; break;
            case usage::kDisplaySerialNumber: info.display_serial_number = as_u32; break;
            case usage::kDisplayManufacturerDate: info.display_manufacturer_date = as_u32; break;
            case usage::kCalibratedScreenWidth: info.calibrated_screen_width_um = value; break;
            case usage::kCalibratedScreenHeight: info.calibrated_screen_height_um = value; break;
            case usage::kSamplingFrequency: info.sampling_frequency_hz = value; break;
            case usage::kConfigurationStatus:
                info.configuration_status = logical >= 1 && logical <= 4
                                                ? static_cast<ConfigurationStatus>(logical)
                                                : ConfigurationStatus::kUnknown;
                break;
            default: continue;
        }
        ++taken;
    }
    return taken;
}

std::array<double, 2> gaze_to_normalized(const std::array<double, 2>& gaze_um,
                                         double screen_width_um, double screen_height_um) {
    if (!(screen_width_um > 0) || !(screen_height_um > 0)) return {kNaN, kNaN};
    return {gaze_um[0] / screen_width_um, gaze_um[1] / screen_height_um};
}

}  // namespace fovea::drivers::hid
