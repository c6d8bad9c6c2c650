#version 450
#extension GL_GOOGLE_include_directive : require
// Depth-only pass from the sun: the same skinning as body.vert.
#include "common.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in uint inJoint;

void main() {
    Instance inst = instances[gl_InstanceIndex];
    JointTransform j = joints[inst.paletteOffset + inJoint];
    vec3 world = j.position.xyz + rotateByQuat(j.rotation, inPosition);
    gl_Position = frame.lightViewProj * vec4(world, 1.0);
}
