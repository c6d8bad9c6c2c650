#include "fray/core/atomic_file.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <system_error>
#include <thread>

namespace fray {

namespace fs = std::filesystem;

namespace {

std::string errnoText(int err) { return std::strerror(err); }

// write(2) until done; false with errno set on failure.
bool writeAll(int fd, std::string_view data) {
    while (!data.empty()) {
        const ssize_t n = ::write(fd, data.data(), data.size());
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        data.remove_prefix(static_cast<std::size_t>(n));
    }
    return true;
}

// Flushes a folder's entries (the rename) to disk. Some file systems refuse
// fsync on a folder (EINVAL): the rename is then as durable as they make it.
void syncFolder(const fs::path& dir) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
}

std::atomic<unsigned> g_tempCounter{0};

}  // namespace

fs::path resolveWriteTarget(const fs::path& path) {
    fs::path p = path;
    for (int hop = 0; hop < 40; ++hop) {
        std::error_code ec;
        if (!fs::is_symlink(p, ec)) return p;
        const fs::path link = fs::read_symlink(p, ec);
        if (ec) return p;
        p = link.is_absolute() ? link : p.parent_path() / link;
    }
    return p;  // a loop of links: the rename below reports it
}

Status writeFileAtomically(const fs::path& path, std::string_view contents) {
    const fs::path target = resolveWriteTarget(path);
    const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    const std::string name = path.string();

    struct stat old {};
    const bool existed = ::stat(target.c_str(), &old) == 0;
    if (existed && !S_ISREG(old.st_mode)) {
        return makeError(ErrorKind::Io, name + ": is not a regular file (a folder, device or pipe); refusing to replace it");
    }

    // A fresh name per save (process id + counter), created exclusively: two
    // processes or threads saving the same file never share a temporary.
    fs::path tmp;
    int fd = -1;
    for (int attempt = 0; attempt < 1000 && fd < 0; ++attempt) {
        tmp = dir / ("." + target.filename().string() + "." + std::to_string(::getpid()) + "." +
                     std::to_string(g_tempCounter.fetch_add(1)) + ".tmp");
        fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST) {
            return makeError(ErrorKind::Io, name + ": cannot create a temporary file in " + dir.string() + ": " + errnoText(errno));
        }
    }
    if (fd < 0) return makeError(ErrorKind::Io, name + ": cannot create a temporary file in " + dir.string());

    auto abandon = [&](const std::string& why) {
        ::close(fd);
        ::unlink(tmp.c_str());
        return makeError(ErrorKind::Io, name + ": " + why);
    };
    if (!writeAll(fd, contents)) {
        const int err = errno;
        return abandon(err == ENOSPC ? "write failed: the disk is full" : "write failed: " + errnoText(err));
    }
    if (existed) {
        // Keep the replaced file's permissions; its owner and group where
        // allowed (only root may give a file away: failure is not an error).
        if (::fchmod(fd, old.st_mode & 07777) != 0) return abandon("cannot keep the file's permissions: " + errnoText(errno));
        if (old.st_uid != ::geteuid() || old.st_gid != ::getegid()) (void)!::fchown(fd, old.st_uid, old.st_gid);
    }
    if (::fsync(fd) != 0) {
        const int err = errno;
        return abandon(err == ENOSPC ? "write failed: the disk is full" : "cannot flush to disk: " + errnoText(err));
    }
    if (::close(fd) != 0) {
        const int err = errno;
        ::unlink(tmp.c_str());
        return makeError(ErrorKind::Io, name + ": write failed: " + errnoText(err));
    }
    if (::rename(tmp.c_str(), target.c_str()) != 0) {
        const int err = errno;
        ::unlink(tmp.c_str());
        return makeError(ErrorKind::Io, name + ": cannot replace the file: " + errnoText(err));
    }
    syncFolder(dir);
    return {};
}

Result<std::string> readWholeFile(const fs::path& path, std::string_view what, std::uintmax_t maxBytes) {
    const std::string prefix = path.string() + ": cannot open " + std::string(what);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) {
        const int err = errno;
        if (err == ENOENT) return makeError(ErrorKind::Io, prefix + ": no such file");
        if (err == EACCES) return makeError(ErrorKind::Io, prefix + ": permission denied");
        return makeError(ErrorKind::Io, prefix + ": " + errnoText(err));
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        const bool folder = S_ISDIR(st.st_mode);
        ::close(fd);
        return makeError(ErrorKind::Io, prefix + (folder ? ": it is a folder" : ": not a regular file (a device, pipe or socket)"));
    }
    if (static_cast<std::uintmax_t>(st.st_size) > maxBytes) {
        ::close(fd);
        return makeError(ErrorKind::Io, path.string() + ": " + std::string(what) + " is " + std::to_string(st.st_size) +
                         " bytes, more than the limit of " + std::to_string(maxBytes));
    }
    std::string out;
    out.resize(static_cast<std::size_t>(st.st_size));
    std::size_t got = 0;
    for (;;) {
        if (got == out.size()) {
            // The file may have grown since fstat: read on, within the limit.
            if (out.size() >= maxBytes) {
                char probe = 0;
                const ssize_t n = ::read(fd, &probe, 1);
                if (n == 0) break;
                ::close(fd);
                return makeError(ErrorKind::Io, path.string() + ": " + std::string(what) + " is more than the limit of " +
                                 std::to_string(maxBytes) + " bytes");
            }
            out.resize(std::min<std::uintmax_t>(maxBytes, out.size() + 65536));
        }
        const ssize_t n = ::read(fd, out.data() + got, out.size() - got);
        if (n < 0) {
            if (errno == EINTR) continue;
            const int err = errno;
            ::close(fd);
            return makeError(ErrorKind::Io, path.string() + ": read error in " + std::string(what) + ": " + errnoText(err));
        }
        if (n == 0) break;
        got += static_cast<std::size_t>(n);
    }
    ::close(fd);
    out.resize(got);
    return out;
}

fs::path FileLock::lockPathFor(const fs::path& file) {
    fs::path p = resolveWriteTarget(file);
    p += ".lock";
    return p;
}

Result<FileLock> FileLock::acquire(const fs::path& file, std::chrono::milliseconds wait) {
    const fs::path lockPath = lockPathFor(file);
    const int fd = ::open(lockPath.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) {
        return makeError(ErrorKind::Io, file.string() + ": cannot create the lock file " + lockPath.string() + ": " + errnoText(errno));
    }
    const auto deadline = std::chrono::steady_clock::now() + wait;
    for (;;) {
        if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return FileLock(fd);
        const int err = errno;
        if (err != EWOULDBLOCK && err != EINTR) {
            ::close(fd);
            return makeError(ErrorKind::Io, file.string() + ": cannot lock " + lockPath.string() + ": " + errnoText(err));
        }
        if (std::chrono::steady_clock::now() >= deadline) {
            ::close(fd);
            return makeError(file.string() + ": another program is still editing it (waited " +
                             std::to_string(wait.count() / 1000) + " s for " + lockPath.string() + "); try again");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

FileLock& FileLock::operator=(FileLock&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = other.fd_;
        other.fd_ = -1;
    }
    return *this;
}

FileLock::~FileLock() {
    if (fd_ >= 0) ::close(fd_);  // closing the descriptor releases the flock
}

}  // namespace fray
