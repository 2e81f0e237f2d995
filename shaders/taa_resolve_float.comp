#version 450
#extension GL_GOOGLE_include_directive : require
// taa_resolve.glsl with rgba32f moment/history storage.
#define TAA_FORMAT rgba32f
#include "taa_resolve.glsl"
