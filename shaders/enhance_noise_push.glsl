// Push constants of the enhance_noise_*.comp passes; mirrors NoisePush in
// sdk/src/vk/post/noise.cpp (std430 push layout, vec2 members first).
#ifndef FOVEA_ENHANCE_NOISE_PUSH_GLSL
#define FOVEA_ENHANCE_NOISE_PUSH_GLSL

layout(push_constant) uniform NoisePush {
    vec2 display_size_px;   // FoveaDisplay of this frame (eccentricity)
    vec2 display_half_tan;
    vec2 gaze_px;
    float ppd;              // pixels per degree at the display centre; <= 0: no noise
    float s_k;              // amplitude scale (Tariq Table 2)
    float s_f;              // bandwidth scale (Tariq Table 2)
    float attenuation_p;    // Laplacian level choice (p = 0.25)
    float radius;           // kernel radius = cell edge, pixels
    float bandwidth;        // Gabor envelope a, cycles per pixel
    float norm;             // 1/sqrt(λ E[w²] ∫g²): noise std ≈ K
    int per_cell;           // impulses per cell
    int cells_x;            // cell grid, origin at cell (-1, -1)
    int cells_y;
    uint seed;              // constant: impulse positions never move
    int group_offset_x;     // apply: first workgroup (tile) of this chunk of the dispatch
    int group_offset_y;
    int chunk_groups_x;     // apply: workgroups per row of this chunk (strip-list rows)
} pc;

#endif
