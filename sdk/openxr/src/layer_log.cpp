#include "layer_log.hpp"

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace fovea::openxr {
namespace {

void vlog(const char* fmt, va_list ap) {
    char line[512];
    std::vsnprintf(line, sizeof line, fmt, ap);
    std::fprintf(stderr, "XR_APILAYER_FOVEA_eye_gaze: %s\n", line);
}

}  // namespace

LogLevel log_level() {
    static const LogLevel level = [] {
        const char* v = std::getenv("FOVEA_OPENXR_LOG");
        if (!v) return LogLevel::kInfo;
        if (std::strcmp(v, "quiet") == 0 || std::strcmp(v, "0") == 0) return LogLevel::kQuiet;
        if (std::strcmp(v, "debug") == 0) return LogLevel::kDebug;
        return LogLevel::kInfo;
    }();
    return level;
}

void log_info(const char* fmt, ...) {
    if (log_level() < LogLevel::kInfo) return;
    va_list ap;
    va_start(ap, fmt);
    vlog(fmt, ap);
    va_end(ap);
}

void log_debug(const char* fmt, ...) {
    if (log_level() < LogLevel::kDebug) return;
    va_list ap;
    va_start(ap, fmt);
    vlog(fmt, ap);
    va_end(ap);
}

}  // namespace fovea::openxr
