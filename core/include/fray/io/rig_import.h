#pragma once
// A skinned rig read through Assimp (glTF/GLB, FBX, DAE, ...) and bound to a
// motion's skeleton, so the renderer can draw it instead of the capsules.
//
// - The rig is the skinned meshes of the file's first armature (a file with
//   several characters gives the first; a warning says so).
// - Rig bones are matched to skeleton joints by name: exactly, then ignoring
//   case, then without a namespace ("mixamorig:Hips", "Armature|Hips") or a
//   prefix all bones share ("red_Hips" in Fray's own FBX export).
// - Units and axes: the rig is scaled so its bones are as long as the
//   skeleton's (the median ratio over matched parent-child pairs; Fray's FBX in
//   centimetres comes out at 0.01), so the body fits the motion whatever the
//   file's unit.
// - Bind: when the rig's bone frames are the skeleton's joint frames (the rig
//   and the motion come from the same source, or Fray exported the rig), the
//   inverse binds are the bones' offset matrices (aiBone::mOffsetMatrix). When
//   they are not, but the rig is modelled in the skeleton's rest pose (a BVH's
//   T-pose with a rig whose bones carry their own rotations), each joint's
//   bind frame is its rest frame at the bone's position, the rig turned by the
//   axis-aligned rotation that best lines its bones up with the skeleton's
//   offsets (a Z-up file comes out Y-up). Whichever of the two fits the
//   skeleton better is used; a poor fit either way is a warning.
// - Each vertex keeps its four largest weights, renormalised.
//
// Errors name the file and what is missing: the file cannot be read
// (Assimp's message), no mesh, no skinned mesh, bones that match no joint
// (up to five names), vertices without weights.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fray/core/result.h"
#include "fray/core/retarget.h"
#include "fray/core/skeleton.h"
#include "fray/core/skinned_mesh.h"

namespace fray {

Result<SkinnedMesh> loadRig(const std::filesystem::path& path, const Skeleton& skeleton);

// The skeleton of a rig file (glTF/GLB, FBX, DAE, ... through Assimp, or BVH)
// as a retarget target for `export --rig` (docs/EXPORT.md): the subtree of
// the joint its names give as the pelvis, each joint's local frame as in the
// file, the bind pose (BVH: the rest pose) as the reference pose; units (m,
// cm, mm, inch) and up axis (Y or Z) read from the head-above-ankles height.
// Errors name the file and what is missing (no feet, no pelvis, ...). A rig
// without a skinned mesh is used as a skeleton; a warning says so.
struct RigSkeleton {
    RetargetTarget target;
    bool skinned = false;               // the file has a mesh with bone weights
    // The rig's own skinned mesh bound to target.skeleton (loadRig), for the
    // export to write instead of Fray's capsules; empty when the file has no
    // skin or it could not be bound (a warning then says why).
    std::optional<SkinnedMesh> skin;
    std::vector<std::string> warnings;  // for the user
};
Result<RigSkeleton> loadRigSkeleton(const std::filesystem::path& path);

}  // namespace fray
