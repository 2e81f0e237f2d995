#include "taa_model.hpp"

#include <algorithm>
#include <cmath>

namespace fovea::vk::post {

namespace {

// Largest tone-mapped component we invert; keeps T/(1 − max T) finite (≈ 10^5 · input scale).
constexpr float kMaxTonemapped = 0.99999f;

float sanitize(float v) {
    if (std::isnan(v)) return 0.0f;
    return std::clamp(v, 0.0f, 3.0e38f);  // +inf → large finite, negatives are not light
}

Vec3 lerp(Vec3 a, Vec3 b, float t) {
    return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t};
}

float store(float v, bool half) { return half ? round_to_half(v) : v; }

}  // namespace

float halton(std::uint32_t index, std::uint32_t base) {
    float f = 1.0f;
    float r = 0.0f;
    while (index > 0) {
        f /= float(base);
        r += f * float(index % base);
        index /= base;
    }
    return r;
}

Jitter halton_jitter(std::uint64_t frame, std::uint32_t length) {
    length = std::max<std::uint32_t>(length, 1);
    // Index 0 is (0, 0) for every base; start at 1 so the sequence is centred.
    const auto i = std::uint32_t(frame % length) + 1;
    return {halton(i, 2) - 0.5f, halton(i, 3) - 0.5f};
}

Vec3 rgb_to_ycocg(Vec3 c) {
    return {0.25f * c.x + 0.5f * c.y + 0.25f * c.z, 0.5f * c.x - 0.5f * c.z,
            -0.25f * c.x + 0.5f * c.y - 0.25f * c.z};
}

Vec3 ycocg_to_rgb(Vec3 c) { return {c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z}; }

Vec3 tonemap_forward(Vec3 c) {
    c = {sanitize(c.x), sanitize(c.y), sanitize(c.z)};
    const float k = 1.0f / (1.0f + std::max({c.x, c.y, c.z}));
    return {c.x * k, c.y * k, c.z * k};
}

Vec3 tonemap_inverse(Vec3 t) {
    t = {std::clamp(t.x, 0.0f, kMaxTonemapped), std::clamp(t.y, 0.0f, kMaxTonemapped),
         std::clamp(t.z, 0.0f, kMaxTonemapped)};
    const float k = 1.0f / (1.0f - std::max({t.x, t.y, t.z}));
    return {t.x * k, t.y * k, t.z * k};
}

Moments moments_3x3(const Image& img, int x, int y) {
    Moments m;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            const Vec3 c{img.fetch(x + dx, y + dy, 0), img.fetch(x + dx, y + dy, 1),
                         img.fetch(x + dx, y + dy, 2)};
            m.m1 = {m.m1.x + c.x, m.m1.y + c.y, m.m1.z + c.z};
            m.m2 = {m.m2.x + c.x * c.x, m.m2.y + c.y * c.y, m.m2.z + c.z * c.z};
        }
    }
    constexpr float kInv9 = 1.0f / 9.0f;
    m.m1 = {m.m1.x * kInv9, m.m1.y * kInv9, m.m1.z * kInv9};
    m.m2 = {m.m2.x * kInv9, m.m2.y * kInv9, m.m2.z * kInv9};
    return m;
}

ClampBox clamp_box(const Moments& m, float gamma) {
    // m2 − m1² cancels catastrophically (and rounds below zero in half); never take sqrt of < 0.
    auto sigma = [](float m1, float m2) { return std::sqrt(std::max(m2 - m1 * m1, 0.0f)); };
    return {m.m1,
            {gamma * sigma(m.m1.x, m.m2.x), gamma * sigma(m.m1.y, m.m2.y),
             gamma * sigma(m.m1.z, m.m2.z)}};
}

ClampBox include_sample(const ClampBox& b, Vec3 s) {
    auto grow = [](float c, float e, float v, float& oc, float& oe) {
        const float lo = std::min(c - e, v);
        const float hi = std::max(c + e, v);
        oc = 0.5f * (lo + hi);
        oe = 0.5f * (hi - lo);
    };
    ClampBox r;
    grow(b.centre.x, b.extent.x, s.x, r.centre.x, r.extent.x);
    grow(b.centre.y, b.extent.y, s.y, r.centre.y, r.extent.y);
    grow(b.centre.z, b.extent.z, s.z, r.centre.z, r.extent.z);
    return r;
}

