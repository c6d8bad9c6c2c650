#pragma once
// Helpers shared by the core tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace fray::test {

inline std::filesystem::path sharedMocap() { return std::filesystem::path(FRAY_SHARED_DIR) / "mocap"; }
inline std::filesystem::path testData() { return std::filesystem::path(FRAY_TEST_DATA); }

// The shared folder is required: its absence fails the calling test.
inline bool requireSharedMocap() {
    if (std::filesystem::is_directory(sharedMocap())) return true;
    ADD_FAILURE() << "shared mocap folder not found at " << sharedMocap()
                  << " (configure with -DFRAY_SHARED_DIR=...); the tests need the real captures";
    return false;
}

// All shared files with this extension (".bvh", ".fbx"), sorted.
inline std::vector<std::filesystem::path> sharedFiles(const std::string& ext) {
    std::vector<std::filesystem::path> out;
    if (!requireSharedMocap()) return out;
    for (const auto& e : std::filesystem::recursive_directory_iterator(sharedMocap()))
        if (e.is_regular_file() && e.path().extension() == ext) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

inline std::vector<std::filesystem::path> sharedBvhFiles() { return sharedFiles(".bvh"); }

}  // namespace fray::test
