// What every importer's fuzz target checks (fovea::import over bytes in memory, one format
// forced): no crash, and whatever is delivered is sane — valid eyes have finite coordinates,
// stamps never go back, events end after they start, issue lists stay bounded.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "fovea/import/reader.hpp"

namespace fovea::fuzz {

inline void check_import(const uint8_t* data, size_t size, import::Format format) {
    import::Options o;
    o.format = format;
    o.max_issues = 8;
    auto r =
        import::open_memory(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz", o);
    if (!r) return;
    import::Reader& reader = **r;
    double prev = -INFINITY;
    for (auto it = reader.next(); it != import::Item::kEnd; it = reader.next()) {
        if (it == import::Item::kSample) {
            const auto& s = reader.sample();
            for (const auto* e : {&s.raw.left, &s.raw.right})
                if (e->valid && !(std::isfinite(e->x) && std::isfinite(e->y))) std::abort();
            if (!(s.time_s >= prev)) std::abort();
            prev = s.time_s;
        } else if (it == import::Item::kEvent) {
            if (!(reader.event().end_s >= reader.event().start_s)) std::abort();
        }
    }
    if (reader.stats().issues.size() > o.max_issues) std::abort();
}

}  // namespace fovea::fuzz
