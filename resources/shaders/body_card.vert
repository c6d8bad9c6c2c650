#version 450
#extension GL_GOOGLE_include_directive : require
// The coarsest level of detail (Fast quality, characters a few dozen pixels
// tall): each capsule is a hexagonal card facing the camera, 4 triangles
// instead of 16, whose normals bend from the card's middle (towards the
// camera) to its edges (sideways), so body.frag shades it like a capsule.
// A vertex holds its end of the capsule (`anchor`) and the other end, both in
// the joint's local frame, like the capsule meshes (body.vert).
#include "common.glsl"

layout(location = 0) in vec4 inAnchor;  // xyz: this end, w: radius
layout(location = 1) in vec3 inOther;   // the other end
layout(location = 2) in uint inCorner;  // bits 0-23: joint; 24-25: 0 tip, 1 and 2 the two sides; 26: second end

layout(location = 0) out vec3 vWorldPos;
layout(location = 1) out vec3 vNormal;
layout(location = 2) flat out vec4 vTint;  // rgb: tint, a: 1 when selected

void main() {
    Instance inst = instances[gl_InstanceIndex];
    JointTransform j = joints[inst.paletteOffset + (inCorner & 0xffffffu)];
    vec3 anchor = j.position.xyz + rotateByQuat(j.rotation, inAnchor.xyz);
    vec3 other = j.position.xyz + rotateByQuat(j.rotation, inOther);
    float r = inAnchor.w;
    vec3 toCamera = normalize(frame.cameraPos.xyz - 0.5 * (anchor + other));
    // Along the capsule in the picture plane, from this end to the other; a
    // bone seen end-on (or a ball) uses a fixed direction, opposite at each end.
    vec3 d = other - anchor;
    d -= toCamera * dot(d, toCamera);
    float len = length(d);
    vec3 along;
    if (len > 1e-5 * r) {
        along = d / len;
    } else {
        vec3 helper = abs(toCamera.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
        along = normalize(cross(toCamera, helper)) * ((inCorner & 0x4000000u) != 0u ? -1.0 : 1.0);
    }
    vec3 across = cross(along, toCamera);
    uint corner = (inCorner >> 24) & 3u;
    vec3 side;
    if (corner == 0u) side = -along;
    else side = corner == 1u ? across : -across;
    // The sides in front of the axis by the radius, where the capsule's
    // surface faces the camera, so thick and thin capsules side by side
    // overlap as the meshes do; the tips stay at the axis' depth, behind the
    // next capsule along the limb, as the round caps of the meshes do.
    vec3 world = anchor + r * (corner == 0u ? side : side + toCamera);
    vWorldPos = world;
    vNormal = 1.5 * side + toCamera;
    vTint = vec4(inst.tint.rgb, float(inst.flags & 1u));
    gl_Position = frame.viewProj * vec4(world, 1.0);
}
