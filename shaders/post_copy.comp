#version 450
// Post pass "copy": colour in -> colour out unchanged. The reference post pass to copy.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D color_in;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2D color_out;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(color_in)))) return;
    imageStore(color_out, p, imageLoad(color_in, p));
}
