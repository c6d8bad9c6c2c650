#pragma once
// What fray_io's importers (motions, rigs) say when Assimp fails, how a
// failed internal check of Assimp becomes such a failure instead of an abort,
// and how the rig readers set up their importer.
#include <string>

namespace Assimp {
class Importer;
// Assimp's assertion handler, replaced for the whole program in assimp_errors.cpp.
void aiAssertViolation(const char* failedExpression, const char* file, int line);
}  // namespace Assimp

namespace fray {

// The importer's error text on one line ("unknown error" when it gave none).
std::string assimpErrorText(const Assimp::Importer& importer);

// An importer for reading a rig's nodes and meshes only: no materials,
// textures, cameras, lights or animations, and no stick-figure mesh made up
// for a file that has none (BVH).
void configureRigImporter(Assimp::Importer& importer);

}  // namespace fray
