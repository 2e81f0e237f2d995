// libFuzzer target: one OSC packet as the osc driver receives it — liblo's message parser, then
// the FrameAssembler of each preset. Invariants: no crash; a valid eye has finite coordinates.
#include <lo/lo.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "osc/osc_map.hpp"

using namespace fovea::drivers::osc;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    // An OSC packet: the address pattern (a padded string), then the message body.
    std::vector<uint8_t> buf(data, data + size);
    const std::size_t end =
        std::string(reinterpret_cast<const char*>(buf.data()), buf.size()).find('\0');
    if (end == std::string::npos || end == 0) return 0;
    const std::string path(reinterpret_cast<const char*>(buf.data()), end);
    int result = 0;
    lo_message m = lo_message_deserialise(buf.data(), buf.size(), &result);
    if (!m) return 0;
    std::vector<double> values;
    arguments_as_numbers(lo_message_get_types(m), lo_message_get_argv(m), lo_message_get_argc(m),
                         values);
    for (const char* preset : {"vrchat", "vrcft-v2"}) {
        auto map = parse_address_map(toml::table{{"preset", preset}});
        if (!map) std::abort();
        FrameAssembler a(*map);
        std::optional<fovea::gaze::RawSample> s;
        for (int k = 0; k < 4; ++k) {  // a frame needs several messages
            a.message(path, values, s);
            if (s)
                for (const auto* e : {&s->left, &s->right})
                    if (e->valid && !(std::isfinite(e->x) && std::isfinite(e->y))) std::abort();
        }
    }
    lo_message_free(m);
    return 0;
}
