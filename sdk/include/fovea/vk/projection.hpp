// Projection helpers for hosts: the frame's sub-pixel jitter and a view's crop applied to the
// host's own projection matrix, so the host's samples land where the module's passes expect them.
// Pure functions, any thread.
//
// Conventions (the whole module's; DESIGN.md §5):
// - Matrices are column-major 4x4 (GLSL, GLM: element [col * 4 + row]) mapping view space to
//   Vulkan clip space: x right, y down (a viewport of positive height), depth 0..1.
// - Pixel (i, j) covers [i, i + 1) x [j, j + 1) from the top-left corner; its centre is i + 0.5.
// - Jitter sign: in frame n the rasterizer's pixel centre p + 0.5 must sample the scene point the
//   unjittered projection puts at p + 0.5 + jitter_px (Foveator::jitter(n), ViewRequest::jitter_px
//   for a view, in that view's pixels). In NDC this shifts the image by -2 * jitter / size:
//       ndc'.x = ndc.x - 2 * jitter.x / width,   ndc'.y = ndc.y - 2 * jitter.y / height.
//   A host that adds the jitter with the opposite sign renders every frame 2 * jitter off and TAA
//   blurs it (a loss no error message reports): use jittered_projection().
// - Depth the module reads (G-buffer depth, post-chain depth): 0..1, increasing with distance,
//   1 = far plane / background. A standard (non-reversed) perspective projection's window depth
//   qualifies as is; a reverse-Z host writes 1 - z (or sets DepthMapping::kReversed where the
//   module reads the host's own depth image). TAA compares depths relative to the current depth
//   (taa.depth_tolerance), so any monotonic mapping works; the demo writes 1 - near / distance.
// - Motion: pixels, current position minus the previous frame's position of the same surface
//   point, measured from the unjittered pixel centre to where the jittered sample was last frame.
#pragma once

#include <array>

#include <vulkan/vulkan.h>

namespace fovea::vk {

using Mat4 = std::array<float, 16>;  // column-major

// `projection` with this frame's jitter (pixels of a `extent`-sized render target) applied.
Mat4 jittered_projection(const Mat4& projection, std::array<float, 2> jitter_px, VkExtent2D extent);

// The projection of a view that renders the normalized sub-rectangle `crop` (x0, y0, x1, y1 of
// the full frame, 0..1, origin top-left; ViewRequest::crop) of `projection` into the whole of a
// `view_extent` target, with the view's jitter in its own pixels. crop {0, 0, 1, 1} with
// view_extent = the frame's size equals jittered_projection().
Mat4 crop_projection(const Mat4& projection, std::array<float, 4> crop,
                     std::array<float, 2> jitter_px, VkExtent2D view_extent);

}  // namespace fovea::vk
