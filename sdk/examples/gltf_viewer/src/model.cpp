#include "gltf_viewer/model.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include <tiny_gltf.h>

namespace gltfv {
namespace {

// Reads accessor `index` as `n` floats per element (normalized integers mapped to 0..1).
bool read_floats(const tinygltf::Model& m, int index, int n, std::vector<float>& out) {
    if (index < 0 || index >= int(m.accessors.size())) return false;
    const tinygltf::Accessor& a = m.accessors[size_t(index)];
    if (a.bufferView < 0 || a.sparse.isSparse) return false;
    const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
    const tinygltf::Buffer& b = m.buffers[size_t(v.buffer)];
    const int comps = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    const int csize = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (comps < n || csize <= 0) return false;
    const int stride = a.ByteStride(v);
    if (stride <= 0) return false;
    const size_t base = v.byteOffset + a.byteOffset;
    if (a.count > 0 &&
        base + size_t(stride) * (a.count - 1) + size_t(comps * csize) > b.data.size())
        return false;
    out.resize(a.count * size_t(n));
    for (size_t i = 0; i < a.count; ++i) {
        const unsigned char* p = b.data.data() + base + i * size_t(stride);
        for (int c = 0; c < n; ++c) {
            const unsigned char* q = p + c * csize;
            float f = 0.f;
            switch (a.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&f, q, 4); break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: f = float(*q) / 255.f; break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                    uint16_t u;
                    std::memcpy(&u, q, 2);
                    f = float(u) / 65535.f;
                    break;
                }
                default: return false;
            }
            out[i * size_t(n) + size_t(c)] = f;
        }
    }
    return true;
}

bool read_indices(const tinygltf::Model& m, int index, std::vector<uint32_t>& out) {
    const tinygltf::Accessor& a = m.accessors[size_t(index)];
    if (a.bufferView < 0 || a.sparse.isSparse) return false;
    const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
    const tinygltf::Buffer& b = m.buffers[size_t(v.buffer)];
    const int csize = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    const int stride = v.byteStride ? int(v.byteStride) : csize;
    const size_t base = v.byteOffset + a.byteOffset;
    if (a.count > 0 && base + size_t(stride) * (a.count - 1) + size_t(csize) > b.data.size())
        return false;
    out.resize(a.count);
    for (size_t i = 0; i < a.count; ++i) {
        const unsigned char* p = b.data.data() + base + i * size_t(stride);
        switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: out[i] = *p; break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t u;
                std::memcpy(&u, p, 2);
                out[i] = u;
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: std::memcpy(&out[i], p, 4); break;
            default: return false;
        }
    }
    return true;
}

Mat4 node_matrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
        Mat4 m;
        for (int i = 0; i < 16; ++i) m[size_t(i)] = float(n.matrix[size_t(i)]);
        return m;
    }
    Vec3 t{0, 0, 0}, s{1, 1, 1};
    std::array<float, 4> q{0, 0, 0, 1};
    for (size_t i = 0; i < n.translation.size() && i < 3; ++i) t[i] = float(n.translation[i]);
    for (size_t i = 0; i < n.scale.size() && i < 3; ++i) s[i] = float(n.scale[i]);
    for (size_t i = 0; i < n.rotation.size() && i < 4; ++i) q[i] = float(n.rotation[i]);
    return trs(t, q, s);
}

