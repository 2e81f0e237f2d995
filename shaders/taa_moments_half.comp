#version 450
#extension GL_GOOGLE_include_directive : require
// taa_moments.glsl with rgba16f moment/history storage.
#define TAA_FORMAT rgba16f
#define TAA_STORED(v) vec3(unpackHalf2x16(packHalf2x16((v).xy)), unpackHalf2x16(packHalf2x16(vec2((v).z, 0.0))).x)
#include "taa_moments.glsl"
