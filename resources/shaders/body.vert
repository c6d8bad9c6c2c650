#version 450
#extension GL_GOOGLE_include_directive : require
// Instanced rigid skinning: each vertex is stored in its joint's local frame,
// so its world position is the joint's world transform applied to it.
#include "common.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in uint inJoint;

layout(location = 0) out vec3 vWorldPos;
layout(location = 1) out vec3 vNormal;
layout(location = 2) flat out vec4 vTint;  // rgb: tint, a: 1 when selected

void main() {
    Instance inst = instances[gl_InstanceIndex];
    JointTransform j = joints[inst.paletteOffset + inJoint];
    vec3 world = j.position.xyz + rotateByQuat(j.rotation, inPosition);
    vWorldPos = world;
    vNormal = rotateByQuat(j.rotation, inNormal);
    vTint = vec4(inst.tint.rgb, float(inst.flags & 1u));
    gl_Position = frame.viewProj * vec4(world, 1.0);
}
