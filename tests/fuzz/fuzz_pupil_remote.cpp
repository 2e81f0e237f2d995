// libFuzzer target: Pupil Remote's replies as the `pupil` driver reads them — the input is the
// answer to "SUB_PORT" (bus_address) and, split at newlines, the answers to a run of "t" requests
// (parse_time_reply, then estimate_offset over them). Invariants: no crash; a bus address is the
// Remote's host with a port 1..65535; a time is finite, and so is the clock offset of any run.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "pupil/pupil_remote.hpp"

using namespace fovea::drivers::pupil;

namespace {

void check(bool ok) {
    if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const std::string remote = "tcp://127.0.0.1:50020";
    if (auto bus = bus_address(remote, text)) {
        check(bus->starts_with("tcp://127.0.0.1:"));
        const std::string port = bus->substr(16);
        check(port == text && std::stol(port) >= 1 && std::stol(port) <= 65535);
    } else {
        check(!bus.error().message.empty() && bus.error().message.size() < 200);
    }
    std::vector<RoundTrip> trips;
    double host = 1.0;
    for (std::size_t start = 0; start <= text.size();) {
        const std::size_t end = std::min(text.find('\n', start), text.size());
        if (auto t = parse_time_reply(text.substr(start, end - start))) {
            check(std::isfinite(*t));
            trips.push_back({host, *t, host + 1e-3 * static_cast<double>(trips.size() % 7)});
            host += 0.01;
        }
        start = end + 1;
    }
    if (auto c = estimate_offset(trips)) {
        check(c->kept >= 1 && c->kept <= c->total && c->total == trips.size());
        check(std::isfinite(c->offset_s) && std::isfinite(c->sd_s));
        check(c->uncertainty_s >= 0 && c->median_rtt_s >= 0);
    }
    return 0;
}
