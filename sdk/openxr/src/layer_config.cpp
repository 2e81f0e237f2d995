#include "layer_config.hpp"

#include <cstdlib>
#include <cstring>

namespace fovea::openxr {
namespace {

// A positive number of milliseconds from the environment, or `fallback` (noting the problem).
int64_t read_ms(const char* name, int64_t fallback, double max_ms, std::string& problems) {
    const char* v = std::getenv(name);
    if (!v || !*v) return fallback;
    char* end = nullptr;
    const double ms = std::strtod(v, &end);
    if (end == v || *end != '\0' || !(ms > 0 && ms <= max_ms)) {
        problems += std::string(problems.empty() ? "" : "; ") + name + "='" + v +
                    "' is not a number of milliseconds in (0, " +
                    std::to_string(static_cast<int>(max_ms)) + "]";
        return fallback;
    }
    return static_cast<int64_t>(ms * 1e6);
}

}  // namespace

LayerConfig read_layer_config() {
    LayerConfig c;
    if (const char* inst = std::getenv("FOVEA_INSTANCE"); inst && *inst) c.gaze.instance = inst;
    if (const char* mode = std::getenv("FOVEA_OPENXR_GAZE"); mode && *mode) {
        if (std::strcmp(mode, "replace") == 0)
            c.replace_runtime_gaze = true;
        else if (std::strcmp(mode, "auto") != 0)
            c.problems += std::string("FOVEA_OPENXR_GAZE='") + mode + "' is not auto or replace";
    }
    c.gaze.timeline.max_prediction_ns = read_ms("FOVEA_OPENXR_MAX_PREDICTION_MS",
                                                c.gaze.timeline.max_prediction_ns, 500, c.problems);
    c.gaze.timeline.stale_ns =
        read_ms("FOVEA_OPENXR_STALE_MS", c.gaze.timeline.stale_ns, 10000, c.problems);
    return c;
}

}  // namespace fovea::openxr
