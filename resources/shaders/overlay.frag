#version 450
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) in vec2 vUV;
layout(location = 1) in vec4 vColor;
layout(location = 2) flat in uint vMode;

layout(location = 0) out vec4 outColor;

void main() {
    vec4 c = vColor;  // display colour
    if (vMode == 1u) {
        // Soft disc (flashes): uv in [-1, 1], a bright core fading out.
        float r = length(vUV);
        if (r > 1.0) discard;
        c.a *= 1.0 - smoothstep(0.35, 1.0, r);
        c.rgb = mix(vec3(1.0), c.rgb, smoothstep(0.0, 0.45, r));
    } else if (vMode == 3u) {
        // Blob shadow: a soft dark ellipse on the floor.
        float r = length(vUV);
        if (r > 1.0) discard;
        c.a *= 1.0 - smoothstep(0.25, 1.0, r);
    } else if (vMode == 2u) {
        // Glyph: uv in the font atlas.
        c.a *= texture(fontAtlas, vUV).r;
        if (c.a < 0.01) discard;
    }
    outColor = c;
}
