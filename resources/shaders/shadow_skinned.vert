#version 450
#extension GL_GOOGLE_include_directive : require
// Depth-only pass from the sun for rigs: the same skinning as body_skinned.vert.
#include "common.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in uvec4 inJoints;
layout(location = 3) in vec4 inWeights;

void main() {
    Instance inst = instances[gl_InstanceIndex];
    vec3 world = vec3(0.0);
    for (int k = 0; k < 4; ++k) {
        if (inWeights[k] <= 0.0) continue;  // unused slot (see body_skinned.vert)
        JointTransform j = joints[inst.paletteOffset + inJoints[k]];
        world += inWeights[k] * (j.position.xyz + rotateByQuat(j.rotation, inPosition));
    }
    gl_Position = frame.lightViewProj * vec4(world, 1.0);
}
