// fovea status: the daemon's status JSON; fovea devices: its devices.
#include <cstdio>
#include <stdexcept>

#include "command.hpp"
#include "control_client.hpp"
#include "paths.hpp"

namespace fovea::cli {
namespace {

void run_query(const char* cmd, bool compact) {
    auto reply = daemon::control_request(daemon::control_socket_path(global_options().instance),
                                         {{"cmd", cmd}});
    if (!reply) throw std::runtime_error(reply.error().message);
    if (!reply->value("ok", false))
        throw std::runtime_error(reply->value("error", std::string("request failed")));
    reply->erase("ok");
    std::printf("%s\n", reply->dump(compact ? -1 : 2).c_str());
}

void setup_status(CLI::App& app) {
    static bool compact = false;
    app.add_flag("--compact", compact, "One line of JSON");
    app.callback([] { run_query("status", compact); });
}

void setup_devices(CLI::App& app) {
    app.callback([] { run_query("devices", false); });
}

const Command kStatus{"status", "Print the daemon's status JSON (devices, rates, drops, latency)",
                      &setup_status};
const Command kDevices{"devices", "Print the daemon's devices and their counters", &setup_devices};

}  // namespace
}  // namespace fovea::cli
