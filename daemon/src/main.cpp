// fovead: the Fovea device daemon. See README.md and `fovead --help`.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "config.hpp"
#include "daemon.hpp"

namespace {

constexpr const char* kSystemConfig = "/etc/fovea/fovead.toml";

int fail(const std::string& line) {
    std::fprintf(stderr, "fovead: %s\n", line.c_str());
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"fovead: reads eye trackers and publishes gaze into shared memory"};
    std::string config_path, instance, log_level;
    uint32_t ring_slots = 0;
    bool check_only = false;
    app.add_option("--config", config_path,
                   "TOML configuration (default /etc/fovea/fovead.toml if present)");
    app.add_option("--instance", instance,
                   "Instance name: ring /fovea.<name>.gaze and <name>.sock");
    app.add_option("--log-level", log_level, "trace, debug, info, warn, error, off")
        ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}));
    app.add_option("--ring-slots", ring_slots, "Slots in the gaze ring (power of two)")
        ->check(CLI::Range(16u, 1u << 20));
    app.add_flag("--check-config", check_only, "Validate the configuration and exit");
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) { return app.exit(e); } catch (const CLI::ParseError& e) {
        return fail(std::string(e.what()) + " (see fovead --help)");
    }

    if (config_path.empty() && access(kSystemConfig, R_OK) == 0) config_path = kSystemConfig;
    fovea::Result<fovea::daemon::DaemonConfig> cfg =
        config_path.empty() ? fovea::daemon::parse_config("", "defaults")
                            : fovea::daemon::load_config(config_path);
    if (!cfg) return fail(cfg.error().message);
    if (!instance.empty()) cfg->instance = instance;
    if (!log_level.empty()) cfg->log_level = log_level;
    if (ring_slots) cfg->ring_slots = ring_slots;
    if (const char* env = std::getenv("FOVEA_LOG_LEVEL"); env && log_level.empty())
        cfg->log_level = env;
    if (check_only) {
        std::printf("%s: OK (%zu device(s))\n",
                    config_path.empty() ? "defaults" : config_path.c_str(), cfg->devices.size());
        return 0;
    }

    auto logger = spdlog::stderr_color_mt("daemon");
    spdlog::set_default_logger(logger);
    spdlog::set_level(spdlog::level::from_str(cfg->log_level));
    spdlog::set_pattern("%Y-%m-%d %H:%M:%S.%e %^%l%$ [%n] %v");

    fovea::daemon::Daemon daemon(std::move(cfg).value(), config_path);
    if (auto r = daemon.start(); !r) return fail(r.error().message);
    return daemon.run();
}
