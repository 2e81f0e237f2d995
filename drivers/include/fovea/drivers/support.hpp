// Small helpers every driver needs: host time, a per-driver logger, typed config keys and
// rate-limited incident logging. Header-only; drivers include it from their .cpp files.
#pragma once

#include <time.h>

#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <toml++/toml.h>

#include "fovea/result.hpp"

namespace fovea::drivers {

inline int64_t monotonic_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

// The logger "drv.<name>"; FOVEA_LOG_DRV_<NAME>=debug (trace, warn, ...) sets its level.
inline std::shared_ptr<spdlog::logger> driver_logger(const std::string& name) {
    const std::string id = "drv." + name;
    auto l = spdlog::get(id);
    if (l) return l;
    l = spdlog::stderr_color_mt(id);
    std::string env = "FOVEA_LOG_DRV_";
    for (char c : name) env += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (const char* level = std::getenv(env.c_str())) l->set_level(spdlog::level::from_str(level));
    return l;
}

// node.value<T>(), except that a float outside int64's range is no integer: toml++ 3 casts it
// to int64 unchecked (undefined behaviour for `seed = 1e300`).
template <typename T>
std::optional<T> toml_value(const toml::node& node) {
    if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
        if (const auto* f = node.as_floating_point()) {
            const double d = f->get();
            if (!(d >= -9.2e18 && d <= 9.2e18)) return std::nullopt;
        }
    }
    return node.value<T>();
}

// Read an optional key of type T; a present key of the wrong type is an error naming it.
template <typename T>
Result<void> read_key(const char* driver, const toml::table& t, const char* key, T& out) {
    const toml::node* node = t.get(key);
    if (!node) return {};
    const auto v = toml_value<T>(*node);
    if (!v) return make_error(std::string(driver) + ": key '" + key + "' has the wrong type");
    out = *v;
    return {};
}

// A driver's `[[device]]` keys read one after another with read_key under the driver's name:
// every read runs, and result() is the first error (a key of the wrong type), or ok.
class ConfigKeys {
public:
    ConfigKeys(const char* driver, const toml::table& table) : driver_(driver), table_(table) {}

    template <typename T>
    void read(const char* key, T& out) {
        read(table_, key, out);
    }
    // A key of a sub-table (e.g. [device.display]).
    template <typename T>
    void read(const toml::table& t, const char* key, T& out) {
        Result<void> r = read_key(driver_, t, key, out);
        if (result_.ok() && !r.ok()) result_ = std::move(r);
    }

    const Result<void>& result() const { return result_; }

private:
    const char* driver_;
    const toml::table& table_;
    Result<void> result_;
};

// A USB vendor or product id from config: an integer or a hex string ("046d", "0x046d").
inline std::optional<uint16_t> parse_usb_id(const toml::node_view<const toml::node>& v) {
    if (v.node() == nullptr) return std::nullopt;
    if (auto i = toml_value<int64_t>(*v.node()); i && *i >= 0 && *i <= 0xFFFF)
        return static_cast<uint16_t>(*i);
    if (auto s = v.value<std::string>()) {
        try {
            std::size_t used = 0;
            const unsigned long n = std::stoul(*s, &used, 16);
            if (used == s->size() && n <= 0xFFFF) return static_cast<uint16_t>(n);
        } catch (...) {}
    }
    return std::nullopt;
}

// One line per incident kind and second; the lines in between are counted, not lost.
class LogLimiter {
public:
    explicit LogLimiter(std::shared_ptr<spdlog::logger> log) : log_(std::move(log)) {}

    void warn(const std::string& message) {
        const auto now = std::chrono::steady_clock::now();
        if (now - last_ < std::chrono::seconds(1)) {
            ++suppressed_;
            return;
        }
        if (suppressed_ != 0)
            log_->warn("{} (+{} similar)", message, suppressed_);
        else
            log_->warn("{}", message);
        last_ = now;
        suppressed_ = 0;
    }

private:
    std::shared_ptr<spdlog::logger> log_;
    std::chrono::steady_clock::time_point last_{};
    uint64_t suppressed_ = 0;
};

}  // namespace fovea::drivers
