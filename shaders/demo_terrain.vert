#version 450
// Terrain of the rasterized demo G-buffer: a camera-centred geometry clipmap generated from
// gl_VertexIndex (no vertex buffer). Level 0 is a kCells x kCells grid of kSpacing cells; level
// L > 0 doubles the spacing and leaves out the middle half, which level L - 1 covers. The centre
// snaps to a 1 m grid so the fine levels do not swim as the camera moves. Vertices on a level's
// outer edge that the next level does not have take the average height of their neighbours,
// matching the coarser level's edge: no cracks.
#extension GL_GOOGLE_include_directive : require
#include "demo_raster.glsl"
#include "demo_scene.glsl"

layout(constant_id = 0) const int kCells = 32;        // per level and side, a multiple of 4
layout(constant_id = 1) const float kSpacing = 0.25;  // level 0 cell size, metres

layout(location = 0) out vec3 world;

const ivec2 kCorner[6] = ivec2[](ivec2(0, 0), ivec2(1, 0), ivec2(0, 1), ivec2(1, 0), ivec2(1, 1),
                                 ivec2(0, 1));

// Cell (i, j) of level `level` for the cell index counted over all levels.
ivec2 terrain_cell(int cell, out int level) {
    int n = kCells, q = kCells / 4, full = kCells * kCells, ring = full - 4 * q * q;
    if (cell < full) {
        level = 0;
        return ivec2(cell % n, cell / n);
    }
    cell -= full;
    level = 1 + cell / ring;
    int r = cell % ring;
    if (r < q * n) return ivec2(r % n, r / n);  // rows above the hole
    r -= q * n;
    if (r < 2 * q * 2 * q) {  // rows beside the hole: q cells left, q cells right
        int col = r % (2 * q);
        return ivec2(col < q ? col : col + 2 * q, q + r / (2 * q));
    }
    r -= 4 * q * q;
    return ivec2(r % n, 3 * q + r / n);  // rows below the hole
}

void main() {
    DemoView v = demo_view;
    int level;
    ivec2 g = terrain_cell(gl_VertexIndex / 6, level) + kCorner[gl_VertexIndex % 6];
    float spacing = kSpacing * float(1 << level);
    vec2 centre = floor(v.pos.xz + 0.5);
    vec2 xz = centre + vec2(g - kCells / 2) * spacing;
    float h;
    bool edge_x = g.y == 0 || g.y == kCells, edge_z = g.x == 0 || g.x == kCells;
    if (edge_x && (g.x & 1) == 1)
        h = 0.5 * (demo_terrain_height(xz - vec2(spacing, 0.0)) +
                   demo_terrain_height(xz + vec2(spacing, 0.0)));
    else if (edge_z && (g.y & 1) == 1)
        h = 0.5 * (demo_terrain_height(xz - vec2(0.0, spacing)) +
                   demo_terrain_height(xz + vec2(0.0, spacing)));
    else
        h = demo_terrain_height(xz);
    world = vec3(xz.x, h, xz.y);
    gl_Position = demo_clip_position(v, world);
}
