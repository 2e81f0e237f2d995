// Integers read from JSON that came from outside (a control request, a stored file). nlohmann's
// get<integer>() of a float, or of a number outside the target type, is undefined behaviour rather
// than an exception, so every such read goes through these checks first. Header-only; thread-safe.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>

#include <nlohmann/json.hpp>

namespace fovea {

// The integer `v` holds when it is one (not a float, bool or string) within [lo, hi].
inline std::optional<int64_t> json_integer(const nlohmann::json& v, int64_t lo, int64_t hi) {
    if (v.is_number_unsigned()) {
        const uint64_t u = v.get<uint64_t>();
        if (hi < 0 || u > static_cast<uint64_t>(hi)) return std::nullopt;
        return static_cast<int64_t>(u) >= lo ? std::optional<int64_t>(static_cast<int64_t>(u))
                                             : std::nullopt;
    }
    if (!v.is_number_integer()) return std::nullopt;
    const int64_t i = v.get<int64_t>();
    if (i < lo || i > hi) return std::nullopt;
    return i;
}

// The count `v` holds when it is a non-negative integer (the whole uint64_t range).
inline std::optional<uint64_t> json_count(const nlohmann::json& v) {
    if (v.is_number_unsigned()) return v.get<uint64_t>();
    if (v.is_number_integer() && v.get<int64_t>() >= 0)
        return static_cast<uint64_t>(v.get<int64_t>());
    return std::nullopt;
}

// The count under `key` of object `j`, `fallback` when the key is absent, nullopt when present but
// not a count.
inline std::optional<uint64_t> json_count(const nlohmann::json& j, const char* key,
                                          uint64_t fallback) {
    const auto it = j.find(key);
    return it == j.end() ? std::optional<uint64_t>(fallback) : json_count(*it);
}

}  // namespace fovea
