#version 450
#extension GL_GOOGLE_include_directive : require
// Instanced linear blend skinning of a rig (fray::SkinnedMesh): each vertex is
// in bind space with up to four joints; the palette holds, per joint, the
// skinning transform world * inverseBind (computed on the CPU), so a vertex
// is the weighted sum of its joints' rigid transforms applied to it.
#include "common.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in uvec4 inJoints;
layout(location = 3) in vec4 inWeights;

layout(location = 0) out vec3 vWorldPos;
layout(location = 1) out vec3 vNormal;
layout(location = 2) flat out vec4 vTint;  // rgb: tint, a: 1 when selected

void main() {
    Instance inst = instances[gl_InstanceIndex];
    vec3 world = vec3(0.0);
    vec3 normal = vec3(0.0);
    // Unused slots (weight 0) are skipped: lavapipe runs a block only when
    // some vertex of its batch needs it, which made a body bound rigidly (one
    // joint per vertex) as cheap as the capsules instead of 45 % dearer
    // (docs/RENDERER.md, Skinning).
    for (int k = 0; k < 4; ++k) {
        if (inWeights[k] <= 0.0) continue;
        JointTransform j = joints[inst.paletteOffset + inJoints[k]];
        world += inWeights[k] * (j.position.xyz + rotateByQuat(j.rotation, inPosition));
        normal += inWeights[k] * rotateByQuat(j.rotation, inNormal);
    }
    vWorldPos = world;
    vNormal = normal;
    vTint = vec4(inst.tint.rgb, float(inst.flags & 1u));
    gl_Position = frame.viewProj * vec4(world, 1.0);
}
