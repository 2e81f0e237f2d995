#include "hid/descriptor.hpp"

#include <cmath>
#include <string>

namespace fovea::drivers::hid {
namespace {

// Global item state (HID 1.11 §6.2.2.7); copied by Push and restored by Pop.
struct GlobalState {
    uint32_t usage_page = 0;
    int64_t logical_min = 0;
    uint32_t logical_max_raw = 0;
    int logical_max_size = 0;
    int64_t physical_min = 0;
    uint32_t physical_max_raw = 0;
    int physical_max_size = 0;
    int8_t unit_exponent = 0;
    uint32_t unit = 0;
    uint32_t report_size = 0;
    uint32_t report_count = 0;
    uint8_t report_id = 0;
};

// A usage as written: 1-2 byte usages take their page from the Usage Page in effect at the
// main item (what Linux does since 5.3), 4-byte usages carry their own page.
struct PendingUsage {
    uint32_t min = 0, max = 0;
    bool extended = false;
};

struct LocalState {
    std::vector<PendingUsage> usages;
    bool have_min = false, have_max = false;
    uint32_t min = 0, max = 0;
    bool min_extended = false, max_extended = false;
    int delimiter_depth = 0;
    int delimited_sets = 0;  // only the first usage of a delimited set is used (HID 1.11 §6.2.2.8)

    void clear() { *this = LocalState{}; }
};

int64_t sign_extend(uint32_t raw, int size) {
    switch (size) {
        case 1: return static_cast<int8_t>(raw);
        case 2: return static_cast<int16_t>(raw);
        case 4: return static_cast<int32_t>(raw);
        default: return 0;
    }
}

// Max values are read as signed only when the matching minimum is negative: descriptors commonly
// write "Logical Maximum (255)" as the single byte 0xFF.
int64_t resolve_max(int64_t min, uint32_t raw, int size) {
    return min < 0 ? sign_extend(raw, size) : static_cast<int64_t>(raw);
}

std::string at(std::size_t offset) { return " at byte " + std::to_string(offset); }

class Parser {
public:
    explicit Parser(std::span<const uint8_t> bytes) : bytes_(bytes) {}

    Result<ReportDescriptor> run() {
        if (bytes_.empty()) return make_error("empty report descriptor");
        if (bytes_.size() > kMaxDescriptorBytes)
            return make_error("report descriptor of " + std::to_string(bytes_.size()) +
                              " bytes exceeds " + std::to_string(kMaxDescriptorBytes));
        std::size_t pos = 0;
        while (pos < bytes_.size()) {
            const std::size_t item_at = pos;
            const uint8_t prefix = bytes_[pos++];
            if (prefix == 0xFE) {  // long item: size, tag, data; none are defined, skip them
                if (pos + 2 > bytes_.size()) return make_error("truncated long item" + at(item_at));
                const std::size_t size = bytes_[pos];
                pos += 2;
                if (pos + size > bytes_.size())
                    return make_error("truncated long item data" + at(item_at));
                pos += size;
                continue;
            }
            static constexpr int kSizes[4] = {0, 1, 2, 4};
            const int size = kSizes[prefix & 3];
            const int type = (prefix >> 2) & 3;
            const int tag = prefix >> 4;
            if (pos + static_cast<std::size_t>(size) > bytes_.size())
                return make_error("truncated item data" + at(item_at));
            uint32_t data = 0;
            for (int i = 0; i < size; ++i) data |= uint32_t{bytes_[pos + i]} << (8 * i);
            pos += static_cast<std::size_t>(size);

            Result<void> r;
            switch (type) {
                case 0: r = main_item(tag, data, size); break;
                case 1: r = global_item(tag, data, size); break;
                case 2: r = local_item(tag, data, size); break;
                default: break;  // reserved item type: skip, as the spec asks
            }
            if (!r) return make_error(r.error().message + at(item_at));
        }
        if (!open_.empty())
            return make_error(std::to_string(open_.size()) + " collection(s) left open");
        if (out_.numbered)
            for (const auto& f : out_.fields)
                if (f.report_id == 0)
                    return make_error(
                        "a field precedes the first Report ID in a numbered "
                        "descriptor");
        return std::move(out_);
    }

private:
    Result<void> global_item(int tag, uint32_t data, int size) {
        switch (tag) {
            case 0: g_.usage_page = data & 0xFFFF; break;
            case 1: g_.logical_min = sign_extend(data, size); break;
            case 2:
                g_.logical_max_raw = data;
                g_.logical_max_size = size;
                break;
            case 3: g_.physical_min = sign_extend(data, size); break;
            case 4:
                g_.physical_max_raw = data;
                g_.physical_max_size = size;
                break;
            case 5:
                // The spec gives a 4-bit two's-complement nibble; some devices write a whole byte.
                if ((data & ~0xFu) == 0)
                    g_.unit_exponent = static_cast<int8_t>(data >= 8 ? int(data) - 16 : int(data));
                else
                    g_.unit_exponent = static_cast<int8_t>(sign_extend(data, size));
                break;
            case 6: g_.unit = data; break;
            case 7:
                if (data > kMaxReportSizeBits)
                    return make_error("Report Size " + std::to_string(data) + " exceeds " +
                                      std::to_string(kMaxReportSizeBits));
                g_.report_size = data;
                break;
            case 8:
                if (data == 0 || data > 255)
                    return make_error("invalid Report ID " + std::to_string(data));
                g_.report_id = static_cast<uint8_t>(data);
                out_.numbered = true;
                break;
            case 9:
                if (data > kMaxReportCount)
                    return make_error("Report Count " + std::to_string(data) + " exceeds " +
                                      std::to_string(kMaxReportCount));
                g_.report_count = data;
                break;
            case 10:
                if (static_cast<int>(stack_.size()) >= kMaxGlobalStack)
                    return make_error("Push nested deeper than " + std::to_string(kMaxGlobalStack));
                stack_.push_back(g_);
                break;
            case 11:
                if (stack_.empty()) return make_error("Pop without Push");
                g_ = stack_.back();
                stack_.pop_back();
                break;
            default: break;  // reserved global tags
        }
        return {};
    }

