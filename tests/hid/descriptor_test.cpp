// The general HID report-descriptor parser: items, globals, locals, errors, bit extraction.
#include <gtest/gtest.h>

#include "hid/descriptor.hpp"
#include "hid_builders.hpp"

using namespace fovea::drivers::hid;
using fovea::test::DescriptorBuilder;
using fovea::test::kConstVarAbs;
using fovea::test::kDataArray;
using fovea::test::kDataVarAbs;

namespace {

ReportDescriptor parse_ok(const DescriptorBuilder& d) {
    auto r = parse_descriptor(d.bytes);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::move(*r) : ReportDescriptor{};
}

std::string parse_error(const DescriptorBuilder& d) {
    auto r = parse_descriptor(d.bytes);
    EXPECT_FALSE(r.ok());
    return r.ok() ? "" : r.error().message;
}

}  // namespace

TEST(HidDescriptor, LogicalMaxByteIsUnsignedWhenMinimumIsNonNegative) {
    DescriptorBuilder d;
    d.usage_page(0xFF00)
        .usage(1)
        .logical_min(0)
        .sized(0x24, 0xFF, 1)
        .report_size(8)
        .report_count(1)
        .input(kDataVarAbs);
    auto desc = parse_ok(d);
    ASSERT_EQ(desc.fields.size(), 1u);
    EXPECT_EQ(desc.fields[0].logical_max, 255);
    EXPECT_FALSE(desc.fields[0].is_signed());
}

TEST(HidDescriptor, LogicalRangeIsSignedWhenMinimumIsNegative) {
    DescriptorBuilder d;
    d.usage_page(0xFF00)
        .usage(1)
        .sized(0x14, 0x80, 1)
        .sized(0x24, 0x7F, 1)
        .report_size(8)
        .report_count(1)
        .input(kDataVarAbs);
    auto desc = parse_ok(d);
    ASSERT_EQ(desc.fields.size(), 1u);
    EXPECT_EQ(desc.fields[0].logical_min, -128);
    EXPECT_EQ(desc.fields[0].logical_max, 127);
    const std::vector<uint8_t> payload{0xFE};
    EXPECT_EQ(to_logical(desc.fields[0], extract_bits(payload, 0, 8)), -2);
}

TEST(HidDescriptor, FourByteLogicalMaximumAboveInt32IsKept) {
    DescriptorBuilder d;
    d.usage_page(0xFF00)
        .usage(1)
        .logical_min(0)
        .sized(0x24, 0xFFFFFFFF, 4)
        .report_size(32)
        .report_count(1)
        .input(kDataVarAbs);
    auto desc = parse_ok(d);
    EXPECT_EQ(desc.fields.at(0).logical_max, 0xFFFFFFFFll);
}

TEST(HidDescriptor, UnitExponentReadsNibbleAndWholeByteForms) {
    DescriptorBuilder a;
    a.usage_page(0xFF00)
        .usage(1)
        .sized(0x54, 0x0C, 1)
        .report_size(8)
        .report_count(1)
        .input(kDataVarAbs);
    EXPECT_EQ(parse_ok(a).fields.at(0).unit_exponent, -4);
    DescriptorBuilder b;
    b.usage_page(0xFF00)
        .usage(1)
        .sized(0x54, 0xFC, 1)
        .report_size(8)
        .report_count(1)
        .input(kDataVarAbs);
    EXPECT_EQ(parse_ok(b).fields.at(0).unit_exponent, -4);
    DescriptorBuilder c;
    c.usage_page(0xFF00)
        .usage(1)
        .sized(0x54, 0x03, 1)
        .report_size(8)
        .report_count(1)
        .input(kDataVarAbs);
    EXPECT_EQ(parse_ok(c).fields.at(0).unit_exponent, 3);
}

TEST(HidDescriptor, UsageRangeExpandsOverVariablesAndLastUsageRepeats) {
    DescriptorBuilder d;
    d.usage_page(0x09)
        .usage_min(1)
        .usage_max(3)
        .logical_min(0)
        .logical_max(1)
        .report_size(1)
        .report_count(3)
        .input(kDataVarAbs);
    d.usage_page(0xFF00).usage(0x10).report_size(4).report_count(3).input(kDataVarAbs);
    auto desc = parse_ok(d);
    ASSERT_EQ(desc.fields.size(), 6u);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(desc.fields[i].usage, make_usage(0x09, static_cast<uint16_t>(i + 1)));
        EXPECT_EQ(desc.fields[i].bit_offset, static_cast<uint32_t>(i));
    }
    for (int i = 3; i < 6; ++i) {
        EXPECT_EQ(desc.fields[i].usage, make_usage(0xFF00, 0x10));
        EXPECT_EQ(desc.fields[i].bit_offset, 3u + 4u * static_cast<uint32_t>(i - 3));
    }
    EXPECT_EQ(desc.reports.at(0).bit_length, 15u);
}

