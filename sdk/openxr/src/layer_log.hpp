// The layer's few log lines: stderr, one line each, prefixed with the layer's name, so they can
// be found in any app's output. FOVEA_OPENXR_LOG=quiet silences them, =debug adds detail.
// Any thread (one fprintf per line).
#pragma once

namespace fovea::openxr {

enum class LogLevel { kQuiet = 0, kInfo = 1, kDebug = 2 };

LogLevel log_level();  // read from the environment once
void log_info(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
void log_debug(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace fovea::openxr
