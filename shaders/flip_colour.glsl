// The colour half of LDR-FLIP: the CPU reference's constants (metrics/src/gpu_flip.cpp fills
// the block; define FLIP_COLOUR_BINDING before including) and the transforms between linear sRGB,
// YCxCz and Hunt-adjusted L*a*b*.

layout(std140, set = 0, binding = FLIP_COLOUR_BINDING) uniform FlipColour {
    mat3 rgb_to_xyz;
    mat3 xyz_to_rgb;
    vec4 white;     // XYZ of linear RGB (1, 1, 1)
    vec4 colour;    // cmax (qc-th power of the green-blue distance), pc * cmax, pt, qc
    vec4 feature;   // 1 / sqrt(2) (the feature exponent qf = 1/2 is a sqrt)
} flip_colour;

vec3 flip_linear_rgb_to_ycxcz(vec3 rgb) {
    vec3 xyz = flip_colour.rgb_to_xyz * rgb / flip_colour.white.xyz;
    return vec3(116.0 * xyz.y - 16.0, 500.0 * (xyz.x - xyz.y), 200.0 * (xyz.y - xyz.z));
}

vec3 flip_ycxcz_to_linear_rgb(vec3 o) {
    float y = (o.x + 16.0) / 116.0;
    vec3 xyz = vec3(y + o.y / 500.0, y, y - o.z / 200.0) * flip_colour.white.xyz;
    return flip_colour.xyz_to_rgb * xyz;
}

float flip_lab_f(float t) {
    const float d = 6.0 / 29.0;
    return t > d * d * d ? pow(t, 1.0 / 3.0) : t / (3.0 * d * d) + 4.0 / 29.0;
}

// CIE L*a*b* with Hunt's adjustment (chroma scaled by 0.01 L*).
vec3 flip_linear_rgb_to_hunt_lab(vec3 rgb) {
    vec3 xyz = flip_colour.rgb_to_xyz * rgb / flip_colour.white.xyz;
    float fx = flip_lab_f(xyz.x), fy = flip_lab_f(xyz.y), fz = flip_lab_f(xyz.z);
    float l = 116.0 * fy - 16.0;
    return vec3(l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz));
}
