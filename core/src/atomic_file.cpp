#include "fray/core/atomic_file.h"

#include <fstream>
#include <iterator>
#include <system_error>

namespace fray {

Status writeFileAtomically(const std::filesystem::path& path, std::string_view contents) {
    std::filesystem::path tmp = path;
    tmp += ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) return makeError(ErrorKind::Io, path.string() + ": cannot open for writing");
        f.write(contents.data(), static_cast<std::streamsize>(contents.size()));
        f.flush();
        if (!f) {
            f.close();
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            return makeError(ErrorKind::Io, path.string() + ": write failed (disk full?)");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        return makeError(ErrorKind::Io, path.string() + ": cannot replace the file: " + ec.message());
    }
    return {};
}

Result<std::string> readWholeFile(const std::filesystem::path& path, std::string_view what) {
    const std::string prefix = path.string() + ": cannot open " + std::string(what);
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return makeError(ErrorKind::Io, prefix + ": no such file");
    if (std::filesystem::is_directory(path, ec)) return makeError(ErrorKind::Io, prefix + ": it is a folder");
    std::ifstream f(path, std::ios::binary);
    if (!f) return makeError(ErrorKind::Io, prefix + ": permission denied?");
    std::string out((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (f.bad()) return makeError(ErrorKind::Io, path.string() + ": read error in " + std::string(what));
    return out;
}

}  // namespace fray