Vec3 clip_toward_centre(Vec3 v, const ClampBox& box) {
    constexpr float kEps = 1e-7f;  // a zero-width box clips onto its centre, never divides by 0
    const Vec3 d{v.x - box.centre.x, v.y - box.centre.y, v.z - box.centre.z};
    const float ux = std::fabs(d.x) / std::max(box.extent.x, kEps);
    const float uy = std::fabs(d.y) / std::max(box.extent.y, kEps);
    const float uz = std::fabs(d.z) / std::max(box.extent.z, kEps);
    const float u = std::max({ux, uy, uz});
    if (!(u > 1.0f)) return v;
    return {box.centre.x + d.x / u, box.centre.y + d.y / u, box.centre.z + d.z / u};
}

std::array<float, 4> catmull_rom_weights(float t) {
    const float t2 = t * t;
    const float t3 = t2 * t;
    return {-0.5f * t3 + t2 - 0.5f * t, 1.5f * t3 - 2.5f * t2 + 1.0f,
            -1.5f * t3 + 2.0f * t2 + 0.5f * t, 0.5f * t3 - 0.5f * t2};
}

float saccade_alpha(float s_prev, float s_cur, const SaccadeParams& p) {
    if (!p.enabled) return p.alpha;
    const float w = std::clamp((s_prev - s_cur) / p.beta, 0.0f, 1.0f);
    return w * p.alpha_max + (1.0f - w) * p.alpha;
}

MipChain taa_moment_chain(const Image& colour, int levels, bool half_storage) {
    Image ycocg(colour.width, colour.height, 3);
    for (int y = 0; y < colour.height; ++y) {
        for (int x = 0; x < colour.width; ++x) {
            const Vec3 t =
                tonemap_forward({colour.at(x, y, 0), colour.at(x, y, 1), colour.at(x, y, 2)});
            const Vec3 q = rgb_to_ycocg(t);
            ycocg.at(x, y, 0) = q.x;
            ycocg.at(x, y, 1) = q.y;
            ycocg.at(x, y, 2) = q.z;
        }
    }
    Image mom(colour.width, colour.height, 6);
    for (int y = 0; y < colour.height; ++y) {
        for (int x = 0; x < colour.width; ++x) {
            const Moments m = moments_3x3(ycocg, x, y);
            const float v[6] = {m.m1.x, m.m1.y, m.m1.z, m.m2.x, m.m2.y, m.m2.z};
            // Level 0 is never stored on the GPU (the resolve computes it in float).
            for (int c = 0; c < 6; ++c) mom.at(x, y, c) = v[c];
        }
    }
    MipChain chain = build_box_mips(std::move(mom), levels);
    if (half_storage) {
        for (std::size_t l = 1; l < chain.size(); ++l) {
            for (float& v : chain[l].data) v = round_to_half(v);
        }
    }
    return chain;
}

std::array<float, 4> catmull_rom_5tap(const Image& img, float x, float y) {
    const float bx = std::floor(x - 0.5f);
    const float by = std::floor(y - 0.5f);
    const auto wx = catmull_rom_weights(x - 0.5f - bx);
    const auto wy = catmull_rom_weights(y - 0.5f - by);
    const float w12x = wx[1] + wx[2];
    const float w12y = wy[1] + wy[2];
    const float c12x = bx + 0.5f + wx[2] / w12x;  // one bilinear fetch for taps 0 and +1
    const float c12y = by + 0.5f + wy[2] / w12y;
    const float c0x = bx - 0.5f, c0y = by - 0.5f, c3x = bx + 2.5f, c3y = by + 2.5f;
    const struct {
        float x, y, k;
    } taps[5] = {{c12x, c0y, w12x * wy[0]},
                 {c0x, c12y, wx[0] * w12y},
                 {c12x, c12y, w12x * w12y},
                 {c3x, c12y, wx[3] * w12y},
                 {c12x, c3y, w12x * wy[3]}};
    std::array<float, 4> acc{0, 0, 0, 0};
    float total = 0;
    for (const auto& t : taps) {
        total += t.k;
        for (int c = 0; c < std::min(img.channels, 4); ++c)
            acc[std::size_t(c)] += t.k * sample_bilinear(img, t.x, t.y, c);
    }
    for (float& v : acc) v /= total;
    return acc;
}

