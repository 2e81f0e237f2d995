#version 450
// LDR-FLIP step 3: every column filtered at its rows' ppd, then per pixel the colour difference
// (filtered YCxCz -> linear RGB clamped to [0, 1] -> Hunt-adjusted L*a*b* -> HyAB^qc,
// redistributed) and the feature difference (edge and point magnitudes). mode 0 keeps this
// image's filtered values as the reference; mode 1 writes FLIP against that reference (NaN where
// the reference pixel is invalid).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 16, local_size_y = 16) in;

#include "flip_common.glsl"
#define FLIP_COLOUR_BINDING 6
#include "flip_colour.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Horizontal { vec4 horizontal[]; };
layout(std430, set = 0, binding = 1) buffer Reference {
    vec4 reference[];  // 2 per pixel: (L, a, b, edge), (point, valid, 0, 0)
};
layout(std430, set = 0, binding = 2) writeonly buffer Map { float map[]; };
layout(std430, set = 0, binding = 3) readonly buffer Axes { FlipAxis axes[]; };
layout(std430, set = 0, binding = 4) readonly buffer Weights { vec4 weights[]; };
layout(std430, set = 0, binding = 5) readonly buffer BlockAxis { uint block_axis[]; };

layout(push_constant) uniform Push {
    uvec2 size;
    uint blocks_x;
    uint mode;          // 0: store as reference, 1: compare with the reference
    uint block_offset;  // this ppd field's first column block in block_axis (rows follow)
    uint reference_offset;  // this reference's first vec4 in reference[]
};

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(p, size))) return;
    FlipAxis column = axes[block_axis[block_offset + gl_WorkGroupID.x]];
    FlipAxis a = axes[block_axis[block_offset + blocks_x + gl_WorkGroupID.y]];
    int last = int(size.y) - 1;
    vec3 c = vec3(0.0);
    for (int j = -a.colour_radius; j <= a.colour_radius; ++j) {
        vec4 h = horizontal[2u * (uint(clamp(int(p.y) + j, 0, last)) * size.x + p.x)];
        vec4 w = weights[a.colour_offset + uint(j + a.colour_radius)];
        c += vec3(w.x * h.x, w.y * h.y, w.z * h.z + w.w * h.w);
    }
    c.z /= column.cz1_sum * a.cz1_sum + column.cz2_sum * a.cz2_sum;
    vec4 d = vec4(0.0);  // dx, ddx, dy, ddy
    for (int j = -a.feature_radius; j <= a.feature_radius; ++j) {
        vec4 h = horizontal[2u * (uint(clamp(int(p.y) + j, 0, last)) * size.x + p.x) + 1u];
        vec3 w = weights[a.feature_offset + uint(j + a.feature_radius)].xyz;
        d += vec4(w.x * h.y, w.x * h.z, w.y * h.x, w.z * h.x);
    }
    vec3 lab = flip_linear_rgb_to_hunt_lab(clamp(flip_ycxcz_to_linear_rgb(c), 0.0, 1.0));
    float edge = length(d.xz), point = length(d.yw);
    uint i = p.y * size.x + p.x;
    uint r = reference_offset + 2u * i;
    float valid = horizontal[2u * i + 1u].w;
    if (mode == 0u) {
        reference[r] = vec4(lab, edge);
        reference[r + 1u] = vec4(point, valid, 0.0, 0.0);
        return;
    }
    vec4 r0 = reference[r], r1 = reference[r + 1u];
    if (r1.y == 0.0) {
        map[i] = uintBitsToFloat(0x7fc00000u);  // NaN: not pooled
        return;
    }
    float hyab = abs(r0.x - lab.x) + length(r0.yz - lab.yz);
    float cmax = flip_colour.colour.x, knee = flip_colour.colour.y, pt = flip_colour.colour.z;
    float e = hyab > 0.0 ? pow(hyab, flip_colour.colour.w) : 0.0;
    float colour = e < knee ? e * pt / knee : pt + (e - knee) / (cmax - knee) * (1.0 - pt);
    float feature = sqrt(max(abs(r0.w - edge), abs(r1.x - point)) * flip_colour.feature.x);
    float exponent = 1.0 - feature;
    // pow(0, y) is undefined in GLSL for y <= 0; the reference's is 0 for y > 0 and 1 at 0.
    map[i] = colour > 0.0 ? pow(colour, exponent) : (exponent > 0.0 ? 0.0 : 1.0);
}