// Per-vertex tangents from the UV gradients of the faces around each vertex (Lengyel 2001),
// orthogonalized against the normal; handedness in w.
void generate_tangents(std::vector<Vertex>& v, const std::vector<uint32_t>& idx, size_t first) {
    std::vector<Vec3> tan(v.size() - first, {0, 0, 0}), bit(v.size() - first, {0, 0, 0});
    for (size_t i = 0; i + 2 < idx.size(); i += 3) {
        const uint32_t a = idx[i], b = idx[i + 1], c = idx[i + 2];
        const Vertex &va = v[a], &vb = v[b], &vc = v[c];
        const Vec3 e1 = Vec3{vb.position[0], vb.position[1], vb.position[2]} -
                        Vec3{va.position[0], va.position[1], va.position[2]};
        const Vec3 e2 = Vec3{vc.position[0], vc.position[1], vc.position[2]} -
                        Vec3{va.position[0], va.position[1], va.position[2]};
        const float du1 = vb.uv[0] - va.uv[0], dv1 = vb.uv[1] - va.uv[1];
        const float du2 = vc.uv[0] - va.uv[0], dv2 = vc.uv[1] - va.uv[1];
        const float det = du1 * dv2 - du2 * dv1;
        if (std::abs(det) < 1e-12f) continue;
        const float r = 1.f / det;
        const Vec3 t = (e1 * dv2 - e2 * dv1) * r, bt = (e2 * du1 - e1 * du2) * r;
        for (uint32_t k : {a, b, c}) {
            tan[k - first] = tan[k - first] + t;
            bit[k - first] = bit[k - first] + bt;
        }
    }
    for (size_t i = first; i < v.size(); ++i) {
        const Vec3 n{v[i].normal[0], v[i].normal[1], v[i].normal[2]};
        Vec3 t = tan[i - first] - n * dot(n, tan[i - first]);
        if (length(t) < 1e-8f)
            t = std::abs(n[0]) < 0.9f ? cross(n, {1, 0, 0}) : cross(n, {0, 1, 0});
        t = normalize(t);
        const float w = dot(cross(n, t), bit[i - first]) < 0.f ? -1.f : 1.f;
        v[i].tangent[0] = t[0];
        v[i].tangent[1] = t[1];
        v[i].tangent[2] = t[2];
        v[i].tangent[3] = w;
    }
}

// Area-weighted face normals where the mesh has none.
void generate_normals(std::vector<Vertex>& v, const std::vector<uint32_t>& idx, size_t first) {
    std::vector<Vec3> n(v.size() - first, {0, 0, 0});
    for (size_t i = 0; i + 2 < idx.size(); i += 3) {
        const Vertex &a = v[idx[i]], &b = v[idx[i + 1]], &c = v[idx[i + 2]];
        const Vec3 e1 = Vec3{b.position[0], b.position[1], b.position[2]} -
                        Vec3{a.position[0], a.position[1], a.position[2]};
        const Vec3 e2 = Vec3{c.position[0], c.position[1], c.position[2]} -
                        Vec3{a.position[0], a.position[1], a.position[2]};
        const Vec3 f = cross(e1, e2);
        for (size_t k = 0; k < 3; ++k) n[idx[i + k] - first] = n[idx[i + k] - first] + f;
    }
    for (size_t i = first; i < v.size(); ++i) {
        const Vec3 u = normalize(n[i - first]);
        std::memcpy(v[i].normal, u.data(), sizeof(v[i].normal));
    }
}

struct Loader {
    const tinygltf::Model& m;
    Model& scene;
    std::vector<std::string>& warnings;
    uint32_t material_base = 0;
    std::map<std::pair<int, bool>, int32_t> textures;  // (glTF texture, sRGB) -> scene index

