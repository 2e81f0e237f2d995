#version 450
// The host's own shading: a fine checker with a smooth colour ramp; static scene and camera,
// so motion is zero; depth is the window depth of a standard projection (0 near .. 1 far).
layout(location = 0) in vec3 world;
layout(location = 0) out vec4 color;
layout(location = 1) out float depth;
layout(location = 2) out vec2 motion;
void main() {
    vec2 q = floor(world.xy * 24.0);
    float checker = mod(q.x + q.y, 2.0);
    color = vec4(vec3(0.2 + 0.6 * checker) * vec3(0.5 + 0.5 * sin(world.z), 0.7, 1.0), 1.0);
    depth = gl_FragCoord.z;
    motion = vec2(0.0);
}
