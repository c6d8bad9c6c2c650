#pragma once
// Import through Assimp (FBX, glTF/GLB, DAE, BVH, ...). Lives in the fray_io
// library, not fray_core, so the motion core stays free of third-party loaders.
//
// What the importer does (see docs/ASSIMP_NOTES.md for the format quirks):
// - picks the animation by name (or the first one);
// - binds channels to nodes by name; where several nodes share a name (glTF
//   allows it), the k-th channel of that name drives the k-th such node in
//   depth-first order;
// - picks the skeleton root by name, or takes the lowest common ancestor of
//   all animated nodes, and keeps the animated nodes below it plus the nodes
//   between them (depth-first, parents before children);
// - folds Assimp's FBX helper nodes ("<joint>_$AssimpFbx$_<part>": pre/post
//   rotation, pivots, offsets) into the joint they belong to, so joint names
//   are the names in the file;
// - samples every joint at a fixed rate (keys interpolated as Assimp does:
//   lerp for translations, shortest-path slerp for rotations);
// - ignores scale (keys and rest transforms) with a warning in
//   Motion::source().warnings, and keeps file units and axes (no global scale).
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "fray/core/motion.h"
#include "fray/core/result.h"

namespace fray {

struct AssimpImportOptions {
    std::string animation;      // animation name; empty = the first one
    std::string skeletonRoot;   // node name of the skeleton root; empty = detect
    double fps = 0.0;           // sampling rate; 0 = from the animation's keys (fallback 30)
    // Ask Assimp to keep FBX pivots as separate "$AssimpFbx$" helper nodes
    // (AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS). They are folded into the real
    // joints either way; false (the default) lets Assimp bake them itself.
    bool preserveFbxPivots = false;
    // Refuse animations whose sampled motion would exceed this many bytes.
    std::size_t maxMotionBytes = std::size_t{4} << 30;
};

// Converts the chosen skeleton and animation to a Motion in file units/axes
// (Assimp's own unit conversion is not applied; normalise afterwards).
// Per frame and joint the motion holds the local translation (rest offset
// included) and local rotation; the root gets 6 channels, other joints 3
// rotation channels (ZXY) plus 3 position channels when their translation
// leaves the rest offset. Errors name the file and say what is wrong.
Result<Motion> importWithAssimp(const std::filesystem::path& path, const AssimpImportOptions& options = {});

// Every skeleton of the file, for files with several characters (Fray's own
// glTF and FBX exports among them): when the animated nodes' common ancestor
// is not animated and several of its child subtrees hold animated nodes, one
// motion per such subtree (in file order), each as importWithAssimp would
// give it with that subtree's root; otherwise the one importWithAssimp gives.
Result<std::vector<Motion>> importAllWithAssimp(const std::filesystem::path& path,
                                                const AssimpImportOptions& options = {});

}  // namespace fray
