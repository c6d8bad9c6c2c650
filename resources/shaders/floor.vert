#version 450
#extension GL_GOOGLE_include_directive : require
// The floor: one square (no vertex buffer) centred under the camera target.
#include "common.glsl"

layout(location = 0) out vec3 vWorldPos;

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(-1, 1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(1, -1));

void main() {
    vec2 xz = frame.floorArea.xy + kCorners[gl_VertexIndex] * frame.floorArea.z;
    vWorldPos = vec3(xz.x, 0.0, xz.y);
    gl_Position = frame.viewProj * vec4(vWorldPos, 1.0);
}
