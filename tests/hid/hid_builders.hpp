// Test helpers: write HID report descriptors item by item (HID 1.11 §6.2.2) and pack report bits
// at hand-computed offsets, so tests never derive a report layout from the parser under test.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <vector>

namespace fovea::test {

class DescriptorBuilder {
public:
    // Short item with the smallest size that holds `value` (signed when `is_signed`).
    DescriptorBuilder& item(uint8_t tag_type, int64_t value, bool is_signed = false) {
        int size = 0;
        if (is_signed) {
            size = (value >= -128 && value <= 127)       ? 1
                   : (value >= -32768 && value <= 32767) ? 2
                                                         : 4;
        } else {
            size = value <= 0xFF ? 1 : value <= 0xFFFF ? 2 : 4;
        }
        return sized(tag_type, static_cast<uint32_t>(value), size);
    }
    DescriptorBuilder& sized(uint8_t tag_type, uint32_t value, int size) {
        const uint8_t code = size == 0 ? 0 : size == 1 ? 1 : size == 2 ? 2 : 3;
        bytes.push_back(static_cast<uint8_t>(tag_type | code));
        for (int i = 0; i < size; ++i) bytes.push_back(static_cast<uint8_t>(value >> (8 * i)));
        return *this;
    }
    DescriptorBuilder& raw(std::initializer_list<uint8_t> b) {
        bytes.insert(bytes.end(), b);
        return *this;
    }
    // Global items
    DescriptorBuilder& usage_page(uint16_t p) { return item(0x04, p); }
    DescriptorBuilder& logical_min(int64_t v) { return item(0x14, v, true); }
    DescriptorBuilder& logical_max(int64_t v) { return item(0x24, v, v < 0 || v <= 0x7FFFFFFF); }
    DescriptorBuilder& physical_min(int64_t v) { return item(0x34, v, true); }
    DescriptorBuilder& physical_max(int64_t v) { return item(0x44, v, true); }
    DescriptorBuilder& unit_exponent(int e) {
        return sized(0x54, static_cast<uint32_t>(e) & 0xF, 1);
    }
    DescriptorBuilder& unit(uint32_t u) { return item(0x64, u); }
    DescriptorBuilder& report_size(uint32_t s) { return item(0x74, s); }
    DescriptorBuilder& report_id(uint8_t id) { return item(0x84, id); }
    DescriptorBuilder& report_count(uint32_t c) { return item(0x94, c); }
    DescriptorBuilder& push() { return sized(0xA4, 0, 0); }
    DescriptorBuilder& pop() { return sized(0xB4, 0, 0); }
    // Local items
    DescriptorBuilder& usage(uint16_t u) { return item(0x08, u); }
    DescriptorBuilder& usage_ext(uint16_t page, uint16_t id) {
        return sized(0x08, uint32_t{page} << 16 | id, 4);
    }
    DescriptorBuilder& usage_min(uint16_t u) { return item(0x18, u); }
    DescriptorBuilder& usage_max(uint16_t u) { return item(0x28, u); }
    DescriptorBuilder& delimiter(bool open) { return sized(0xA8, open ? 1 : 0, 1); }
    // Main items
    DescriptorBuilder& input(uint32_t flags) { return item(0x80, flags); }
    DescriptorBuilder& output(uint32_t flags) { return item(0x90, flags); }
    DescriptorBuilder& feature(uint32_t flags) { return item(0xB0, flags); }
    DescriptorBuilder& collection(uint8_t type) { return sized(0xA0, type, 1); }
    DescriptorBuilder& end_collection() { return sized(0xC0, 0, 0); }
    DescriptorBuilder& long_item(uint8_t tag, std::initializer_list<uint8_t> data) {
        bytes.push_back(0xFE);
        bytes.push_back(static_cast<uint8_t>(data.size()));
        bytes.push_back(tag);
        bytes.insert(bytes.end(), data);
        return *this;
    }

    std::vector<uint8_t> bytes;
};

inline constexpr uint32_t kData = 0x00, kConst = 0x01, kVar = 0x02;
inline constexpr uint32_t kDataVarAbs = kData | kVar;
inline constexpr uint32_t kConstVarAbs = kConst | kVar;
inline constexpr uint32_t kDataArray = kData;
inline constexpr uint32_t kNullState = 0x40;

// A report buffer written bit by bit, little-endian, as HID lays out fields.
class ReportBuilder {
public:
    ReportBuilder(std::size_t bytes, int report_id = -1) {
        if (report_id >= 0) prefix_ = 1;
        data.assign(bytes + prefix_, 0);
        if (report_id >= 0) data[0] = static_cast<uint8_t>(report_id);
    }
    ReportBuilder& put(uint32_t bit_offset, uint32_t bit_size, uint64_t value) {
        for (uint32_t i = 0; i < bit_size; ++i) {
            const uint32_t bit = bit_offset + i;
            if ((value >> i) & 1) data[prefix_ + bit / 8] |= static_cast<uint8_t>(1u << (bit % 8));
        }
        return *this;
    }
    std::vector<uint8_t> data;

private:
    std::size_t prefix_ = 0;
};

}  // namespace fovea::test
