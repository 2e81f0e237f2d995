#version 450
#extension GL_GOOGLE_include_directive : require
// taa_moments.glsl with rgba32f moment/history storage.
#define TAA_FORMAT rgba32f
#include "taa_moments.glsl"
