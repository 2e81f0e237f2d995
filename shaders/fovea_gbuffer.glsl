// The G-buffer's packed surface texel (sdk/include/fovea/vk/gbuffer.hpp): what a host's G-buffer
// pass writes into the surface image and what the module reads back. No bindings, so host
// fragment shaders include it as well as the module's compute shaders. Mirrored on the CPU by
// fovea::vk::pack_surface() / unpack_surface() (sdk/src/vk/gbuffer.cpp).
//   x  normal, octahedral (Cigolle et al. 2014), packSnorm2x16
//   y  albedo rgb + a (host-defined), packUnorm4x8
//   z  bits 0-15 material id (an integer, never blended), bits 16-31 material.y as a half
//   w  material.z, material.w as halves (packHalf2x16)
#ifndef FOVEA_GBUFFER_GLSL
#define FOVEA_GBUFFER_GLSL

// -1 or +1, never 0, so the fold maps the axes and the equator both ways consistently.
vec2 fovea_sign_not_zero(vec2 v) { return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0); }

// Any non-zero finite vector to its octahedral square [-1, 1]^2; zero or non-finite -> (0, 0),
// which decodes to +z.
vec2 fovea_oct_encode(vec3 n) {
    float l1 = abs(n.x) + abs(n.y) + abs(n.z);
    if (!(l1 > 0.0 && l1 < 3.0e38)) return vec2(0.0);
    vec2 p = n.xy / l1;
    return n.z >= 0.0 ? p : (1.0 - abs(p.yx)) * fovea_sign_not_zero(p);
}

// Unit vector from an octahedral square point.
vec3 fovea_oct_decode(vec2 e) {
    vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    float t = max(-v.z, 0.0);
    v.xy += vec2(v.x >= 0.0 ? -t : t, v.y >= 0.0 ? -t : t);
    return normalize(v);
}

// material.x is the id (rounded, 0..65535); yzw are stored as halves.
uvec4 fovea_pack_surface(vec3 normal, vec3 albedo, float albedo_a, vec4 material) {
    uint id = uint(clamp(material.x + 0.5, 0.0, 65535.0));
    return uvec4(packSnorm2x16(fovea_oct_encode(normal)), packUnorm4x8(vec4(albedo, albedo_a)),
                 id | (packHalf2x16(vec2(material.y, 0.0)) << 16),
                 packHalf2x16(material.zw));
}

vec3 fovea_unpack_normal(uvec4 s) { return fovea_oct_decode(unpackSnorm2x16(s.x)); }
vec4 fovea_unpack_albedo(uvec4 s) { return unpackUnorm4x8(s.y); }
uint fovea_unpack_material_id(uvec4 s) { return s.z & 0xffffu; }
vec4 fovea_unpack_material(uvec4 s) {
    return vec4(float(s.z & 0xffffu), unpackHalf2x16(s.z >> 16).x, unpackHalf2x16(s.w));
}

#endif
