#version 450
// Second half of Stengel's cheap 5x5 dilation: 3x3 max over the half-resolution map.
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D half_p;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D half_dilated;

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(half_p);
    if (any(greaterThanEqual(t, size))) return;
    float m = 0.0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
            m = max(m, imageLoad(half_p, clamp(t + ivec2(dx, dy), ivec2(0), size - 1)).x);
    imageStore(half_dilated, t, vec4(m));
}