    int32_t texture(int gltf_index, bool srgb) {
        if (gltf_index < 0 || gltf_index >= int(m.textures.size())) return -1;
        if (auto it = textures.find({gltf_index, srgb}); it != textures.end()) return it->second;
        const tinygltf::Texture& t = m.textures[size_t(gltf_index)];
        if (t.source < 0 || t.source >= int(m.images.size())) return -1;
        const tinygltf::Image& im = m.images[size_t(t.source)];
        if (im.width <= 0 || im.height <= 0 || im.image.empty() || im.component < 1) {
            warnings.push_back("image '" + im.uri + "' could not be decoded; texture ignored");
            return -1;
        }
        TextureData d;
        d.width = uint32_t(im.width);
        d.height = uint32_t(im.height);
        d.srgb = srgb;
        d.rgba.resize(size_t(d.width) * d.height * 4);
        const size_t bytes = im.bits == 16 ? 2 : 1;
        for (size_t p = 0; p < size_t(d.width) * d.height; ++p)
            for (int c = 0; c < 4; ++c) {
                uint8_t value = 255;
                if (c < im.component) {
                    const size_t at = (p * size_t(im.component) + size_t(c)) * bytes;
                    value = bytes == 2 ? im.image[at + 1] : im.image[at];  // 16-bit: high byte
                } else if (c < 3 && im.component < 3) {
                    value = im.image[p * size_t(im.component) * bytes];  // grey
                }
                d.rgba[p * 4 + size_t(c)] = value;
            }
        if (t.sampler >= 0 && t.sampler < int(m.samplers.size()) &&
            (m.samplers[size_t(t.sampler)].wrapS != TINYGLTF_TEXTURE_WRAP_REPEAT ||
             m.samplers[size_t(t.sampler)].wrapT != TINYGLTF_TEXTURE_WRAP_REPEAT))
            warnings.push_back("texture " + std::to_string(gltf_index) +
                               ": wrap mode other than REPEAT drawn as REPEAT");
        const int32_t index = int32_t(scene.textures.size());
        scene.textures.push_back(std::move(d));
        textures[{gltf_index, srgb}] = index;
        return index;
    }

    void materials() {
        material_base = uint32_t(scene.materials.size());
        for (const tinygltf::Material& src : m.materials) {
            MaterialGpu g{};
            const auto& pbr = src.pbrMetallicRoughness;
            for (int i = 0; i < 4; ++i)
                g.base_color[i] = i < int(pbr.baseColorFactor.size())
                                      ? float(pbr.baseColorFactor[size_t(i)])
                                      : 1.f;
            float strength = 1.f;
            if (auto it = src.extensions.find("KHR_materials_emissive_strength");
                it != src.extensions.end() && it->second.Has("emissiveStrength"))
                strength = float(it->second.Get("emissiveStrength").GetNumberAsDouble());
            for (int i = 0; i < 3; ++i)
                g.emissive[i] =
                    (i < int(src.emissiveFactor.size()) ? float(src.emissiveFactor[size_t(i)])
                                                        : 0.f) *
                    strength;
            g.metallic = float(pbr.metallicFactor);
            g.roughness = float(pbr.roughnessFactor);
            g.normal_scale = float(src.normalTexture.scale);
            g.occlusion_strength = float(src.occlusionTexture.strength);
            g.alpha_cutoff = src.alphaMode == "MASK" ? float(src.alphaCutoff) : -1.f;
            if (src.alphaMode == "BLEND") {
                g.alpha_cutoff = 0.5f;
                warnings.push_back("material '" + src.name +
                                   "': alpha BLEND drawn as MASK at 0.5 (no sorted transparency)");
            }
            // KHR_materials_ior (default 1.5) and _specular (default 1) set the dielectric F0.
            double ior = 1.5, specular = 1.0;
            if (auto it = src.extensions.find("KHR_materials_ior");
                it != src.extensions.end() && it->second.Has("ior"))
                ior = it->second.Get("ior").GetNumberAsDouble();
            if (auto it = src.extensions.find("KHR_materials_specular");
                it != src.extensions.end() && it->second.Has("specularFactor"))
                specular = it->second.Get("specularFactor").GetNumberAsDouble();
            const double r = (ior - 1.0) / (ior + 1.0);
            g.f0 = float(std::min(1.0, r * r * specular));
            g.base_tex = texture(pbr.baseColorTexture.index, true);
            g.mr_tex = texture(pbr.metallicRoughnessTexture.index, false);
            g.normal_tex = texture(src.normalTexture.index, false);
            g.occlusion_tex = texture(src.occlusionTexture.index, false);
            g.emissive_tex = texture(src.emissiveTexture.index, true);
            for (const auto& [name, value] : src.extensions)
                if (name != "KHR_materials_emissive_strength" && name != "KHR_materials_ior" &&
                    name != "KHR_materials_specular")
                    warnings.push_back("material '" + src.name + "': " + name +
                                       " not implemented, core metallic-roughness used");
            scene.materials.push_back(g);
        }
        // The default material for primitives without one (glTF §3.9.6).
        MaterialGpu def{};
        for (float& c : def.base_color) c = 1.f;
        def.metallic = def.roughness = 1.f;
        def.normal_scale = def.occlusion_strength = 1.f;
        def.alpha_cutoff = -1.f;
        scene.materials.push_back(def);
    }

