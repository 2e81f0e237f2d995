// Valid tracker descriptors for the report fuzzer (tests/fuzz/fuzz_hid_report.cpp), written with
// the same builder as the unit tests.
#pragma once

#include <vector>

#include "hid_builders.hpp"

namespace fovea::test {

inline std::vector<std::vector<uint8_t>> fuzz_descriptors() {
    constexpr int32_t kMin32 = -2147483647 - 1, kMax32 = 2147483647;
    std::vector<std::vector<uint8_t>> out;
    {  // numbered, 3 padding bytes, 64-bit timestamp as 8 bytes, gaze + both eyes, features
        DescriptorBuilder d;
        d.usage_page(0x12).usage(0x01).collection(1).usage(0x10).collection(2).report_id(0x10);
        d.logical_min(0).logical_max(255).report_size(8).report_count(3).input(kConstVarAbs);
        d.usage(0x20).report_count(8).input(kDataVarAbs);
        d.report_count(1).report_size(32).logical_min(kMin32).logical_max(kMax32);
        d.usage(0x24)
            .collection(0)
            .report_count(2)
            .usage(0x21)
            .usage(0x22)
            .input(kDataVarAbs)
            .end_collection();
        for (uint16_t eye : {0x25, 0x26})
            d.usage(eye)
                .collection(0)
                .report_count(3)
                .usage(0x21)
                .usage(0x22)
                .usage(0x23)
                .input(kDataVarAbs)
                .end_collection();
        d.end_collection();
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
        d.usage(0x13)
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
        d.end_collection();
        out.push_back(d.bytes);
    }
    {  // unnumbered, 12-bit gaze with physical range and null state, 20-bit timestamp
        DescriptorBuilder d;
        d.usage_page(0x12).usage(0x01).collection(1).usage(0x10).collection(0);
        d.logical_min(0)
            .logical_max(4094)
            .physical_min(0)
            .physical_max(530000)
            .report_size(12)
            .report_count(2)
            .usage(0x24)
            .collection(0)
            .usage(0x21)
            .usage(0x22)
            .input(kDataVarAbs | kNullState)
            .end_collection();
        d.report_size(4).report_count(1).input(kConstVarAbs);
        d.physical_min(0)
            .physical_max(0)
            .logical_min(0)
            .logical_max(0xFFFFF)
            .report_size(20)
            .usage(0x20)
            .input(kDataVarAbs);
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
        out.push_back(d.bytes);
    }
    {  // mouse + eye tracker (24-bit gaze) + head tracker (position, direction point, rotation)
        DescriptorBuilder d;
        d.usage_page(0x01)
            .usage(0x02)
            .collection(1)
            .report_id(1)
            .usage(0x30)
            .usage(0x31)
            .logical_min(-127)
            .logical_max(127)
            .report_size(8)
            .report_count(2)
            .input(kDataVarAbs | 0x04)
            .end_collection();
        d.usage_ext(0x12, 0x01)
            .collection(1)
            .usage_ext(0x12, 0x10)
            .collection(2)
            .report_id(2)
            .usage_page(0x12);
        d.logical_min(0).logical_max(0xFFFF).report_size(16).report_count(1).usage(0x20).input(
            kDataVarAbs);
        d.logical_min(-1000000)
            .logical_max(1000000)
            .report_size(24)
            .report_count(2)
            .usage(0x24)
            .collection(0)
            .usage(0x21)
            .usage(0x22)
            .input(kDataVarAbs)
            .end_collection();
        d.end_collection().end_collection();
        d.usage(0x02).collection(1).usage(0x10).collection(2).report_id(3);
        d.logical_min(kMin32).logical_max(kMax32).report_size(32).report_count(3);
        d.usage(0x27)
            .collection(0)
            .usage(0x21)
            .usage(0x22)
            .usage(0x23)
            .input(kDataVarAbs)
            .end_collection();
        d.usage(0x28)
            .collection(0)
            .usage(0x21)
            .usage(0x22)
            .usage(0x23)
            .input(kDataVarAbs)
            .end_collection();
        d.unit(0x12)
            .unit_exponent(-3)
            .logical_min(-3142)
            .logical_max(3142)
            .report_size(16)
            .report_count(3)
            .usage_min(0x29)
            .usage_max(0x2B)
            .input(kDataVarAbs);
        d.end_collection().end_collection();
        out.push_back(d.bytes);
    }
    return out;
}

}  // namespace fovea::test
