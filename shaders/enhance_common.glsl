// Enhancement helpers shared by the enhance_*.comp passes; mirror sdk/src/vk/post/enhance_model.cpp.
#ifndef FOVEA_ENHANCE_COMMON_GLSL
#define FOVEA_ENHANCE_COMMON_GLSL

float enh_display_encode(float c) {
    c = isnan(c) ? 0.0 : clamp(c, 0.0, 3.0e38);
    return pow(c / (1.0 + c), 1.0 / 2.2);
}

float enh_display_decode(float d) {
    float t = min(pow(clamp(d, 0.0, 1.0), 2.2), 0.99999);
    return t / (1.0 - t);
}

float enh_luma(vec3 d) { return dot(d, vec3(0.2126, 0.7152, 0.0722)); }

float enh_blur_sigma_for_rate(float s) {
    s = (isnan(s) || isinf(s)) ? 1.0 : clamp(s, 0.0, 1.0);
    float edge = exp2(2.0 * s);
    return sqrt(max(edge * edge - 1.0, 0.0) / 12.0);
}

#endif