    void primitive(const tinygltf::Primitive& p, const Mat4& world) {
        const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
        auto pos_it = p.attributes.find("POSITION");
        std::vector<float> pos, nrm, tan, uv;
        if (mode != TINYGLTF_MODE_TRIANGLES || pos_it == p.attributes.end() ||
            !read_floats(m, pos_it->second, 3, pos)) {
            ++scene.skipped_primitives;
            return;
        }
        const size_t n = pos.size() / 3, first = scene.vertices.size();
        const auto attr = [&](const char* name, int comps, std::vector<float>& out) {
            auto it = p.attributes.find(name);
            return it != p.attributes.end() && read_floats(m, it->second, comps, out) &&
                   out.size() == n * size_t(comps);
        };
        const bool has_n = attr("NORMAL", 3, nrm), has_t = attr("TANGENT", 4, tan);
        const bool has_uv = attr("TEXCOORD_0", 2, uv);
        std::vector<uint32_t> local;
        if (p.indices >= 0) {
            if (!read_indices(m, p.indices, local)) {
                ++scene.skipped_primitives;
                return;
            }
        } else {
            local.resize(n);
            for (size_t i = 0; i < n; ++i) local[i] = uint32_t(i);
        }
        for (uint32_t& i : local) {
            if (i >= n) {
                ++scene.skipped_primitives;
                return;
            }
            i += uint32_t(first);
        }
        for (size_t i = 0; i < n; ++i) {
            Vertex v{};
            std::memcpy(v.position, &pos[i * 3], 12);
            if (has_n) std::memcpy(v.normal, &nrm[i * 3], 12);
            if (has_t) std::memcpy(v.tangent, &tan[i * 4], 16);
            if (has_uv) std::memcpy(v.uv, &uv[i * 2], 8);
            scene.vertices.push_back(v);
            const Vec3 w = transform_point(world, {v.position[0], v.position[1], v.position[2]});
            for (int k = 0; k < 3; ++k) {
                scene.bounds_min[k] = std::min(scene.bounds_min[k], w[k]);
                scene.bounds_max[k] = std::max(scene.bounds_max[k], w[k]);
            }
        }
        if (!has_n) generate_normals(scene.vertices, local, first);
        if (!has_t) generate_tangents(scene.vertices, local, first);
        Primitive out;
        out.first_index = uint32_t(scene.indices.size());
        out.index_count = uint32_t(local.size());
        const bool has_material = p.material >= 0 && p.material < int(m.materials.size());
        out.material = has_material ? material_base + uint32_t(p.material)
                                    : material_base + uint32_t(m.materials.size());
        out.double_sided = has_material && m.materials[size_t(p.material)].doubleSided;
        out.world = world;
        scene.indices.insert(scene.indices.end(), local.begin(), local.end());
        scene.primitives.push_back(out);
    }

    void node(int index, const Mat4& parent, int depth) {
        if (index < 0 || index >= int(m.nodes.size()) || depth > 64) return;  // cycles, bad refs
        const tinygltf::Node& nd = m.nodes[size_t(index)];
        const Mat4 world = multiply(parent, node_matrix(nd));
        if (nd.mesh >= 0 && nd.mesh < int(m.meshes.size()))
            for (const tinygltf::Primitive& p : m.meshes[size_t(nd.mesh)].primitives)
                primitive(p, world);
        for (int c : nd.children) node(c, world, depth + 1);
    }
};

}  // namespace

