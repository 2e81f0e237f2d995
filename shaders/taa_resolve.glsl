// TAA pass 4: variance-sampled resolve (Patney §4.2–4.3). Clamp box μ ± γσ from the moment chain
// at LOD = 4·S_t (levels ≥ 1 through the sampler's trilinear filter: one fetch per moment image;
// level 0, a pixel's own 3×3 window, computed here where LOD < 1, i.e. only in the fovea), grown
// to contain the current sample; history fetched with Catmull-Rom and clipped toward the box
// centre in YCoCg; saccade-aware α from the accumulated S in the history's alpha; disocclusion
// from depth and from motion leaving the screen. Mirrors taa_resolve() in
// sdk/src/vk/post/taa_model.cpp.
//
// One workgroup per 8×8 tile of a list made by taa_tiles.comp, dispatched indirectly. lavapipe
// runs every line for every lane (branches only mask lanes), so each list's pipeline
// (kTileClass) holds only the moment reads its tiles need: the level-0 window (9 loads) only
// where some pixel has LOD < 1, the chain fetch only where some pixel has LOD > 0.
//
// Approximation (the issue allows it, the model does the same): the 16-tap Catmull-Rom history
// filter is Jimenez's 5-tap "Catmull-Rom lite" (Filmic SMAA, SIGGRAPH 2016): the four corner
// taps (weights ≤ 1/64 of the total) dropped, renormalized. Jimenez folds the other 12 into 5
// bilinear fetches; here they are 12 storage-image loads with the same weights, which lavapipe
// runs in about half the time of 5 sampler fetches.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D color_in;
layout(set = 0, binding = 1, r32f) uniform readonly image2D depth_in;
layout(set = 0, binding = 2, rg16f) uniform readonly image2D motion_in;
layout(set = 0, binding = 3, r16f) uniform readonly image2D rate_in;
layout(set = 0, binding = 4) uniform sampler2D m1_tex;  // chain levels 1.., trilinear, clamp
layout(set = 0, binding = 5) uniform sampler2D m2_tex;
layout(set = 0, binding = 6, TAA_FORMAT) uniform readonly image2D hist_in;
layout(set = 0, binding = 7, r32f) uniform readonly image2D hist_depth_in;  // last frame's, raw
layout(set = 0, binding = 8, TAA_FORMAT) uniform writeonly image2D hist_out;
layout(set = 0, binding = 9, rgba16f) uniform image2D color_out;  // read back for luma_out
layout(std430, set = 0, binding = 10) readonly buffer TaaTileLists { uint tile[]; } tiles;
layout(set = 0, binding = 11, r32f) uniform writeonly image2D luma_out;  // when kWriteLuma

// Tile classes, as the lists of taa_tiles.comp.
const int kFoveal = 0;      // some pixel with LOD < 1 (not all 0)
const int kPeripheral = 1;  // every LOD ≥ 1
const int kFullRate = 2;    // every LOD 0
layout(constant_id = 0) const int kTileClass = kFoveal;
// Also write enhance_luma.comp's display luminance of color_out for the enhancement pass after
// this one (PostFrame::display_luma_out), saving it a full-screen pass.
layout(constant_id = 1) const bool kWriteLuma = false;

layout(push_constant) uniform Push {
    vec2 jitter;  // this frame's sub-pixel jitter, pixels (first: vec2 needs 8-byte alignment)
    float alpha;
    float alpha_max;
    float beta;
    float gamma;
    float depth_tolerance;
    int levels;
    uint flags;  // bit 0: history valid, bit 1: saccade term on
    uint tiles_x;     // 8×8 tiles per row
    uint list_base;   // first entry of this dispatch's list in `tiles`
} pc;

#include "enhance_common.glsl"
#include "taa_common.glsl"

// Catmull-Rom "lite" at continuous pixel position q (texel centres at integer + 0.5): the 4×4
// taps around q without the corners, clamped to the edge like the model's bilinear fetches.
vec4 history_catmull_rom(vec2 q, ivec2 size) {
    vec2 f = q - 0.5;
    vec2 b = floor(f);
    vec2 t = f - b;
    vec4 wx = taa_catmull_rom(t.x);
    vec4 wy = taa_catmull_rom(t.y);
    ivec2 hi = size - 1;
    ivec2 x = clamp(ivec2(b.x) + ivec2(-1, 2), 0, hi.x);  // outer columns
    ivec2 y = clamp(ivec2(b.y) + ivec2(-1, 2), 0, hi.y);  // outer rows
    ivec2 c = clamp(ivec2(b), ivec2(0), hi);                // inner 2×2 origin
    ivec2 c1 = clamp(ivec2(b) + 1, ivec2(0), hi);
    vec4 top = wx.y * imageLoad(hist_in, ivec2(c.x, y.x)) +
               wx.z * imageLoad(hist_in, ivec2(c1.x, y.x));
    vec4 bottom = wx.y * imageLoad(hist_in, ivec2(c.x, y.y)) +
                  wx.z * imageLoad(hist_in, ivec2(c1.x, y.y));
    vec4 row0 = wx.x * imageLoad(hist_in, ivec2(x.x, c.y)) +
                wx.y * imageLoad(hist_in, ivec2(c.x, c.y)) +
                wx.z * imageLoad(hist_in, ivec2(c1.x, c.y)) +
                wx.w * imageLoad(hist_in, ivec2(x.y, c.y));
    vec4 row1 = wx.x * imageLoad(hist_in, ivec2(x.x, c1.y)) +
                wx.y * imageLoad(hist_in, ivec2(c.x, c1.y)) +
                wx.z * imageLoad(hist_in, ivec2(c1.x, c1.y)) +
                wx.w * imageLoad(hist_in, ivec2(x.y, c1.y));
    vec4 acc = wy.x * top + wy.y * row0 + wy.z * row1 + wy.w * bottom;
    float total = (wx.y + wx.z) * (wy.x + wy.w) + (wx.x + wx.y + wx.z + wx.w) * (wy.y + wy.z);
    return acc / total;
}

