// glTF 2.0 / GLB content on the CPU, ready to upload: every triangle primitive of the scene's
// node hierarchy with its world transform, the metallic-roughness materials (normal maps, alpha
// mask, KHR_materials_emissive_strength / _ior / _specular read; other extensions fall back to
// the core model their defaults reduce to), and the decoded textures. Loading is tinygltf's
// (Debian's libtinygltf-dev), which also decodes PNG/JPEG with stb_image.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "gltf_viewer/math.hpp"

namespace gltfv {

struct Vertex {
    float position[3];
    float normal[3];
    float tangent[4];  // xyz, w = bitangent sign
    float uv[2];
};
static_assert(sizeof(Vertex) == 48);

// std430 mirror of shaders/viewer_common.glsl Material.
struct MaterialGpu {
    float base_color[4];
    float emissive[3];
    float metallic;
    float roughness;
    float normal_scale;
    float occlusion_strength;
    float alpha_cutoff;  // alpha mask; < 0: opaque
    int32_t base_tex = -1, mr_tex = -1, normal_tex = -1, occlusion_tex = -1;
    int32_t emissive_tex = -1;
    float f0 = 0.04f;  // dielectric reflectance from KHR_materials_ior/_specular
    float pad[2]{};
};
static_assert(sizeof(MaterialGpu) == 80);

struct TextureData {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba;  // 8-bit RGBA, top row first
    bool srgb = false;          // base colour and emissive
};

struct Primitive {
    uint32_t first_index = 0, index_count = 0;
    uint32_t material = 0;
    Mat4 world = identity();
    bool double_sided = false;
};

// One glTF file: its primitives in model space (node transforms applied).
struct Model {
    std::string path;
    std::vector<Vertex> vertices;
    std::vector<uint32_t> indices;  // into `vertices`
    std::vector<MaterialGpu> materials;
    std::vector<TextureData> textures;
    std::vector<Primitive> primitives;
    Vec3 bounds_min{1e30f, 1e30f, 1e30f}, bounds_max{-1e30f, -1e30f, -1e30f};
    uint32_t skipped_primitives = 0;  // not triangles, or without positions
};

// Loads the default scene of `path` (.gltf or .glb). Returns an empty string or the error;
// warnings (unsupported features) go to `warnings`.
std::string load_gltf(const std::string& path, Model& model, std::vector<std::string>& warnings);

// Everything the renderer draws: models' data once each, placed instances of them.
struct CpuScene {
    std::vector<Vertex> vertices;
    std::vector<uint32_t> indices;  // absolute into `vertices`
    std::vector<MaterialGpu> materials;
    std::vector<TextureData> textures;
    std::vector<Primitive> primitives;  // world transforms
    Vec3 bounds_min{1e30f, 1e30f, 1e30f}, bounds_max{-1e30f, -1e30f, -1e30f};

    // Adds an instance of `model` (its data copied on its first instance only). `fit` > 0 scales
    // it so its largest bounding-box edge is `fit` units, centred on x/z with its base at y = 0,
    // before `placement`.
    void add_instance(const Model& model, const Mat4& placement, float fit);

private:
    struct Bases {
        uint32_t index, material;
    };
    std::vector<std::pair<const Model*, Bases>> added_;
};

}  // namespace gltfv
