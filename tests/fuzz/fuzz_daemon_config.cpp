// fovead's TOML configuration (/etc/fovea/fovead.toml, --config, SIGHUP reload): any text gives a
// config or one clear error line naming where — never a crash or an escaped exception.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    auto cfg = fovea::daemon::parse_config(text, "fuzz.toml");
    if (!cfg) {
        const std::string& m = cfg.error().message;
        if (m.empty() || m.find('\n') != std::string::npos) std::abort();  // one line
        if (m.find("fuzz.toml") == std::string::npos) std::abort();        // says where
    }
    return 0;
}
