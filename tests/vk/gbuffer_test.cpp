// The packed G-buffer surface texel (gbuffer.hpp, shaders/fovea_gbuffer.glsl): what a host packs
// is what a shading function reads, the CPU packer agrees with the GLSL one bit for bit, and the
// octahedral normal stays within a tiny angle everywhere, including its fold and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "fovea/vk/gbuffer.hpp"
#include "gpu.hpp"
#include "shader_compiler.hpp"
#include "vk_test_util.hpp"

namespace fovea::vk {
namespace {

double angle_deg(const std::array<float, 3>& a, const std::array<double, 3>& b) {
    const double la = std::sqrt(double(a[0]) * a[0] + double(a[1]) * a[1] + double(a[2]) * a[2]);
    const double lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
    c = std::clamp(c, -1.0, 1.0);
    return std::acos(c) * 180.0 / M_PI;
}

// Normals that stress the encoding: uniform on the sphere, the six axes, the fold (z ~ 0, either
// sign), the poles' neighbourhood, and lengths far from 1.
std::vector<std::array<double, 3>> hard_normals() {
    std::vector<std::array<double, 3>> v;
    std::mt19937 rng(7);
    std::normal_distribution<double> g;
    for (int i = 0; i < 20000; ++i) v.push_back({g(rng), g(rng), g(rng)});
    for (int a = 0; a < 3; ++a)
        for (double s : {1.0, -1.0}) {
            std::array<double, 3> n{0, 0, 0};
            n[size_t(a)] = s;
            v.push_back(n);
        }
    std::uniform_real_distribution<double> u(-M_PI, M_PI);
    for (int i = 0; i < 2000; ++i) {
        const double phi = u(rng);
        for (double z : {0.0, 1e-7, -1e-7, 1e-3, -1e-3, 0.9999999, -0.9999999})
            v.push_back({std::cos(phi), std::sin(phi), z});
    }
    for (size_t i = 0; i < 200; ++i)
        for (double scale : {1e-30, 1e-3, 7.0, 1e30}) {
            auto s = v[i];
            for (double& c : s) c *= scale;
            v.push_back(s);
        }
    return v;
}

TEST(GBufferSurface, OctahedralNormalWithinATinyAngleEverywhere) {
    double worst = 0.0;
    for (const auto& n : hard_normals()) {
        SurfaceSample s;
        s.normal = {float(n[0]), float(n[1]), float(n[2])};
        const SurfaceSample back = unpack_surface(pack_surface(s));
        const double len = std::hypot(back.normal[0], back.normal[1], back.normal[2]);
        ASSERT_NEAR(len, 1.0, 1e-6);
        worst = std::max(worst, angle_deg(back.normal, n));
    }
    // 16-bit octahedral; the old RGBA16F normal rounded each component to 11 bits (~0.03 deg).
    std::printf("worst octahedral normal error: %.5f deg\n", worst);
    EXPECT_LT(worst, 0.01);
}

TEST(GBufferSurface, DegenerateNormalsDecodeToPlusZ) {
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (const std::array<float, 3> n : {std::array<float, 3>{0.f, 0.f, 0.f},
                                         {nan, 0.f, 1.f},
                                         {inf, 0.f, 0.f},
                                         {-inf, inf, 1.f},
                                         {0.f, nan, nan}}) {
        SurfaceSample s;
        s.normal = n;
        const SurfaceSample back = unpack_surface(pack_surface(s));
        EXPECT_EQ(back.normal[0], 0.f);
        EXPECT_EQ(back.normal[1], 0.f);
        EXPECT_EQ(back.normal[2], 1.f);
    }
}

TEST(GBufferSurface, MaterialIdExactAlbedoAndHalvesAsStored) {
    for (uint32_t id : {0u, 1u, 2u, 11u, 2049u, 40000u, 65535u}) {
        SurfaceSample s;
        s.material = {float(id), 0.35f, 1.f, 17.f};
        s.albedo = {0.f, 0.5f, 1.f};
        s.albedo_a = 0.25f;
        const SurfaceSample back = unpack_surface(pack_surface(s));
        EXPECT_EQ(back.material[0], float(id));
        EXPECT_NEAR(back.material[1], 0.35f, 0.35f / 2048.f);  // a half: 11 significant bits
        EXPECT_EQ(back.material[2], 1.f);
        EXPECT_EQ(back.material[3], 17.f);
        EXPECT_EQ(back.albedo[0], 0.f);
        EXPECT_NEAR(back.albedo[1], 0.5f, 0.501f / 255.f);  // 127.5 rounds to even
        EXPECT_EQ(back.albedo[2], 1.f);
        EXPECT_EQ(back.albedo_a, 64.f / 255.f);
    }
    SurfaceSample out_of_range;
    out_of_range.material[0] = 1e9f;
    out_of_range.albedo = {-1.f, 2.f, std::numeric_limits<float>::quiet_NaN()};
    const SurfaceSample back = unpack_surface(pack_surface(out_of_range));
    EXPECT_EQ(back.material[0], 65535.f);
    EXPECT_EQ(back.albedo[0], 0.f);
    EXPECT_EQ(back.albedo[1], 1.f);
}

// Packs every input with fovea_pack_surface() and decodes the CPU-packed texels with the
// shader-side unpackers, as a host's G-buffer pass and fovea_frame.glsl do.
constexpr const char* kPackShader = R"(#version 450
#extension GL_GOOGLE_include_directive : require
#include "fovea_gbuffer.glsl"
layout(local_size_x = 64) in;
struct In { vec4 normal; vec4 albedo; vec4 material; };
layout(std430, set = 0, binding = 0) readonly buffer Inputs { In v[]; } inputs;
layout(std430, set = 0, binding = 1) readonly buffer CpuTexels { uvec4 t[]; } cpu;
layout(std430, set = 0, binding = 2) writeonly buffer Packed { uvec4 t[]; } packed;
struct Out { vec4 normal; vec4 albedo; vec4 material; };
layout(std430, set = 0, binding = 3) writeonly buffer Decoded { Out v[]; } decoded;
layout(push_constant) uniform Push { uint count; } pc;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    In s = inputs.v[i];
    packed.t[i] = fovea_pack_surface(s.normal.xyz, s.albedo.rgb, s.albedo.a, s.material);
    uvec4 t = cpu.t[i];
    decoded.v[i].normal = vec4(fovea_unpack_normal(t), 0.0);
    decoded.v[i].albedo = fovea_unpack_albedo(t);
    decoded.v[i].material = fovea_unpack_material(t);
}
)";