Image taa_resolve(const TaaFrame& frame, TaaHistory& history, const TaaParams& params) {
    const Image& colour = *frame.colour;
    const int w = colour.width;
    const int h = colour.height;
    const MipChain chain = taa_moment_chain(colour, params.moment_levels, params.half_storage);

    const bool have_history = history.valid && !frame.camera_cut && history.colour.width == w &&
                              history.colour.height == h;
    Image next(w, h, 4);
    Image next_depth(w, h, 1);
    Image out(w, h, 3);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const Vec3 cur_t =
                tonemap_forward({colour.at(x, y, 0), colour.at(x, y, 1), colour.at(x, y, 2)});
            const Vec3 cur_q = rgb_to_ycocg(cur_t);
            const float s_raw = frame.rate ? frame.rate->at(x, y) : 0.0f;
            const float s_cur = std::isfinite(s_raw) ? std::clamp(s_raw, 0.0f, 1.0f) : 1.0f;
            const float d_raw = frame.depth ? frame.depth->at(x, y) : 0.0f;
            const float d_cur = std::isfinite(d_raw) ? d_raw : 0.0f;

            Vec3 blended_q = cur_q;
            float blended_s = s_cur;
            const float px = float(x) + 0.5f;
            const float py = float(y) + 0.5f;
            float mx = frame.motion ? frame.motion->at(x, y, 0) : 0.0f;
            float my = frame.motion ? frame.motion->at(x, y, 1) : 0.0f;
            if (!std::isfinite(mx) || !std::isfinite(my)) mx = my = 1e9f;  // treat as off screen
            // Without the jitter the history would be fetched half a pixel off, differently
            // every frame: the converged image would swim by the jitter pattern (flicker).
            const float qx = px - (mx + frame.jitter.x);
            const float qy = py - (my + frame.jitter.y);
            const bool on_screen = qx >= 0.0f && qy >= 0.0f && qx < float(w) && qy < float(h);
            bool occluded = !on_screen;
            if (have_history && on_screen && frame.depth) {
                const float d_prev = history.depth.at(int(qx), int(qy));
                occluded = std::fabs(d_prev - d_cur) >
                           params.depth_tolerance * std::max(std::fabs(d_cur), 1e-6f);
            }
            if (have_history && !occluded) {
                const std::array<float, 4> acc = catmull_rom_5tap(history.colour, qx, qy);
                // Catmull-Rom rings below zero next to edges; negative light is not a colour.
                const Vec3 hist_t{std::max(acc[0], 0.0f), std::max(acc[1], 0.0f),
                                  std::max(acc[2], 0.0f)};
                const float s_prev = std::clamp(acc[3], 0.0f, 1.0f);

                const float lod = 4.0f * s_cur;
                Moments m;
                m.m1 = {sample_trilinear(chain, px, py, lod, 0),
                        sample_trilinear(chain, px, py, lod, 1),
                        sample_trilinear(chain, px, py, lod, 2)};
                m.m2 = {sample_trilinear(chain, px, py, lod, 3),
                        sample_trilinear(chain, px, py, lod, 4),
                        sample_trilinear(chain, px, py, lod, 5)};
                const ClampBox box = include_sample(clamp_box(m, params.gamma), cur_q);
                const Vec3 hist_q = clip_toward_centre(rgb_to_ycocg(hist_t), box);
                const float a = saccade_alpha(s_prev, s_cur, params.saccade);
                blended_q = lerp(hist_q, cur_q, a);
                blended_s = s_prev + (s_cur - s_prev) * a;
            }
            Vec3 t = ycocg_to_rgb(blended_q);
            t = {std::clamp(t.x, 0.0f, kMaxTonemapped), std::clamp(t.y, 0.0f, kMaxTonemapped),
                 std::clamp(t.z, 0.0f, kMaxTonemapped)};
            const bool half = params.half_storage;
            next.at(x, y, 0) = store(t.x, half);
            next.at(x, y, 1) = store(t.y, half);
            next.at(x, y, 2) = store(t.z, half);
            next.at(x, y, 3) = store(blended_s, half);
            next_depth.at(x, y) = d_cur;
            const Vec3 lin =
                tonemap_inverse({next.at(x, y, 0), next.at(x, y, 1), next.at(x, y, 2)});
            out.at(x, y, 0) = lin.x;
            out.at(x, y, 1) = lin.y;
            out.at(x, y, 2) = lin.z;
        }
    }
    history.colour = std::move(next);
    history.depth = std::move(next_depth);
    history.valid = true;
    return out;
}

Image taa_history_tonemapped(const TaaHistory& history) {
    Image t(history.colour.width, history.colour.height, 3);
    for (int y = 0; y < t.height; ++y) {
        for (int x = 0; x < t.width; ++x) {
            for (int c = 0; c < 3; ++c) t.at(x, y, c) = history.colour.at(x, y, c);
        }
    }
    return t;
}

}  // namespace fovea::vk::post
