#version 450
#extension GL_GOOGLE_include_directive : require
// The floor: a square (no vertex buffer) centred under the camera target, in
// two draws: vertices 0-5 the square inside the circle where fog starts
// (drawn without fog), 6-29 the ring of four trapezoids around it up to the
// floor's edge (with fog).
#include "common.glsl"

layout(location = 0) out vec3 vWorldPos;

// xy: corner of a unit square, z: 0 on the inner square, 1 on the floor's edge.
const vec3 kCorners[30] = vec3[](
    vec3(-1, -1, 0), vec3(-1, 1, 0), vec3(1, 1, 0), vec3(-1, -1, 0), vec3(1, 1, 0), vec3(1, -1, 0),
    vec3(-1, -1, 0), vec3(-1, -1, 1), vec3(1, -1, 1), vec3(-1, -1, 0), vec3(1, -1, 1), vec3(1, -1, 0),
    vec3(1, -1, 0), vec3(1, -1, 1), vec3(1, 1, 1), vec3(1, -1, 0), vec3(1, 1, 1), vec3(1, 1, 0),
    vec3(1, 1, 0), vec3(1, 1, 1), vec3(-1, 1, 1), vec3(1, 1, 0), vec3(-1, 1, 1), vec3(-1, 1, 0),
    vec3(-1, 1, 0), vec3(-1, 1, 1), vec3(-1, -1, 1), vec3(-1, 1, 0), vec3(-1, -1, 1), vec3(-1, -1, 0));

void main() {
    vec3 c = kCorners[gl_VertexIndex];
    // The inner square's corners lie on the circle where fog starts.
    float extent = c.z > 0.5 ? frame.floorArea.z : frame.floorArea.w * 0.70710678;
    vec2 xz = frame.floorArea.xy + c.xy * extent;
    vWorldPos = vec3(xz.x, 0.0, xz.y);
    gl_Position = frame.viewProj * vec4(vWorldPos, 1.0);
}