    Result<void> local_item(int tag, uint32_t data, int size) {
        const bool extended = size == 4;
        switch (tag) {
            case 0:  // Usage
                if (l_.delimiter_depth > 0 && l_.delimited_sets > 0) break;
                l_.usages.push_back({data, data, extended});
                if (l_.delimiter_depth > 0) ++l_.delimited_sets;
                break;
            case 1:
                l_.have_min = true;
                l_.min = data;
                l_.min_extended = extended;
                break;
            case 2:
                l_.have_max = true;
                l_.max = data;
                l_.max_extended = extended;
                break;
            case 10:  // Delimiter: 1 opens a set of alternative usages, 0 closes it
                if (data == 1) {
                    if (l_.delimiter_depth > 0) return make_error("nested Delimiter");
                    l_.delimiter_depth = 1;
                    l_.delimited_sets = 0;
                } else if (data == 0) {
                    if (l_.delimiter_depth == 0) return make_error("Delimiter close without open");
                    l_.delimiter_depth = 0;
                }
                break;
            default: break;  // designators, strings: carry no data layout
        }
        if (l_.have_min && l_.have_max) {
            const uint32_t lo = resolve(l_.min, l_.min_extended);
            const uint32_t hi = resolve(l_.max, l_.max_extended);
            if (lo > hi) return make_error("Usage Minimum above Usage Maximum");
            // Resolved already: mark extended so the main item leaves the page alone.
            l_.usages.push_back({lo, hi, true});
            l_.have_min = l_.have_max = false;
        }
        return {};
    }

    uint32_t resolve(uint32_t usage, bool extended) const {
        return extended
                   ? usage
                   : make_usage(static_cast<uint16_t>(g_.usage_page), static_cast<uint16_t>(usage));
    }

    std::vector<UsageRange> resolved_usages() const {
        std::vector<UsageRange> out;
        out.reserve(l_.usages.size());
        for (const auto& u : l_.usages)
            out.push_back({resolve(u.min, u.extended), resolve(u.max, u.extended)});
        return out;
    }

    Result<void> main_item(int tag, uint32_t data, int /*size*/) {
        Result<void> r;
        switch (tag) {
            case 8: r = data_item(ReportType::kInput, data); break;
            case 9: r = data_item(ReportType::kOutput, data); break;
            case 11: r = data_item(ReportType::kFeature, data); break;
            case 10: {
                if (static_cast<int>(open_.size()) >= kMaxCollectionDepth)
                    return make_error("collections nested deeper than " +
                                      std::to_string(kMaxCollectionDepth));
                const auto usages = resolved_usages();
                Collection c;
                c.usage = usages.empty() ? 0 : usages.front().min;
                c.type = static_cast<uint8_t>(data & 0xFF);
                c.parent = open_.empty() ? -1 : open_.back();
                out_.collections.push_back(c);
                open_.push_back(static_cast<int>(out_.collections.size()) - 1);
                break;
            }
            case 12:
                if (open_.empty()) return make_error("End Collection without Collection");
                open_.pop_back();
                break;
            default: break;  // reserved main tags
        }
        l_.clear();
        return r;
    }