TEST(HidDescriptor, ArrayKeepsItsUsageRangesAndCount) {
    DescriptorBuilder d;
    d.usage_page(0x07)
        .usage_min(0)
        .usage_max(101)
        .logical_min(0)
        .logical_max(101)
        .report_size(8)
        .report_count(6)
        .input(kDataArray);
    auto desc = parse_ok(d);
    ASSERT_EQ(desc.fields.size(), 1u);
    EXPECT_FALSE(desc.fields[0].is_variable());
    EXPECT_EQ(desc.fields[0].count, 6u);
    ASSERT_EQ(desc.fields[0].array_usages.size(), 1u);
    EXPECT_EQ(desc.fields[0].array_usages[0].max, make_usage(0x07, 101));
    EXPECT_EQ(desc.reports.at(0).bit_length, 48u);
}

TEST(HidDescriptor, PushPopRestoresGlobalState) {
    DescriptorBuilder d;
    d.usage_page(0xFF00)
        .report_size(8)
        .report_count(1)
        .logical_min(0)
        .logical_max(100)
        .push()
        .report_size(16)
        .usage_page(0xFF01)
        .logical_max(1000)
        .usage(1)
        .input(kDataVarAbs)
        .pop()
        .usage(2)
        .input(kDataVarAbs);
    auto desc = parse_ok(d);
    ASSERT_EQ(desc.fields.size(), 2u);
    EXPECT_EQ(desc.fields[0].bit_size, 16u);
    EXPECT_EQ(desc.fields[0].usage, make_usage(0xFF01, 1));
    EXPECT_EQ(desc.fields[1].bit_size, 8u);
    EXPECT_EQ(desc.fields[1].usage, make_usage(0xFF00, 2));
    EXPECT_EQ(desc.fields[1].logical_max, 100);
    EXPECT_EQ(desc.fields[1].bit_offset, 16u);
}

TEST(HidDescriptor, ReportIdsSplitReportsPerTypeAndId) {
    DescriptorBuilder d;
    d.usage_page(0xFF00)
        .report_size(8)
        .report_count(2)
        .report_id(1)
        .usage(1)
        .input(kDataVarAbs)
        .report_id(2)
        .report_count(3)
        .usage(2)
        .input(kDataVarAbs)
        .usage(3)
        .feature(kDataVarAbs)
        .report_id(1)
        .report_count(1)
        .usage(4)
        .input(kDataVarAbs);
    auto desc = parse_ok(d);
    EXPECT_TRUE(desc.numbered);
    ASSERT_NE(desc.find_report(ReportType::kInput, 1), nullptr);
    EXPECT_EQ(desc.find_report(ReportType::kInput, 1)->bit_length, 24u);
    EXPECT_EQ(desc.find_report(ReportType::kInput, 1)->wire_bytes(true), 4u);
    EXPECT_EQ(desc.find_report(ReportType::kInput, 2)->bit_length, 24u);
    EXPECT_EQ(desc.find_report(ReportType::kFeature, 2)->bit_length, 24u);
    EXPECT_EQ(desc.fields.back().bit_offset, 16u);  // appended after report 1's first item
}

TEST(HidDescriptor, ExtendedUsageCarriesItsOwnPage) {
    DescriptorBuilder d;
    d.usage_page(0x01).usage_ext(0x12, 0x24).report_size(8).report_count(1).input(kDataVarAbs);
    EXPECT_EQ(parse_ok(d).fields.at(0).usage, make_usage(0x12, 0x24));
}

TEST(HidDescriptor, ShortUsageTakesThePageInEffectAtTheMainItem) {
    DescriptorBuilder d;
    d.usage(0x24).usage_page(0x12).report_size(8).report_count(1).input(kDataVarAbs);
    EXPECT_EQ(parse_ok(d).fields.at(0).usage, make_usage(0x12, 0x24));
}

TEST(HidDescriptor, DelimitedSetUsesItsFirstUsage) {
    DescriptorBuilder d;
    d.usage_page(0xFF00)
        .delimiter(true)
        .usage(7)
        .usage(8)
        .delimiter(false)
        .report_size(8)
        .report_count(1)
        .input(kDataVarAbs);
    EXPECT_EQ(parse_ok(d).fields.at(0).usage, make_usage(0xFF00, 7));
}

TEST(HidDescriptor, CollectionsNestAndFieldsKnowTheirCollection) {
    DescriptorBuilder d;
    d.usage_page(0x12)
        .usage(0x01)
        .collection(1)
        .usage(0x10)
        .collection(2)
        .usage(0x24)
        .collection(0)
        .usage(0x21)
        .report_size(8)
        .report_count(1)
        .input(kDataVarAbs)
        .end_collection()
        .end_collection()
        .end_collection();
    auto desc = parse_ok(d);
    ASSERT_EQ(desc.collections.size(), 3u);
    EXPECT_EQ(desc.collections[2].parent, 1);
    EXPECT_EQ(desc.collections[1].parent, 0);
    EXPECT_EQ(desc.fields.at(0).collection, 2);
    EXPECT_TRUE(desc.within(2, make_usage(0x12, 0x01)));
    EXPECT_FALSE(desc.within(0, make_usage(0x12, 0x24)));
}

