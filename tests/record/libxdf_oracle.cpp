#include "libxdf_oracle.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fovea/record/xdf.hpp"

namespace fovea::record::test {
namespace {

using nlohmann::json;

// libxdf_summary's numbers: JSON numbers, or "nan" / "inf" / "-inf".
double number(const json& j) {
    if (j.is_number()) return j.get<double>();
    const std::string s = j.get<std::string>();
    return s == "nan" ? NAN : s == "inf" ? INFINITY : -INFINITY;
}

// What libxdf_summary prints for `path`; null (and a test failure) if libxdf rejects the file.
json libxdf_read(const std::string& path) {
    const std::string cmd = std::string(FOVEA_LIBXDF_SUMMARY) + " '" + path + "' 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) {
        ADD_FAILURE() << "cannot run " << cmd;
        return nullptr;
    }
    std::string out;
    char b[65536];
    std::size_t n;
    while ((n = std::fread(b, 1, sizeof b, p)) > 0) out.append(b, n);
    const int rc = ::pclose(p);
    if (rc != 0) {
        ADD_FAILURE() << "libxdf rejected " << path << ": " << out;
        return nullptr;
    }
    json j = json::parse(out, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded()) ADD_FAILURE() << "libxdf_summary printed no JSON: " << out.substr(0, 500);
    return j;
}

}  // namespace

void expect_libxdf_agrees(const std::string& path, bool require_footers) {
    auto ours = xdf::read_file(path);
    ASSERT_TRUE(ours.ok()) << path << ": " << ours.error().message;
    const json theirs = libxdf_read(path);
    ASSERT_TRUE(theirs.is_object());
    const json& streams = theirs["streams"];
    ASSERT_EQ(streams.size(), ours->streams.size()) << path;
    for (std::size_t k = 0; k < ours->streams.size(); ++k) {
        const xdf::Stream& o = ours->streams[k];
        const json& t = streams[k];
        SCOPED_TRACE(path + ", stream " + o.name);
        EXPECT_EQ(t["name"], o.name);
        EXPECT_EQ(t["type"], o.type);
        EXPECT_EQ(t["channel_count"], o.channel_count);
        EXPECT_EQ(t["channel_format"], xdf::format_name(o.format));
        EXPECT_EQ(t["nominal_srate"].get<double>(), o.nominal_srate);
        EXPECT_EQ(t["labels"], json(o.labels));
        const json& stamps = t["time_stamps"];
        ASSERT_EQ(stamps.size(), o.sample_count());
        for (std::size_t i = 0; i < o.sample_count(); ++i)
            ASSERT_EQ(number(stamps[i]), o.stamps[i]) << "time stamp of sample " << i;
        if (o.format != xdf::Format::kString && o.sample_count() > 0) {
            const json& series = t["time_series"];  // libxdf keeps every channel as float
            ASSERT_EQ(series.size(), static_cast<std::size_t>(o.channel_count));
            for (int c = 0; c < o.channel_count; ++c) {
                const json& column = series[static_cast<std::size_t>(c)];
                ASSERT_EQ(column.size(), o.sample_count()) << "channel " << c;
                for (std::size_t i = 0; i < o.sample_count(); ++i) {
                    const float want = static_cast<float>(o.value(i, c));
                    const double got = number(column[i]);
                    ASSERT_TRUE(std::isnan(want) ? std::isnan(got) : got == want)
                        << "channel " << c << " sample " << i << ": libxdf " << got << ", ours "
                        << want;
                }
            }
        }
        if (require_footers) {
            EXPECT_TRUE(t["has_footer"].get<bool>()) << "no StreamFooter";
            EXPECT_EQ(t["footer_sample_count"], o.sample_count()) << "footer sample_count";
        }
    }
}

}  // namespace fovea::record::test
