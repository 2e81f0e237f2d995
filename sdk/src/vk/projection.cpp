#include "fovea/vk/projection.hpp"

namespace fovea::vk {

Mat4 crop_projection(const Mat4& p, std::array<float, 4> crop, std::array<float, 2> jitter_px,
                     VkExtent2D view_extent) {
    // View NDC = scale * full NDC + offset per axis (the crop), then the jitter's -2 j / size;
    // in clip space the offset multiplies w, i.e. row 3 of the matrix.
    Mat4 out = p;
    const float size[2] = {static_cast<float>(view_extent.width),
                           static_cast<float>(view_extent.height)};
    for (int axis = 0; axis < 2; ++axis) {
        const float lo = crop[axis], hi = crop[axis + 2];
        const float scale = 1.0f / (hi - lo);
        const float offset =
            (1.0f - 2.0f * lo) * scale - 1.0f - 2.0f * jitter_px[axis] / size[axis];
        for (int col = 0; col < 4; ++col)
            out[col * 4 + axis] = scale * p[col * 4 + axis] + offset * p[col * 4 + 3];
    }
    return out;
}

Mat4 jittered_projection(const Mat4& projection, std::array<float, 2> jitter_px,
                         VkExtent2D extent) {
    return crop_projection(projection, {0.f, 0.f, 1.f, 1.f}, jitter_px, extent);
}

}  // namespace fovea::vk
