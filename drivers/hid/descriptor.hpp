// A general HID report-descriptor parser (HID 1.11 §6.2.2) producing a flat field model:
// every variable data field gets its own Field with its bit position inside its report, arrays
// keep their usage ranges. Knows nothing about eye trackers; tracker.hpp builds on it.
// Pure functions: any thread.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "fovea/result.hpp"

namespace fovea::drivers::hid {

enum class ReportType : uint8_t { kInput = 0, kOutput = 1, kFeature = 2 };

// Main item data bits (HID 1.11 §6.2.2.5).
inline constexpr uint32_t kFlagConstant = 0x001;
inline constexpr uint32_t kFlagVariable = 0x002;
inline constexpr uint32_t kFlagRelative = 0x004;
inline constexpr uint32_t kFlagNullState = 0x040;
inline constexpr uint32_t kFlagBufferedBytes = 0x100;

// Extended 32-bit usage: page in the high 16 bits, id in the low 16.
constexpr uint32_t make_usage(uint16_t page, uint16_t id) { return uint32_t{page} << 16 | id; }
constexpr uint16_t usage_page(uint32_t usage) { return static_cast<uint16_t>(usage >> 16); }
constexpr uint16_t usage_id(uint32_t usage) { return static_cast<uint16_t>(usage & 0xFFFF); }

struct Collection {
    uint32_t usage = 0;  // extended usage; 0 when the descriptor gave none
    uint8_t type = 0;    // 0 physical, 1 application, 2 logical, 3 report, ...
    int parent = -1;     // index into ReportDescriptor::collections, -1 at top level
};

struct UsageRange {
    uint32_t min = 0, max = 0;  // extended usages, inclusive
};

struct Field {
    ReportType type = ReportType::kInput;
    uint8_t report_id = 0;                 // 0 when the descriptor uses no report IDs
    uint32_t bit_offset = 0;               // from the first bit after the report ID byte
    uint32_t bit_size = 0;                 // Report Size
    uint32_t count = 1;                    // 1 for a variable; Report Count for an array
    uint32_t flags = 0;                    // kFlag* bits of the main item
    uint32_t usage = 0;                    // variables: extended usage (0 for padding / constants)
    std::vector<UsageRange> array_usages;  // arrays: usages selectable by index, in order
    int64_t logical_min = 0, logical_max = 0;    // max may exceed INT32_MAX when min >= 0
    int64_t physical_min = 0, physical_max = 0;  // both 0: physical = logical
    uint32_t unit = 0;
    int8_t unit_exponent = 0;
    int collection = -1;  // innermost enclosing collection

    bool is_variable() const { return (flags & kFlagVariable) != 0; }
    bool is_constant() const { return (flags & kFlagConstant) != 0; }
    bool is_signed() const { return logical_min < 0; }
};

struct Report {
    ReportType type = ReportType::kInput;
    uint8_t id = 0;
    uint32_t bit_length = 0;  // payload bits, without the report ID byte

    // Bytes on the wire, including the report ID byte when the device numbers its reports.
    uint32_t wire_bytes(bool numbered) const { return (bit_length + 7) / 8 + (numbered ? 1 : 0); }
};

struct ReportDescriptor {
    std::vector<Collection> collections;
    std::vector<Field> fields;
    std::vector<Report> reports;
    bool numbered = false;  // the device prefixes every report with its ID byte

    const Report* find_report(ReportType type, uint8_t id) const;
    // True if `collection` is, or is nested inside, a collection with `usage`.
    bool within(int collection, uint32_t usage) const;
    // Innermost enclosing collection (self included) whose usage is on `page`, or -1.
    int enclosing_on_page(int collection, uint16_t page) const;
};

// Limits that keep a hostile descriptor from exhausting memory (Linux uses similar caps).
inline constexpr std::size_t kMaxDescriptorBytes = 4096;
inline constexpr uint32_t kMaxReportSizeBits = 256;
inline constexpr uint32_t kMaxReportCount = 4096;
inline constexpr uint32_t kMaxReportBits = 16384 * 8;
inline constexpr std::size_t kMaxFields = 16384;
inline constexpr int kMaxCollectionDepth = 32;
inline constexpr int kMaxGlobalStack = 16;

Result<ReportDescriptor> parse_descriptor(std::span<const uint8_t> bytes);

// Raw little-endian bits of one field element (bit_size <= 64). The caller checks the range.
uint64_t extract_bits(std::span<const uint8_t> payload, uint32_t bit_offset, uint32_t bit_size);
// The field's logical value: sign-extended when the logical range is signed.
int64_t to_logical(const Field& field, uint64_t raw);
// Logical value in the field's physical range, times 10^unit_exponent (HID 1.11 §6.2.2.7).
double to_physical(const Field& field, int64_t logical);
// Values outside the logical range are the HID "null" (no data) encoding.
bool in_logical_range(const Field& field, int64_t logical);

}  // namespace fovea::drivers::hid
