#include "zmq_config.hpp"

#include "fovea/drivers/support.hpp"

namespace fovea::daemon {
namespace {

// zmq.publish and zmq.remote: absent leaves `out` empty; present must look like an endpoint.
Result<void> read_endpoint(const toml::table& t, const char* key, const char* example,
                           const std::string& origin, std::string& out) {
    const toml::node* n = t.get(key);
    if (!n) return {};
    auto v = n->value<std::string>();
    if (!v || v->find("://") == std::string::npos)
        return make_error(origin + ": zmq." + key +
                          ": must be a ZeroMQ endpoint string such as \"" + example + "\"");
    out = *v;
    return {};
}

}  // namespace

Result<ZmqConfig> parse_zmq_config(const toml::table& t, const std::string& origin) {
    ZmqConfig c;
    for (const auto& [key, node] : t)
        if (key.str() != "publish" && key.str() != "send_hwm" && key.str() != "remote")
            return make_error(origin + ": zmq." + std::string(key.str()) + ": unknown key");
    if (auto r = read_endpoint(t, "publish", "tcp://127.0.0.1:50020", origin, c.publish); !r)
        return r.error();
    if (const toml::node* n = t.get("send_hwm")) {
        auto v = drivers::toml_value<int64_t>(*n);
        if (!v || *v < 1 || *v > 100'000'000)
            return make_error(origin + ": zmq.send_hwm: must be an integer in [1, 100000000]");
        c.send_hwm = static_cast<int>(*v);
    }
    if (auto r = read_endpoint(t, "remote", "tcp://127.0.0.1:50021", origin, c.remote); !r)
        return r.error();
    if (!c.remote.empty() && c.publish.empty())
        return make_error(origin + ": zmq.remote: needs zmq.publish (the port it hands out)");
    return c;
}

}  // namespace fovea::daemon
