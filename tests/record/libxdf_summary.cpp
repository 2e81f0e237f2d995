// libxdf_summary FILE: what Debian's libxdf (the reader SigViewer uses) reads from an XDF file,
// as JSON on stdout, for the record tests' oracle (libxdf_oracle.cpp). A process of its own and
// never sanitized: libxdf 0.99.8 strlen()s the file header buffer one past its end, which ASan
// would report inside the test instead of a disagreement about the file.
#include <xdf.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace {

nlohmann::json number(double v) {  // JSON has no NaN or infinities
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: libxdf_summary FILE\n");
        return 2;
    }
    Xdf x;
    std::ostringstream chatter;  // load_xdf reports its timing on std::cout
    auto* out = std::cout.rdbuf(chatter.rdbuf());
    const int rc = x.load_xdf(argv[1]);
    std::cout.rdbuf(out);
    if (rc != 0) {
        std::fprintf(stderr, "libxdf: load_xdf returned %d: %s\n", rc, chatter.str().c_str());
        return 1;
    }
    nlohmann::json streams = nlohmann::json::array();
    for (const auto& s : x.streams) {
        nlohmann::json labels = nlohmann::json::array();
        for (const auto& ch : s.info.channels) {
            const auto l = ch.find("label");
            labels.push_back(l == ch.end() ? nlohmann::json() : nlohmann::json(l->second));
        }
        nlohmann::json stamps = nlohmann::json::array(), series = nlohmann::json::array();
        for (double t : s.time_stamps) stamps.push_back(number(t));
        for (const auto& channel : s.time_series) {
            nlohmann::json c = nlohmann::json::array();
            for (float v : channel) c.push_back(number(v));
            series.push_back(std::move(c));
        }
        streams.push_back({{"name", s.info.name},
                           {"type", s.info.type},
                           {"channel_format", s.info.channel_format},
                           {"channel_count", s.info.channel_count},
                           {"nominal_srate", s.info.nominal_srate},
                           {"labels", std::move(labels)},
                           {"has_footer", !s.streamFooter.empty()},
                           {"footer_sample_count", s.info.sample_count},
                           {"time_stamps", std::move(stamps)},
                           {"time_series", std::move(series)}});
    }
    std::cout << nlohmann::json{{"streams", std::move(streams)}}.dump() << "\n";
    return 0;
}
