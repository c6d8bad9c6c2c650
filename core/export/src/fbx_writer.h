#pragma once
// FBX through Assimp's exporter (binary FBX 7.5), in centimetres (FBX's
// default unit: UnitScaleFactor 1), Y up. Assimp 5.2's output is repaired
// (its nested lists lack their null records, so Assimp and Blender cannot read
// it back; its layers name elements it did not write) and its creation time
// fixed, so the file is readable and reproducible.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include "fray/core/result.h"
#include "sampled_scene.h"

namespace fray::exporter {

Result<std::string> writeFbx(const SampledScene& scene, std::string_view name);

// Binary FBX node records (FBX 7.x; 64-bit record headers from 7.5 on).
// Offset of the first property (its type code) of the first node at `path`
// (top-level node first), or nothing when the path does not exist.
std::optional<std::size_t> fbxPropertyOffset(std::string_view bytes, std::initializer_list<std::string_view> path);

// Assimp writes the wall-clock time into FBXHeaderExtension/CreationTimeStamp;
// this sets it to the fixed time Assimp writes in CreationTime
// (1970-01-01 10:00:00:000) so the file is reproducible. A file without the
// node is left as it is; one whose fields are not 32-bit integers is an error.
Status fixFbxCreationTime(std::string& bytes);

}  // namespace fray::exporter