TEST(HidDescriptor, LongItemsAreSkipped) {
    DescriptorBuilder d;
    d.usage_page(0xFF00)
        .long_item(0xF0, {1, 2, 3, 4, 5})
        .usage(1)
        .report_size(8)
        .report_count(1)
        .input(kDataVarAbs);
    EXPECT_EQ(parse_ok(d).fields.size(), 1u);
}

TEST(HidDescriptor, ConstantPaddingWithoutUsageAddsBitsButNoField) {
    DescriptorBuilder d;
    d.usage_page(0xFF00)
        .report_size(5)
        .report_count(1)
        .input(kConstVarAbs)
        .usage(1)
        .report_size(3)
        .input(kDataVarAbs);
    auto desc = parse_ok(d);
    ASSERT_EQ(desc.fields.size(), 1u);
    EXPECT_EQ(desc.fields[0].bit_offset, 5u);
}

TEST(HidDescriptor, RejectsMalformedDescriptorsWithTheReason) {
    EXPECT_NE(parse_error(DescriptorBuilder{}).find("empty"), std::string::npos);
    DescriptorBuilder truncated;
    truncated.raw({0x05, 0x12, 0x26, 0xFF});  // Logical Maximum announces 2 bytes, has 1
    EXPECT_NE(parse_error(truncated).find("truncated item data at byte 2"), std::string::npos);
    DescriptorBuilder pop;
    pop.pop();
    EXPECT_NE(parse_error(pop).find("Pop without Push"), std::string::npos);
    DescriptorBuilder end;
    end.end_collection();
    EXPECT_NE(parse_error(end).find("End Collection without Collection"), std::string::npos);
    DescriptorBuilder open;
    open.usage_page(1).usage(2).collection(1);
    EXPECT_NE(parse_error(open).find("left open"), std::string::npos);
    DescriptorBuilder id0;
    id0.report_id(0);
    EXPECT_NE(parse_error(id0).find("invalid Report ID 0"), std::string::npos);
    DescriptorBuilder big;
    big.report_size(300);
    EXPECT_NE(parse_error(big).find("Report Size 300"), std::string::npos);
    DescriptorBuilder count;
    count.report_count(100000);
    EXPECT_NE(parse_error(count).find("Report Count"), std::string::npos);
    DescriptorBuilder longrep;
    longrep.usage_page(0xFF00)
        .usage(1)
        .report_size(256)
        .report_count(4096)
        .input(kDataVarAbs)
        .input(kDataVarAbs);
    EXPECT_NE(parse_error(longrep).find("longer than"), std::string::npos);
    DescriptorBuilder early;
    early.usage_page(0xFF00)
        .usage(1)
        .report_size(8)
        .report_count(1)
        .input(kDataVarAbs)
        .report_id(3)
        .usage(2)
        .input(kDataVarAbs);
    EXPECT_NE(parse_error(early).find("precedes the first Report ID"), std::string::npos);
    DescriptorBuilder range;
    range.usage_page(9).usage_min(5).usage_max(2);
    EXPECT_NE(parse_error(range).find("Usage Minimum above Usage Maximum"), std::string::npos);
    std::vector<uint8_t> huge(kMaxDescriptorBytes + 1, 0x00);
    EXPECT_FALSE(parse_descriptor(huge).ok());
}

TEST(HidDescriptor, ExtractBitsReadsUnalignedFieldsUpToSixtyFourBits) {
    std::vector<uint8_t> p(10, 0);
    // 64-bit value at bit offset 5 spans nine bytes.
    const uint64_t v = 0xF123456789ABCDEFull;
    for (int i = 0; i < 64; ++i)
        if ((v >> i) & 1) p[(5 + i) / 8] |= static_cast<uint8_t>(1u << ((5 + i) % 8));
    EXPECT_EQ(extract_bits(p, 5, 64), v);
    EXPECT_EQ(extract_bits(p, 5, 12), v & 0xFFF);
    EXPECT_EQ(extract_bits(p, 17, 1), (v >> 12) & 1);
}

TEST(HidDescriptor, PhysicalRangeAndUnitExponentScaleLogicalValues) {
    Field f;
    f.logical_min = 0;
    f.logical_max = 4095;
    f.physical_min = 0;
    f.physical_max = 8190;
    f.unit_exponent = -1;
    EXPECT_DOUBLE_EQ(to_physical(f, 4095), 819.0);
    EXPECT_DOUBLE_EQ(to_physical(f, 1), 0.2);
    f.physical_min = f.physical_max = 0;
    EXPECT_DOUBLE_EQ(to_physical(f, 40), 4.0);
    EXPECT_FALSE(in_logical_range(f, 4096));
    EXPECT_TRUE(in_logical_range(f, 0));
}
