#version 450
// Overlays (trajectories, checkpoints, selection rings, flashes, labels):
// pre-built triangles in world space or in pixels, transformed by the push
// constant matrix.
layout(push_constant) uniform Push {
    mat4 transform;
} pc;

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec2 inUV;
layout(location = 2) in vec4 inColor;
layout(location = 3) in uint inMode;

layout(location = 0) out vec2 vUV;
layout(location = 1) out vec4 vColor;
layout(location = 2) flat out uint vMode;

void main() {
    vUV = inUV;
    vColor = inColor;
    vMode = inMode;
    gl_Position = pc.transform * vec4(inPosition, 1.0);
}
