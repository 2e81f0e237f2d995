// fovea/json_integer.hpp: integers from outside JSON are read only when they are integers in range,
// never through nlohmann's get<integer>() of a float (undefined behaviour, not an exception).
#include "fovea/json_integer.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

using fovea::json_count;
using fovea::json_integer;
using nlohmann::json;

TEST(JsonInteger, AcceptsOnlyIntegersWithinTheRange) {
    EXPECT_EQ(json_integer(json(7), 0, 10), 7);
    EXPECT_EQ(json_integer(json(-7), -10, 10), -7);
    EXPECT_EQ(json_integer(json(10u), 0, 10), 10);
    EXPECT_FALSE(json_integer(json(11), 0, 10));
    EXPECT_FALSE(json_integer(json(-1), 0, 10));
    EXPECT_FALSE(json_integer(json(std::numeric_limits<uint64_t>::max()), 0, INT64_MAX));
    EXPECT_EQ(json_integer(json(uint64_t{INT64_MAX}), 0, INT64_MAX), INT64_MAX);
    EXPECT_FALSE(json_integer(json(5u), -10, -1));
}

TEST(JsonInteger, FloatsStringsBoolsAndNullAreNotIntegers) {
    for (const json& v : {json(1e300), json(2.5), json(3.0), json(-1e300), json("3"), json(true),
                          json(nullptr), json::array({1}), json::object()}) {
        EXPECT_FALSE(json_integer(v, INT64_MIN, INT64_MAX)) << v.dump();
        EXPECT_FALSE(json_count(v)) << v.dump();
    }
}

TEST(JsonInteger, CountsAreNonNegativeOverTheWholeUnsignedRange) {
    EXPECT_EQ(json_count(json(0)), 0u);
    EXPECT_EQ(json_count(json(std::numeric_limits<uint64_t>::max())),
              std::numeric_limits<uint64_t>::max());
    EXPECT_FALSE(json_count(json(-1)));
    const json j = {{"n", 4}, {"bad", 4.5}};
    EXPECT_EQ(json_count(j, "n", 9), 4u);
    EXPECT_EQ(json_count(j, "absent", 9), 9u);
    EXPECT_FALSE(json_count(j, "bad", 9));
}
