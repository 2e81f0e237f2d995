// fovea/half.hpp against the compiler's own IEEE binary16 (_Float16, round-to-nearest-even):
// every half bit pattern one way, a dense sweep of float bit patterns the other.
#include "fovea/half.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>

namespace {

std::uint16_t reference_bits(float f) {
    const _Float16 h = static_cast<_Float16>(f);
    std::uint16_t b;
    std::memcpy(&b, &h, 2);
    return b;
}

float from_float_bits(std::uint32_t b) {
    float f;
    std::memcpy(&f, &b, 4);
    return f;
}

bool same_float(float a, float b) {
    return std::memcmp(&a, &b, 4) == 0 || (std::isnan(a) && std::isnan(b));
}

TEST(Half, EveryHalfBitPatternWidensExactlyAndNarrowsBackToItself) {
    for (std::uint32_t h = 0; h <= 0xffffu; ++h) {
        _Float16 ref;
        const std::uint16_t bits = std::uint16_t(h);
        std::memcpy(&ref, &bits, 2);
        const float f = fovea::half_from_bits(bits);
        ASSERT_TRUE(same_float(f, static_cast<float>(ref))) << std::hex << h;
        if (!std::isnan(f)) { ASSERT_EQ(fovea::half_bits(f), bits) << std::hex << h; }
    }
}

// The rounding decision lives in the low 13 mantissa bits (more for results that are subnormal
// halves): every sign, exponent and top-10 mantissa, with the low bits at the tie, one either
// side of it, and at both ends; then a prime stride through all 2^32 patterns.
TEST(Half, FloatsRoundToNearestEvenLikeTheCompilersHalf) {
    const std::uint32_t lows[] = {0x0000, 0x0001, 0x0fff, 0x1000, 0x1001, 0x1fff};
    for (std::uint32_t high = 0; high < (1u << 19); ++high) {
        for (const std::uint32_t low : lows) {
            const float f = from_float_bits(high << 13 | low);
            ASSERT_EQ(fovea::half_bits(f), reference_bits(f)) << f;
        }
    }
    for (std::uint64_t b = 0; b <= 0xffffffffu; b += 257) {
        const float f = from_float_bits(std::uint32_t(b));
        ASSERT_EQ(fovea::half_bits(f), reference_bits(f)) << std::hex << b;
    }
}

TEST(Half, RoundToHalfIsTheValueTheBitsStandFor) {
    for (std::uint64_t b = 0; b <= 0xffffffffu; b += 1009) {
        const float f = from_float_bits(std::uint32_t(b));
        const float r = fovea::round_to_half(f);
        ASSERT_TRUE(same_float(r, fovea::half_from_bits(fovea::half_bits(f)))) << f;
    }
}

TEST(Half, EdgesOfTheRange) {
    EXPECT_EQ(fovea::half_bits(65504.0f), 0x7bffu);    // largest half
    EXPECT_EQ(fovea::half_bits(65519.996f), 0x7bffu);  // just under the tie
    EXPECT_EQ(fovea::half_bits(65520.0f), 0x7c00u);    // tie, to even: inf
    EXPECT_EQ(fovea::half_bits(-INFINITY), 0xfc00u);
    EXPECT_EQ(fovea::half_bits(std::ldexp(1.0f, -24)), 0x0001u);  // smallest subnormal
    EXPECT_EQ(fovea::half_bits(std::ldexp(1.0f, -25)), 0x0000u);  // tie, to even: zero
    EXPECT_EQ(fovea::half_bits(std::ldexp(1.5f, -25)), 0x0001u);
    EXPECT_EQ(fovea::half_bits(-0.0f), 0x8000u);
    EXPECT_TRUE(std::isnan(fovea::half_from_bits(fovea::half_bits(NAN))));
    const unsigned char bytes[3] = {0xff, 0x00, 0x3c};  // 1.0 at an odd address
    EXPECT_EQ(fovea::half_from_bytes(bytes + 1), 1.0f);
}

}  // namespace
