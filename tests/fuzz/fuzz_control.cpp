// Control-socket requests against a started fovead (the simulated tracker, rings, every command
// registered: status, devices, shutdown, record.*, latency.*, calibrate.*). Each input is one
// request line from a local client, admin or not; every reply must be a JSON object with a
// boolean "ok" and, when false, a string "error" — never a crash or an escaped exception.
// Absolute "path"s are pointed into a scratch directory so record.start writes only there.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "daemon.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct Harness {
    std::string dir;
    std::unique_ptr<fovea::daemon::Daemon> daemon;

    Harness() {
        const std::string instance = "fz" + std::to_string(getpid());
        dir = (fs::temp_directory_path() / ("fovea-fuzz-control-" + instance)).string();
        fs::create_directories(dir);
        setenv("FOVEA_RUNTIME_DIR", dir.c_str(), 1);
        setenv("FOVEA_STATE_DIR", (dir + "/state").c_str(), 1);
        auto cfg = fovea::daemon::parse_config(
            "[[device]]\ndriver = \"sim\"\nseed = 3\n"
            "[calibration]\nsettle_ms = 0\ncollect_ms = 50\n",
            "fuzz");
        if (!cfg) std::abort();
        cfg->instance = instance;
        daemon = std::make_unique<fovea::daemon::Daemon>(std::move(cfg).value(), "");
        if (auto r = daemon->start(); !r) std::abort();
    }
    ~Harness() {
        daemon.reset();
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
};

void check(bool ok) {
    if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static Harness h;
    std::string line(reinterpret_cast<const char*>(data), size);
    json req = json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (req.is_object() && req.contains("path") && req["path"].is_string()) {
        const std::string p = req["path"];
        if (!p.empty() && p.front() == '/') {
            req["path"] = h.dir + "/rec.xdf";
            line = req.dump();
        }
    }
    // Uid 0 is admin; 65534 (nobody) is not: mutating commands must refuse it.
    const fovea::daemon::PeerCredentials peer{1, size % 2 ? 0u : 65534u, size % 2 ? 0u : 65534u};
    const json reply = h.daemon->control().handle_line(line, peer);
    check(reply.is_object());
    if (reply.contains("ok")) {
        check(reply["ok"].is_boolean());
        if (!reply["ok"].get<bool>()) check(reply.contains("error") && reply["error"].is_string());
    }
    check(!reply.dump().empty());  // serialisable: no invalid UTF-8 echoed back into the reply
    // Work the commands posted (a stop, collection, recording flushes) runs as in the loop.
    h.daemon->io().restart();
    h.daemon->io().poll();
    return 0;
}