std::string load_gltf(const std::string& path, Model& model, std::vector<std::string>& warnings) {
    tinygltf::TinyGLTF loader;
    tinygltf::Model gltf;
    std::string err, warn;
    const bool glb = path.size() > 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
    const bool ok = glb ? loader.LoadBinaryFromFile(&gltf, &err, &warn, path)
                        : loader.LoadASCIIFromFile(&gltf, &err, &warn, path);
    if (!warn.empty()) warnings.push_back(path + ": " + warn);
    if (!ok) return path + ": " + (err.empty() ? "not a glTF file" : err);
    std::vector<int> roots;
    const int s = gltf.defaultScene >= 0 ? gltf.defaultScene : 0;
    if (s < int(gltf.scenes.size())) roots = gltf.scenes[size_t(s)].nodes;
    if (roots.empty())  // no scene: every node no other node names as a child
        for (size_t i = 0; i < gltf.nodes.size(); ++i) {
            bool child = false;
            for (const auto& n : gltf.nodes)
                child |= std::count(n.children.begin(), n.children.end(), int(i)) > 0;
            if (!child) roots.push_back(int(i));
        }
    model = Model{};
    model.path = path;
    Loader l{gltf, model, warnings};
    l.materials();
    for (int r : roots) l.node(r, identity(), 0);
    if (model.primitives.empty()) return path + ": no triangle primitives";
    if (model.skipped_primitives > 0)
        warnings.push_back(path + ": " + std::to_string(model.skipped_primitives) +
                           " primitives skipped (not triangles, or unreadable accessors)");
    return {};
}

void CpuScene::add_instance(const Model& model, const Mat4& placement, float fit) {
    auto it = std::find_if(added_.begin(), added_.end(),
                           [&](const auto& a) { return a.first == &model; });
    if (it == added_.end()) {
        const Bases b{uint32_t(indices.size()), uint32_t(materials.size())};
        const uint32_t vbase = uint32_t(vertices.size());
        const int32_t tbase = int32_t(textures.size());
        vertices.insert(vertices.end(), model.vertices.begin(), model.vertices.end());
        for (uint32_t i : model.indices) indices.push_back(i + vbase);
        for (MaterialGpu g : model.materials) {
            for (int32_t* t :
                 {&g.base_tex, &g.mr_tex, &g.normal_tex, &g.occlusion_tex, &g.emissive_tex})
                if (*t >= 0) *t += tbase;
            materials.push_back(g);
        }
        textures.insert(textures.end(), model.textures.begin(), model.textures.end());
        added_.push_back({&model, b});
        it = added_.end() - 1;
    }
    Mat4 pre = identity();
    if (fit > 0.f) {
        const Vec3 size = model.bounds_max - model.bounds_min;
        const float edge = std::max({size[0], size[1], size[2]});
        const float k = edge > 0.f ? fit / edge : 1.f;
        const Vec3 c = (model.bounds_min + model.bounds_max) * 0.5f;
        pre = multiply(trs({0, 0, 0}, {0, 0, 0, 1}, {k, k, k}),
                       trs({-c[0], -model.bounds_min[1], -c[2]}, {0, 0, 0, 1}, {1, 1, 1}));
    }
    const Mat4 place = multiply(placement, pre);
    for (Primitive p : model.primitives) {
        p.first_index += it->second.index;
        p.material += it->second.material;
        p.world = multiply(place, p.world);
        primitives.push_back(p);
    }
    for (int corner = 0; corner < 8; ++corner) {  // the placed model's box, conservatively
        const Vec3 local{corner & 1 ? model.bounds_max[0] : model.bounds_min[0],
                         corner & 2 ? model.bounds_max[1] : model.bounds_min[1],
                         corner & 4 ? model.bounds_max[2] : model.bounds_min[2]};
        const Vec3 w = transform_point(place, local);
        for (int k = 0; k < 3; ++k) {
            bounds_min[k] = std::min(bounds_min[k], w[k]);
            bounds_max[k] = std::max(bounds_max[k], w[k]);
        }
    }
}

}  // namespace gltfv
