#version 450
// Sky: drawn last, behind everything, where no surface was rasterized.
#extension GL_GOOGLE_include_directive : require
#define DEMO_RASTER_FRAGMENT
#include "demo_raster.glsl"

void main() { demo_write_background(demo_pixel_ray(demo_view, gl_FragCoord.xy)); }
