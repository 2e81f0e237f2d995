#version 450
#extension GL_GOOGLE_include_directive : require
// taa_resolve.glsl with rgba16f moment/history storage.
#define TAA_FORMAT rgba16f
#include "taa_resolve.glsl"
