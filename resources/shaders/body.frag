#version 450
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(location = 0) in vec3 vWorldPos;
layout(location = 1) in vec3 vNormal;
layout(location = 2) flat in vec4 vTint;  // rgb: tint, a: 1 when selected

layout(location = 0) out vec4 outColor;

void main() {
    vec3 n = normalize(vNormal);
    vec3 v = normalize(frame.cameraPos.xyz - vWorldPos);
    vec3 l = -frame.lightDir.xyz;
    float ndl = max(dot(n, l), 0.0);
    float sun = ndl > 0.0 ? sunVisibility(vWorldPos, n) : 0.0;
    vec3 albedo = toLinear(vTint.rgb);
    vec3 color = albedo * (ambientLight(n) + frame.lightColor.rgb * ndl * sun);
    vec3 h = normalize(l + v);
    float s2 = max(dot(n, h), 0.0);
    s2 *= s2;
    float s8 = s2 * s2;
    s8 *= s8;
    color += frame.lightColor.rgb * (0.12 * s8 * s8 * s8) * sun;  // specular, exponent 24
    if (vTint.a > 0.5) {
        // Selection: a glowing rim in the highlight colour.
        float rim = 1.0 - max(dot(n, v), 0.0);
        rim *= sqrt(rim);
        color = mix(color, toLinear(frame.highlightColor.rgb), clamp(rim * 1.2, 0.0, 1.0));
    }
    outColor = vec4(toDisplay(color), 1.0);
}
