#include "fray/core/atomic_file.h"

#include <fstream>
#include <system_error>

namespace fray {

Status writeFileAtomically(const std::filesystem::path& path, std::string_view contents) {
    std::filesystem::path tmp = path;
    tmp += ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) return makeError(path.string() + ": cannot open for writing");
        f.write(contents.data(), static_cast<std::streamsize>(contents.size()));
        f.flush();
        if (!f) {
            f.close();
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            return makeError(path.string() + ": write failed (disk full?)");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        return makeError(path.string() + ": cannot replace the file: " + ec.message());
    }
    return {};
}

}  // namespace fray
