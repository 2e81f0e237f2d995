#version 450
#extension GL_GOOGLE_include_directive : require
// taa_moments.glsl with rgba16f moment/history storage.
#define TAA_FORMAT rgba16f
#include "taa_moments.glsl"
