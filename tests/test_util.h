#pragma once
// Helpers shared by the core tests.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace fray::test {

inline std::filesystem::path sharedMocap() { return std::filesystem::path(FRAY_SHARED_DIR) / "mocap"; }
inline std::filesystem::path testData() { return std::filesystem::path(FRAY_TEST_DATA); }

// All shared BVH files. Fails the calling test when the shared folder is missing.
inline std::vector<std::filesystem::path> sharedBvhFiles() {
    std::vector<std::filesystem::path> out;
    const auto root = sharedMocap();
    if (!std::filesystem::is_directory(root)) {
        ADD_FAILURE() << "shared mocap folder not found at " << root << " (set FRAY_SHARED_DIR)";
        return out;
    }
    for (const auto& e : std::filesystem::recursive_directory_iterator(root))
        if (e.is_regular_file() && e.path().extension() == ".bvh") out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace fray::test
