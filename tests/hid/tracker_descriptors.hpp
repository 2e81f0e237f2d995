// Page 0x12 descriptor pieces and whole tracker descriptors shared by the unit tests
// (tracker_test.cpp), the benchmark (hid_bench.cpp) and the report fuzzer
// (tests/fuzz/fuzz_hid_report.cpp), written with the item builder of hid_builders.hpp. Bit offsets
// in the comments are those of the report that the piece adds to (after the report ID byte).
#pragma once

#include <cstdint>
#include <vector>

#include "hid_builders.hpp"

namespace fovea::test {

inline constexpr int32_t kMin32 = -2147483647 - 1;
inline constexpr int32_t kMax32 = 2147483647;

// Gaze point (0x24): a Physical collection of X and Y, with the report size, count and range set
// before it.
inline DescriptorBuilder& gaze_point(DescriptorBuilder& d, uint32_t flags = kDataVarAbs) {
    return d.usage(0x24).collection(0).usage(0x21).usage(0x22).input(flags).end_collection();
}

// A Physical collection `usage` (0x25/0x26 eye position, 0x27 head position, 0x28 head direction
// point) of X, Y and Z, with the report size, count and range set before it.
inline DescriptorBuilder& xyz_point(DescriptorBuilder& d, uint16_t usage,
                                    uint32_t flags = kDataVarAbs) {
    return d.usage(usage)
        .collection(0)
        .usage(0x21)
        .usage(0x22)
        .usage(0x23)
        .input(flags)
        .end_collection();
}

// Report 0x10 Tracking Data of the Windows reference eye tracker (HUTRR74): 3 padding bytes, a
// 64-bit timestamp declared as 8 one-byte fields, gaze point and both eye positions as 32-bit
// signed micrometres. Opened and closed here, inside an Eye Tracker application collection.
inline DescriptorBuilder& reference_tracking_data(DescriptorBuilder& d) {
    d.usage(0x10).collection(2).report_id(0x10);
    d.logical_min(0).logical_max(255).report_size(8).report_count(3).input(kConstVarAbs);  // 0..23
    d.usage(0x20).report_count(8).input(kDataVarAbs);                                      // 24..87
    d.report_count(1).report_size(32).logical_min(kMin32).logical_max(kMax32);
    d.usage(0x24)
        .collection(0)
        .report_count(2)
        .usage(0x21)
        .usage(0x22)
        .input(kDataVarAbs)
        .end_collection();             // X 88, Y 120
    for (uint16_t eye : {0x25, 0x26})  // left 152, 184, 216; right 248, 280, 312
        d.usage(eye)
            .collection(0)
            .report_count(3)
            .usage(0x21)
            .usage(0x22)
            .usage(0x23)
            .input(kDataVarAbs)
            .end_collection();
    return d.end_collection();
}

// Status feature report 0x13: configuration status (8 bits, 0..4) at 0, sampling frequency
// (16 bits) at 8.
inline DescriptorBuilder& status_feature(DescriptorBuilder& d) {
    return d.usage(0x13)
        .collection(2)
        .report_id(0x13)
        .report_size(8)
        .report_count(1)
        .logical_min(0)
        .logical_max(4)
        .usage(0x301)
        .feature(kDataVarAbs)
        .report_size(16)
        .logical_max(0x7FFF)
        .usage(0x300)
        .feature(kDataVarAbs)
        .end_collection();
}

// Generic Desktop X and Y of a mouse: 8-bit signed, relative.
inline DescriptorBuilder& mouse_xy(DescriptorBuilder& d) {
    return d.usage(0x30)
        .usage(0x31)
        .logical_min(-127)
        .logical_max(127)
        .report_size(8)
        .report_count(2)
        .input(kDataVarAbs | 0x04);
}

// Head rotation: three 16-bit fields of radians x 10^-3 (-pi..pi) from Rotation X to Rotation Z.
inline DescriptorBuilder& head_rotation_mrad(DescriptorBuilder& d) {
    return d.unit(0x12)
        .unit_exponent(-3)
        .logical_min(-3142)
        .logical_max(3142)
        .report_size(16)
        .report_count(3)
        .usage_min(0x29)
        .usage_max(0x2B)
        .input(kDataVarAbs);
}

// No report IDs, 12-bit gaze with a physical range (0..4094 -> 0..530000 um) and a null state, 4
// bits of padding, a 20-bit timestamp; calibrated size in an unnumbered feature.
inline DescriptorBuilder unnumbered_packed_descriptor() {
    DescriptorBuilder d;
    d.usage_page(0x12).usage(0x01).collection(1);
    d.usage(0x10).collection(0);
    d.logical_min(0)
        .logical_max(4094)
        .physical_min(0)
        .physical_max(530000)
        .report_size(12)
        .report_count(2);
    gaze_point(d, kDataVarAbs | kNullState);               // 0, 12
    d.report_size(4).report_count(1).input(kConstVarAbs);  // 24..27
    d.physical_min(0)
        .physical_max(0)
        .logical_min(0)
        .logical_max(0xFFFFF)
        .report_size(20)
        .usage(0x20)
        .input(kDataVarAbs);  // 28..47
    d.end_collection();
    d.usage(0x12)
        .collection(2)
        .logical_min(0)
        .logical_max(kMax32)
        .report_size(32)
        .report_count(2)
        .usage(0x204)
        .usage(0x205)
        .feature(kDataVarAbs)
        .end_collection();
    d.end_collection();
    return d;
}

// Valid tracker descriptors for the report fuzzer.
inline std::vector<std::vector<uint8_t>> fuzz_descriptors() {
    std::vector<std::vector<uint8_t>> out;
    {  // numbered, 3 padding bytes, 64-bit timestamp as 8 bytes, gaze + both eyes, features
        DescriptorBuilder d;
        d.usage_page(0x12).usage(0x01).collection(1);
        reference_tracking_data(d);
        d.usage(0x12)
            .collection(2)
            .report_id(0x12)
            .report_size(32)
            .report_count(2)
            .logical_min(0)
            .logical_max(kMax32)
            .usage(0x204)
            .usage(0x205)
            .feature(kDataVarAbs)
            .end_collection();
        status_feature(d);
        d.end_collection();
        out.push_back(d.bytes);
    }
    // unnumbered, 12-bit gaze with physical range and null state, 20-bit timestamp
    out.push_back(unnumbered_packed_descriptor().bytes);
    {  // mouse + eye tracker (24-bit gaze) + head tracker (position, direction point, rotation)
        DescriptorBuilder d;
        d.usage_page(0x01).usage(0x02).collection(1).report_id(1);
        mouse_xy(d).end_collection();
        d.usage_ext(0x12, 0x01)
            .collection(1)
            .usage_ext(0x12, 0x10)
            .collection(2)
            .report_id(2)
            .usage_page(0x12);
        d.logical_min(0).logical_max(0xFFFF).report_size(16).report_count(1).usage(0x20).input(
            kDataVarAbs);
        d.logical_min(-1000000).logical_max(1000000).report_size(24).report_count(2);
        gaze_point(d);
        d.end_collection().end_collection();
        d.usage(0x02).collection(1).usage(0x10).collection(2).report_id(3);
        d.logical_min(kMin32).logical_max(kMax32).report_size(32).report_count(3);
        xyz_point(d, 0x27);
        xyz_point(d, 0x28);
        head_rotation_mrad(d);
        d.end_collection().end_collection();
        out.push_back(d.bytes);
    }
    return out;
}

}  // namespace fovea::test