TEST(GBufferSurface, GpuPacksAndDecodesLikeTheCpu) {
    FOVEA_REQUIRE_DEVICE();
    std::vector<SurfaceSample> in;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (const auto& n : hard_normals()) {
        SurfaceSample s;
        s.normal = {float(n[0]), float(n[1]), float(n[2])};
        s.albedo = {u(rng), u(rng), u(rng)};
        s.albedo_a = u(rng);
        s.material = {std::floor(u(rng) * 70000.f), u(rng) * 4.f - 2.f, u(rng), u(rng) * 100.f};
        in.push_back(s);
    }
    const uint32_t count = uint32_t(in.size());
    struct Vec4x3 {
        float v[12];
    };
    Buffer inputs(*device, count * sizeof(Vec4x3), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
    Buffer cpu(*device, count * sizeof(SurfaceTexel), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
    Buffer packed(*device, count * sizeof(SurfaceTexel), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
    Buffer decoded(*device, count * sizeof(Vec4x3), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
    std::vector<SurfaceTexel> cpu_texels(count);
    for (uint32_t i = 0; i < count; ++i) {
        const SurfaceSample& s = in[i];
        const Vec4x3 v{{s.normal[0], s.normal[1], s.normal[2], 0.f, s.albedo[0], s.albedo[1],
                        s.albedo[2], s.albedo_a, s.material[0], s.material[1], s.material[2],
                        s.material[3]}};
        std::memcpy(static_cast<Vec4x3*>(inputs.data()) + i, &v, sizeof v);
        cpu_texels[i] = pack_surface(s);
    }
    std::memcpy(cpu.data(), cpu_texels.data(), count * sizeof(SurfaceTexel));

    auto spirv = compile_glsl(kPackShader, "gbuffer_pack_test");
    ASSERT_TRUE(spirv) << spirv.error().message;
    const Binding buf{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
    const Binding bindings[] = {buf, buf, buf, buf};
    ComputePipeline pipe(*device, *spirv, VK_NULL_HANDLE, bindings, sizeof(uint32_t));
    VkDescriptorSet set = pipe.allocate_set();
    DescriptorWriter(device->device(), set)
        .storage_buffer(0, inputs)
        .storage_buffer(1, cpu)
        .storage_buffer(2, packed)
        .storage_buffer(3, decoded)
        .commit();
    device->submit_and_wait([&](VkCommandBuffer cmd) {
        pipe.bind(cmd, VK_NULL_HANDLE, set, &count, sizeof count);
        vkCmdDispatch(cmd, div_up(count, 64), 1, 1);
    });

    const auto* gpu_texels = static_cast<const SurfaceTexel*>(packed.data());
    const auto* gpu_decoded = static_cast<const Vec4x3*>(decoded.data());
    int differing_texels = 0;
    float worst_decode = 0.f;
    for (uint32_t i = 0; i < count; ++i) {
        if (gpu_texels[i] != cpu_texels[i] && ++differing_texels <= 5)
            ADD_FAILURE() << "input " << i << ": GPU " << std::hex << gpu_texels[i][0] << ' '
                          << gpu_texels[i][1] << ' ' << gpu_texels[i][2] << ' ' << gpu_texels[i][3]
                          << ", CPU " << cpu_texels[i][0] << ' ' << cpu_texels[i][1] << ' '
                          << cpu_texels[i][2] << ' ' << cpu_texels[i][3];
        const SurfaceSample c = unpack_surface(cpu_texels[i]);
        const float* g = gpu_decoded[i].v;
        const float want[12] = {c.normal[0],   c.normal[1],   c.normal[2],   0.f,
                                c.albedo[0],   c.albedo[1],   c.albedo[2],   c.albedo_a,
                                c.material[0], c.material[1], c.material[2], c.material[3]};
        for (int k = 0; k < 12; ++k)
            worst_decode = std::max(worst_decode, std::fabs(g[k] - want[k]));
    }
    EXPECT_EQ(differing_texels, 0) << "of " << count;
    EXPECT_LT(worst_decode, 1e-6f);
    FOVEA_EXPECT_NO_VALIDATION_ERRORS();
}

}  // namespace
}  // namespace fovea::vk
