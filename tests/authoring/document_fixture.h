#pragma once
// The demo project the build writes, opened as a document in a scratch folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include "fray/authoring/project_document.h"
#include "temp_dir.h"

namespace fray::test {

inline std::filesystem::path demoProject() { return FRAY_DEMO_PROJECT; }

inline std::string readFile(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A copy of the demo project in `dir`, opened.
inline std::unique_ptr<authoring::ProjectDocument> openDemoCopy(const TempDir& dir,
                                                                const std::string& name = "demo.frayproj") {
    const auto target = dir / name;
    std::filesystem::copy_file(demoProject(), target, std::filesystem::copy_options::overwrite_existing);
    auto doc = authoring::ProjectDocument::open(target);
    if (!doc) {
        ADD_FAILURE() << doc.error().message;
        return nullptr;
    }
    return std::move(*doc);
}

}  // namespace fray::test
