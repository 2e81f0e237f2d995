// IEEE 754 binary16 ("half") conversions for the rgba16f / rg16f / r16f images a host uploads to
// or reads back from the foveation module. Header-only, no state: any thread.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace fovea {

// f rounded to the nearest half and widened back: round-to-nearest-even, overflow to ±inf,
// subnormal halves kept, NaN and ±inf unchanged. What a float stored in a 16-bit float image
// reads back as, so CPU models can run the same arithmetic as the GPU storage.
inline float round_to_half(float f) {
    if (!std::isfinite(f)) return f;
    const float a = std::fabs(f);
    if (a >= 65520.0f) return std::copysign(INFINITY, f);  // halfway past 65504 rounds up
    if (a < 6.103515625e-05f) {                            // subnormal half: spacing 2^-24
        return std::copysign(std::nearbyint(a * 16777216.0f) / 16777216.0f, f);
    }
    int e = 0;
    std::frexp(a, &e);                           // a = m·2^e, m in [0.5, 1)
    const float ulp = std::ldexp(1.0f, e - 11);  // 10 stored mantissa bits + the implicit one
    return std::copysign(std::nearbyint(a / ulp) * ulp, f);
}

// The binary16 bit pattern of round_to_half(f). A NaN stays a (quiet) NaN, its sign kept.
inline std::uint16_t half_bits(float f) {
    const float r = round_to_half(f);
    std::uint32_t b;
    std::memcpy(&b, &r, 4);
    const std::uint32_t sign = (b >> 16) & 0x8000u;
    const std::uint32_t exp = (b >> 23) & 0xffu;
    const std::uint32_t man = b & 0x7fffffu;
    if (exp == 0xff) return std::uint16_t(sign | 0x7c00u | (man ? 0x200u | (man >> 13) : 0u));
    const int e = int(exp) - 127 + 15;
    if (e >= 31) return std::uint16_t(sign | 0x7c00u);
    if (e <= 0) {  // subnormal: r is already on the 2^-24 grid
        return std::uint16_t(sign | std::uint32_t(std::fabs(r) * 16777216.0f));
    }
    return std::uint16_t(sign | std::uint32_t(e) << 10 | man >> 13);
}

// The float a binary16 bit pattern stands for (exact: every half is a float).
inline float half_from_bits(std::uint16_t h) {
    const std::uint32_t sign = std::uint32_t(h & 0x8000u) << 16;
    const std::uint32_t exp = (h >> 10) & 0x1fu;
    const std::uint32_t man = h & 0x3ffu;
    if (exp == 0) {
        const float f = float(man) / 16777216.0f;
        return sign ? -f : f;
    }
    const std::uint32_t b =
        exp == 31 ? (sign | 0x7f800000u | man << 13) : (sign | (exp - 15 + 127) << 23 | man << 13);
    float f;
    std::memcpy(&f, &b, 4);
    return f;
}

// Reads one half from possibly unaligned bytes (a tightly packed read-back).
inline float half_from_bytes(const void* p) {
    std::uint16_t h;
    std::memcpy(&h, p, 2);
    return half_from_bits(h);
}

}  // namespace fovea
