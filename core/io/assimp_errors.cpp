#include "assimp_errors.h"

#include <stdexcept>

#include <assimp/Importer.hpp>
#include <assimp/config.h>

// Debian's Assimp 5.2.5 is built with its internal assertions on, and a failed
// one calls Assimp::aiAssertViolation, which aborts the process. Damaged files
// trip them: an FBX export with three bytes changed stops the program in
// FBXConverter.cpp:1523 ('out_idx != nullptr'). The library calls the handler
// through the PLT, so this definition replaces it in any program that links
// fray_io: it throws, Assimp's importer catches the exception (as it does its
// own import errors) and ReadFile fails with this text, which the importers
// report as "<file>: Assimp cannot read the file: Assimp's internal check
// failed: ...". Without assertions in the library this is never called.
namespace Assimp {
void aiAssertViolation(const char* failedExpression, const char* file, int line) {
    throw std::runtime_error(std::string("Assimp's internal check failed: ") + (failedExpression ? failedExpression : "?") + " (" +
                             (file ? file : "?") + ":" + std::to_string(line) + ")");
}
}  // namespace Assimp

namespace fray {

std::string assimpErrorText(const Assimp::Importer& importer) {
    std::string s = importer.GetErrorString();
    for (char& c : s)
        if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s.empty() ? std::string("unknown error") : s;
}

void configureRigImporter(Assimp::Importer& importer) {
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_MATERIALS, false);
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_TEXTURES, false);
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_CAMERAS, false);
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_LIGHTS, false);
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_ANIMATIONS, false);
    importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
}

}  // namespace fray