    Result<void> data_item(ReportType type, uint32_t flags) {
        const uint32_t size = g_.report_size;
        const uint32_t count = g_.report_count;
        Report& report = report_for(type, g_.report_id);
        const uint64_t bits = uint64_t{size} * count;
        if (report.bit_length + bits > kMaxReportBits)
            return make_error("report " + std::to_string(g_.report_id) + " longer than " +
                              std::to_string(kMaxReportBits / 8) + " bytes");
        const uint32_t base = report.bit_length;
        report.bit_length += static_cast<uint32_t>(bits);
        if (bits == 0) return {};

        Field proto;
        proto.type = type;
        proto.report_id = g_.report_id;
        proto.bit_size = size;
        proto.flags = flags;
        proto.logical_min = g_.logical_min;
        proto.logical_max = resolve_max(g_.logical_min, g_.logical_max_raw, g_.logical_max_size);
        proto.physical_min = g_.physical_min;
        proto.physical_max =
            resolve_max(g_.physical_min, g_.physical_max_raw, g_.physical_max_size);
        proto.unit = g_.unit;
        proto.unit_exponent = g_.unit_exponent;
        proto.collection = open_.empty() ? -1 : open_.back();

        const auto usages = resolved_usages();
        if (!(flags & kFlagVariable)) {  // array: one field, `count` indices into the usages
            if (out_.fields.size() >= kMaxFields) return make_error("too many fields");
            proto.bit_offset = base;
            proto.count = count;
            proto.array_usages = usages;
            out_.fields.push_back(std::move(proto));
            return {};
        }
        // Variables: the i-th field takes the i-th usage; the last usage repeats (HID 1.11
        // §6.2.2.8).
        std::size_t range = 0;
        uint32_t next = usages.empty() ? 0 : usages.front().min;
        uint32_t usage = 0;
        for (uint32_t i = 0; i < count; ++i) {
            if (range < usages.size()) {
                usage = next;
                if (next < usages[range].max) {
                    ++next;
                } else if (++range < usages.size()) {
                    next = usages[range].min;
                }
            }
            if (usage == 0 && (flags & kFlagConstant)) continue;  // padding
            if (out_.fields.size() >= kMaxFields) return make_error("too many fields");
            Field f = proto;
            f.bit_offset = base + i * size;
            f.usage = usage;
            out_.fields.push_back(std::move(f));
        }
        return {};
    }

    Report& report_for(ReportType type, uint8_t id) {
        for (auto& r : out_.reports)
            if (r.type == type && r.id == id) return r;
        out_.reports.push_back({type, id, 0});
        return out_.reports.back();
    }

    std::span<const uint8_t> bytes_;
    GlobalState g_;
    LocalState l_;
    std::vector<GlobalState> stack_;
    std::vector<int> open_;
    ReportDescriptor out_;
};

}  // namespace

const Report* ReportDescriptor::find_report(ReportType type, uint8_t id) const {
    for (const auto& r : reports)
        if (r.type == type && r.id == id) return &r;
    return nullptr;
}

bool ReportDescriptor::within(int collection, uint32_t usage) const {
    for (int c = collection; c >= 0; c = collections[static_cast<std::size_t>(c)].parent)
        if (collections[static_cast<std::size_t>(c)].usage == usage) return true;
    return false;
}

int ReportDescriptor::enclosing_on_page(int collection, uint16_t page) const {
    for (int c = collection; c >= 0; c = collections[static_cast<std::size_t>(c)].parent)
        if (usage_page(collections[static_cast<std::size_t>(c)].usage) == page) return c;
    return -1;
}

Result<ReportDescriptor> parse_descriptor(std::span<const uint8_t> bytes) {
    return Parser(bytes).run();
}

uint64_t extract_bits(std::span<const uint8_t> payload, uint32_t bit_offset, uint32_t bit_size) {
    const uint8_t* p = payload.data() + bit_offset / 8;
    const uint32_t shift = bit_offset % 8;
    const uint32_t nbytes = (shift + bit_size + 7) / 8;  // at most 9
    uint64_t v = 0;
    for (uint32_t k = 0; k < nbytes && k < 8; ++k) v |= uint64_t{p[k]} << (8 * k);
    v >>= shift;
    if (nbytes == 9) v |= uint64_t{p[8]} << (64 - shift);
    if (bit_size < 64) v &= (uint64_t{1} << bit_size) - 1;
    return v;
}

int64_t to_logical(const Field& field, uint64_t raw) {
    if (field.is_signed() && field.bit_size > 0 && field.bit_size < 64) {
        const uint64_t sign = uint64_t{1} << (field.bit_size - 1);
        return static_cast<int64_t>((raw ^ sign) - sign);
    }
    return static_cast<int64_t>(raw);
}

double to_physical(const Field& field, int64_t logical) {
    double p = static_cast<double>(logical);
    if ((field.physical_min != 0 || field.physical_max != 0) &&
        field.logical_max != field.logical_min) {
        p = static_cast<double>(field.physical_min) +
            (p - static_cast<double>(field.logical_min)) *
                static_cast<double>(field.physical_max - field.physical_min) /
                static_cast<double>(field.logical_max - field.logical_min);
    }
    return field.unit_exponent == 0 ? p : p * std::pow(10.0, field.unit_exponent);
}

bool in_logical_range(const Field& field, int64_t logical) {
    if (field.logical_min > field.logical_max) return true;  // no usable range declared
    return logical >= field.logical_min && logical <= field.logical_max;
}

}  // namespace fovea::drivers::hid
