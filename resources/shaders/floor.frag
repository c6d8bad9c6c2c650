#version 450
#extension GL_GOOGLE_include_directive : require
// Floor: base colour, the painted bitmap, a 1 m / 5 m grid, sun and shadows,
// fading into the background with distance.
#include "common.glsl"

layout(constant_id = 1) const bool kBitmap = false;
// Off for the square inside the circle where fog starts (floor.vert): the
// fog costs about a tenth of a frame on lavapipe, and is 0 there anyway.
layout(constant_id = 2) const bool kFog = true;

layout(location = 0) in vec3 vWorldPos;
layout(location = 0) out vec4 outColor;

// 1 on a grid line of the given spacing, 0 away from it; about one pixel wide.
float gridLine(vec2 p, float spacing) {
    vec2 q = p / spacing;
    vec2 w = max(fwidth(q), vec2(1e-5));
    vec2 d = abs(fract(q - 0.5) - 0.5) / w;
    return 1.0 - min(min(d.x, d.y), 1.0);
}

void main() {
    vec2 p = vWorldPos.xz;
    vec3 base = frame.floorColor.rgb;
    if (kBitmap) {
        vec2 lo = frame.bitmapRect.xy;
        vec2 hi = frame.bitmapRect.zw;
        if (all(greaterThanEqual(p, lo)) && all(lessThanEqual(p, hi))) {
            vec4 b = texture(floorBitmap, (p - lo) / (hi - lo));
            base = mix(base, b.rgb, b.a * frame.floorParams.x);
        }
    }
    if (frame.floorParams.y > 0.5) {
        vec2 fw = fwidth(p);
        float minorFade = 1.0 - smoothstep(0.08, 0.3, max(fw.x, fw.y));
        vec3 lineColor = vec3(0.25, 0.26, 0.28);
        base = mix(base, lineColor, gridLine(p, 1.0) * 0.45 * minorFade);
        base = mix(base, lineColor, gridLine(p, 5.0) * 0.7);
    }
    vec3 n = vec3(0.0, 1.0, 0.0);
    float ndl = max(-frame.lightDir.y, 0.0);
    float sun = sunVisibility(vWorldPos, n);
    vec3 color = toLinear(base) * (ambientLight(n) + frame.lightColor.rgb * ndl * sun);
    if (kFog) {
        float dist = length(vWorldPos.xz - frame.floorArea.xy);
        float fog = smoothstep(frame.floorArea.w, frame.floorParams.z, dist);
        color = mix(color, toLinear(frame.fogColor.rgb), fog);
    }
    outColor = vec4(toDisplay(color), 1.0);
}
