#pragma once
// The default body: a low-poly capsule per bone, built from the skeleton alone,
// rigidly skinned to the bone's parent joint. Shared by the renderer and the
// scene exporters (glTF, FBX). Vertices are stored in the joint's local frame,
// so the skinning transform of a vertex is just the world transform of its
// joint (no inverse bind matrices) and the GPU needs one position + one
// quaternion per joint; the exporters add the rest position of the joint.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "fray/core/skeleton.h"

namespace fray {

struct BodyVertex {
    glm::vec3 position;  // in the joint's local frame
    glm::vec3 normal;    // in the joint's local frame
    std::uint32_t joint;
};
static_assert(sizeof(BodyVertex) == 28);

struct BodyMeshOptions {
    int sides = 8;     // around each capsule (0: the renderer's choice)
    int capRings = 2;  // latitude rings per hemispherical cap, the equator included (0: the renderer's choice)
};

struct BodyMesh {
    std::vector<BodyVertex> vertices;
    std::vector<std::uint32_t> indices;  // triangles, counter-clockwise seen from outside
    int bones = 0;                       // capsules built
};

// One capsule of the default body: the segment a-b in its joint's local frame.
struct BodyCapsule {
    glm::vec3 a;
    glm::vec3 b;
    float radius;  // metres
    std::uint32_t joint;
};

// The capsules buildBodyMesh tessellates, in its order: one per bone from a
// joint to each child, one per end site (a round one for the head).
std::vector<BodyCapsule> bodyCapsules(const Skeleton& skeleton);

// Capsule radii come from the bone's role (torso, head, limbs; found by
// guessStandardJoints) and scale with the skeleton's rest size. Bones shorter
// than 1 mm get no capsule. Every vertex's joint is < skeleton.jointCount().
BodyMesh buildBodyMesh(const Skeleton& skeleton, const BodyMeshOptions& options = {});

// Content hash of what the body mesh depends on (parents, offsets, end sites,
// names); two skeletons with equal fingerprints share one GPU mesh.
std::uint64_t skeletonFingerprint(const Skeleton& skeleton);

}  // namespace fray
