#pragma once
// BVH reader and writer. The reader streams the file in fixed-size chunks,
// caps memory for absurd joint/frame counts, and reports errors as
// "FILE:LINE: problem".
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "fray/core/motion.h"
#include "fray/core/result.h"

namespace fray {

struct BvhReadOptions {
    std::size_t maxJoints = 1024;
    std::size_t maxFrames = 10'000'000;
    // Refuse files whose decoded motion would exceed this many bytes.
    std::size_t maxMotionBytes = std::size_t{4} << 30;
    // Some converters (e.g. the CMU-135 BVH set) write world positions into the
    // position channels of inner joints. When a joint's position channels stray
    // far from its offset (more than twice the bone length on average) they are
    // ignored and the offset is used, with a warning in SourceInfo.
    bool ignoreForeignJointPositions = true;
};

// Reads a BVH file into a Motion in file units and axes (not normalised).
Result<Motion> readBvh(const std::filesystem::path& path, const BvhReadOptions& options = {});
// Same, from memory. `name` is used in error messages in place of a file name.
Result<Motion> readBvhFromMemory(std::string_view data, std::string_view name,
                                 const BvhReadOptions& options = {});

struct BvhWriteOptions {
    int precision = 9;  // significant digits for channel values
    // Each joint's Euler triple is the equivalent one nearest the previous
    // frame's (fray::nearestEquivalentEuler), so channels do not jump by 360
    // degrees where an angle wraps; off: each frame in the principal range.
    bool continuousEuler = false;
};

// Writes the motion with its skeleton's channel layout. Re-importing the output
// reproduces the motion to within 1e-5.
Status writeBvh(const Motion& motion, const std::filesystem::path& path, const BvhWriteOptions& options = {});
std::string writeBvhToString(const Motion& motion, const BvhWriteOptions& options = {});

}  // namespace fray
