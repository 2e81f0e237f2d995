#version 450
// Enhancement pass 2: Burt–Adelson REDUCE (5-tap binomial, decimate by 2, clamp-to-edge), one
// Gaussian pyramid level per dispatch. Mirrors gaussian_pyramid() in enhance_model.cpp.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D src;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D dst;

const float kW[5] = float[5](1.0 / 16.0, 4.0 / 16.0, 6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0);

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(dst)))) return;
    ivec2 hi = imageSize(src) - 1;
    float acc = 0.0;
    for (int j = 0; j < 5; ++j) {
        float row = 0.0;
        for (int i = 0; i < 5; ++i)
            row += kW[i] * imageLoad(src, clamp(2 * p + ivec2(i - 2, j - 2), ivec2(0), hi)).x;
        acc += kW[j] * row;
    }
    imageStore(dst, p, vec4(acc));
}
