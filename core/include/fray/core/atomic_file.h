#pragma once
// Whole-file I/O and the file-safety model of every save (docs/FILES.md).
//
// writeFileAtomically: the new contents go to a uniquely named temporary file
// in the target's folder, are flushed and fsync'd, then renamed over the
// target, and the folder is fsync'd. A failure at any step leaves the old
// file as it was. A symbolic link is followed: the file it points to is
// replaced and the link stays a link. The replaced file keeps its permission
// bits (and its owner and group where the process may set them). Hard links:
// the saved name gets the new contents; other names of the same file keep the
// old contents (renaming is what makes the save atomic).
//
// FileLock: an advisory lock (flock) on "<file>.lock" beside a file, for
// read-modify-write cycles between processes: take it, read the file again,
// edit, save, release.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "fray/core/result.h"

namespace fray {

// The largest file readWholeFile reads by default (1 GiB).
inline constexpr std::uintmax_t kMaxReadBytes = std::uintmax_t{1} << 30;

Status writeFileAtomically(const std::filesystem::path& path, std::string_view contents);

// The file a save of `path` replaces: `path` with symbolic links of its last
// component followed (relative links resolve against the link's folder).
std::filesystem::path resolveWriteTarget(const std::filesystem::path& path);

// Reads a whole regular file of at most maxBytes. Errors name the file and
// what it was meant to be: readWholeFile("p.frayproj", "the project file") ->
// "p.frayproj: cannot open the project file: no such file". Devices, pipes
// and folders are refused (reading /dev/zero would never end).
Result<std::string> readWholeFile(const std::filesystem::path& path, std::string_view what = "the file",
                                  std::uintmax_t maxBytes = kMaxReadBytes);

// An exclusive advisory lock on "<target>.lock" (target: resolveWriteTarget
// of the file). The lock file is created when missing and left in place
// (removing it would let two processes lock different files). Released by the
// destructor or when the process ends.
class FileLock {
public:
    // Waits up to `wait` for other holders; then an error naming the file.
    static Result<FileLock> acquire(const std::filesystem::path& file,
                                    std::chrono::milliseconds wait = std::chrono::seconds(30));
    static std::filesystem::path lockPathFor(const std::filesystem::path& file);

    FileLock(FileLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
    FileLock& operator=(FileLock&& other) noexcept;
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;
    ~FileLock();

private:
    explicit FileLock(int fd) : fd_(fd) {}
    int fd_ = -1;
};

}  // namespace fray
