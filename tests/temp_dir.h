#pragma once
// A fresh folder under the system temp directory, removed at scope exit.
// Shared by the test binaries.
#include <filesystem>
#include <random>
#include <string>
#include <system_error>

namespace fray::test {

class TempDir {
public:
    explicit TempDir(const std::string& prefix = "fray_test_") {
        std::random_device rd;
        path_ = std::filesystem::temp_directory_path() / (prefix + std::to_string(rd()) + std::to_string(rd()));
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

}  // namespace fray::test
