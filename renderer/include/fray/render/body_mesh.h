#pragma once
// The body mesh lives in fray_core (the exporters build it too); the renderer
// keeps its names.
#include "fray/core/body_mesh.h"

namespace fray::render {

using fray::BodyMesh;
using fray::BodyMeshOptions;
using fray::BodyVertex;
using fray::buildBodyMesh;
using fray::skeletonFingerprint;

}  // namespace fray::render
