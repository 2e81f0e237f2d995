// msgpack-cxx helpers for reading foreign maps (Pupil datums, pldata files, the zmq fan-out's
// own messages): bounded unpacking (no exception escapes, no allocation a hostile size field can
// blow up) and typed lookups that never throw. Thread rules: free functions, no state.
#pragma once

#include <msgpack.hpp>

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

#include "fovea/result.hpp"

namespace fovea::msgpack_read {

// Sizes no real datum comes near; a hostile length field fails fast instead of allocating.
inline msgpack::unpack_limit datum_limits() {
    return msgpack::unpack_limit(/*array=*/1u << 16, /*map=*/1u << 12, /*str=*/1u << 20,
                                 /*bin=*/16u << 20, /*ext=*/16u << 20, /*depth=*/32);
}

enum class Unpacked { kOk, kNeedMore, kMalformed };

// One object from data[off...]; on kOk `off` moves past it. Never throws.
inline Unpacked unpack_at(const char* data, std::size_t size, std::size_t& off,
                          msgpack::object_handle& out, std::string* why = nullptr) {
    std::size_t pos = off;
    try {
        out = msgpack::unpack(data, size, pos, nullptr, nullptr, datum_limits());
    } catch (const msgpack::insufficient_bytes&) {
        return Unpacked::kNeedMore;
    } catch (const std::exception& e) {  // parse_error, size overflows, bad_alloc
        if (why) *why = e.what();
        return Unpacked::kMalformed;
    }
    off = pos;
    return Unpacked::kOk;
}

// Exactly one object filling `bytes`.
inline Result<void> unpack_one(std::string_view bytes, msgpack::object_handle& out) {
    std::size_t off = 0;
    std::string why;
    switch (unpack_at(bytes.data(), bytes.size(), off, out, &why)) {
        case Unpacked::kNeedMore: return make_error("msgpack cut short");
        case Unpacked::kMalformed: return make_error("malformed msgpack (" + why + ")");
        case Unpacked::kOk: break;
    }
    if (off != bytes.size()) return make_error("bytes after the msgpack object");
    return {};
}

inline const msgpack::object* find(const msgpack::object& map, std::string_view key) {
    if (map.type != msgpack::type::MAP) return nullptr;
    for (uint32_t i = 0; i < map.via.map.size; ++i) {
        const msgpack::object& k = map.via.map.ptr[i].key;
        if (k.type == msgpack::type::STR && k.via.str.size == key.size() &&
            std::memcmp(k.via.str.ptr, key.data(), key.size()) == 0)
            return &map.via.map.ptr[i].val;
    }
    return nullptr;
}

inline std::optional<double> number(const msgpack::object* o) {
    if (!o) return std::nullopt;
    switch (o->type) {
        case msgpack::type::FLOAT32:
        case msgpack::type::FLOAT64: return o->via.f64;
        case msgpack::type::POSITIVE_INTEGER: return static_cast<double>(o->via.u64);
        case msgpack::type::NEGATIVE_INTEGER: return static_cast<double>(o->via.i64);
        default: return std::nullopt;
    }
}

// Integers exactly (a double would round nanosecond times); floats are not integers here.
inline std::optional<int64_t> integer(const msgpack::object* o) {
    if (!o) return std::nullopt;
    if (o->type == msgpack::type::POSITIVE_INTEGER && o->via.u64 <= INT64_MAX)
        return static_cast<int64_t>(o->via.u64);
    if (o->type == msgpack::type::NEGATIVE_INTEGER) return o->via.i64;
    return std::nullopt;
}

// A two-element array of numbers.
inline bool pair(const msgpack::object* o, double out[2]) {
    if (!o || o->type != msgpack::type::ARRAY || o->via.array.size != 2) return false;
    for (uint32_t i = 0; i < 2; ++i) {
        const auto v = number(&o->via.array.ptr[i]);
        if (!v) return false;
        out[i] = *v;
    }
    return true;
}

inline std::optional<std::string> text(const msgpack::object* o) {
    if (!o) return std::nullopt;
    if (o->type == msgpack::type::STR) return std::string(o->via.str.ptr, o->via.str.size);
    if (o->type == msgpack::type::BIN) return std::string(o->via.bin.ptr, o->via.bin.size);
    return std::nullopt;
}

}  // namespace fovea::msgpack_read
