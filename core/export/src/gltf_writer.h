#pragma once
// glTF 2.0 written directly (nlohmann-json for the document, our own binary
// buffer): docs/EXPORT.md says why not Assimp's glTF2 exporter.
#include <string>
#include <string_view>

#include "sampled_scene.h"

namespace fray::exporter {

enum class GltfContainer { Embedded, Binary };  // .gltf with a base64 data URI, or .glb

// The whole file. Per character: a group node named after the character
// (extras: side, group) over its joint hierarchy, a skin over the joints with
// the rest pose as bind pose, and a mesh node (at the scene root, as glTF
// wants for skinned meshes) with the capsule body and the side's material.
// One animation, named `name`, with a translation and a rotation channel per
// joint (LINEAR, sampled at the export rate, one shared time accessor).
std::string writeGltf(const SampledScene& scene, std::string_view name, GltfContainer container);

// Standard base64 with padding (the data URI of an embedded buffer).
std::string base64(std::string_view bytes);

}  // namespace fray::exporter
