#pragma once
// The sampled scene as an Assimp scene, for Assimp's exporters (FBX): the same
// content as the glTF file. Assimp's FBX exporter binds bones to nodes by name,
// so joint nodes are named "<character>_<joint>" to keep them unique.
#include <memory>
#include <string>
#include <string_view>

#include <assimp/scene.h>

#include "sampled_scene.h"

namespace fray::exporter {

// unitScale multiplies every length (100: metres -> centimetres).
std::unique_ptr<aiScene> buildAssimpScene(const SampledScene& scene, std::string_view name, float unitScale);

std::string jointNodeName(const CharacterTake& character, int joint);

}  // namespace fray::exporter