void main() {
    uint tile = tiles.tile[pc.list_base + gl_WorkGroupID.x];  // x | y << 16, see taa_tiles.comp
    ivec2 p = ivec2(int(tile & 0xffffu), int(tile >> 16)) * 8 + ivec2(gl_LocalInvocationID.xy);
    ivec2 size = imageSize(color_in);
    if (any(greaterThanEqual(p, size))) return;
    vec2 full = vec2(size);

    vec3 cur_t = taa_tonemap(imageLoad(color_in, p).rgb);
    vec3 cur_q = taa_rgb_to_ycocg(cur_t);
    float s_raw = imageLoad(rate_in, p).x;
    float s_cur = (isnan(s_raw) || isinf(s_raw)) ? 1.0 : clamp(s_raw, 0.0, 1.0);
    float d_raw = imageLoad(depth_in, p).x;
    float d_cur = (isnan(d_raw) || isinf(d_raw)) ? 0.0 : d_raw;

    vec3 blended_q = cur_q;
    float blended_s = s_cur;
    vec2 px = vec2(p) + 0.5;
    vec2 m = imageLoad(motion_in, p).xy;
    if (any(isnan(m)) || any(isinf(m))) m = vec2(-1e9);
    // Motion runs from the unjittered pixel centre to the previous position of the jittered
    // sample's surface: the centre's own flow is motion + jitter (taa_model.hpp, TaaFrame).
    vec2 q = px - (m + pc.jitter);
    bool on_screen = q.x >= 0.0 && q.y >= 0.0 && q.x < full.x && q.y < full.y;
    bool have_history = (pc.flags & 1u) != 0u;
    bool occluded = !on_screen;
    if (have_history && on_screen) {
        float d_prev = imageLoad(hist_depth_in, ivec2(q)).x;  // a copy: sanitized as d_cur
        d_prev = (isnan(d_prev) || isinf(d_prev)) ? 0.0 : d_prev;
        occluded = abs(d_prev - d_cur) > pc.depth_tolerance * max(abs(d_cur), 1e-6);
    }
    if (have_history && !occluded) {
        vec4 acc = history_catmull_rom(q, size);
        vec3 hist_t = max(acc.rgb, vec3(0.0));
        float s_prev = clamp(acc.a, 0.0, 1.0);

        float lod = 4.0 * s_cur;
        lod = min(lod, float(pc.levels - 1));
        vec2 uv = px / full;
        // One trilinear fetch per moment image serves both cases (image mip k holds chain level
        // k + 1): at LOD ≥ 1 it is the box, below it is level 1 for the blend. lavapipe runs
        // both sides of a branch under a lane mask, so fetching in each side paid twice.
        vec3 m1 = vec3(0.0);
        vec3 m2 = vec3(0.0);
        if (kTileClass != kFullRate) {
            m1 = textureLod(m1_tex, uv, max(lod - 1.0, 0.0)).xyz;
            m2 = textureLod(m2_tex, uv, max(lod - 1.0, 0.0)).xyz;
        }
        if (kTileClass != kPeripheral && lod < 1.0) {
            vec3 a1 = vec3(0.0);
            vec3 a2 = vec3(0.0);
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    ivec2 n = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
                    vec3 c = taa_rgb_to_ycocg(taa_tonemap(imageLoad(color_in, n).rgb));
                    a1 += c;
                    a2 += c * c;
                }
            }
            vec3 level1_m1 = m1;
            vec3 level1_m2 = m2;
            m1 = a1 * (1.0 / 9.0);
            m2 = a2 * (1.0 / 9.0);
            // Blend toward level 1 like the model's trilinear.
            if (kTileClass == kFoveal && lod > 0.0 && pc.levels > 1) {
                m1 += (level1_m1 - m1) * lod;
                m2 += (level1_m2 - m2) * lod;
            }
        }
        vec3 sigma = sqrt(max(m2 - m1 * m1, vec3(0.0)));  // never a negative variance
        vec3 lo = min(m1 - pc.gamma * sigma, cur_q);
        vec3 hi = max(m1 + pc.gamma * sigma, cur_q);
        vec3 hist_q = taa_clip(taa_rgb_to_ycocg(hist_t), 0.5 * (lo + hi), 0.5 * (hi - lo));
        float a = taa_saccade_alpha(s_prev, s_cur, pc.alpha, pc.alpha_max, pc.beta,
                                    (pc.flags & 2u) != 0u);
        blended_q = mix(hist_q, cur_q, a);
        blended_s = s_prev + (s_cur - s_prev) * a;
    }
    vec3 t = clamp(taa_ycocg_to_rgb(blended_q), vec3(0.0), vec3(kTaaMaxTonemapped));
    imageStore(hist_out, p, vec4(t, blended_s));
    // Read back what the history stores (half or float) so output and history agree.
    vec3 shown = taa_tonemap_inverse(t);
    imageStore(color_out, p, vec4(shown, 1.0));
    if (kWriteLuma) {
        // From the half floats color_out holds, as enhance_luma.comp reads them: read back,
        // because lavapipe's store rounds to half unlike packHalf2x16 (the bytes differed).
        vec3 c = imageLoad(color_out, p).rgb;
        vec3 d = vec3(enh_display_encode(c.r), enh_display_encode(c.g), enh_display_encode(c.b));
        imageStore(luma_out, p, vec4(clamp(enh_luma(d), 0.0, 1.0)));
    }
}
