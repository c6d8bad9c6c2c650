#include "script_lines.h"

#include <charconv>
#include <cmath>

namespace fray::player {
namespace {

std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        if (i >= line.size()) break;
        std::size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
        out.push_back(line.substr(i, j - i));
        i = j;
    }
    return out;
}

}  // namespace

bool scriptInt(std::string_view word, int& out) {
    const auto r = std::from_chars(word.data(), word.data() + word.size(), out);
    return r.ec == std::errc() && r.ptr == word.data() + word.size();
}

bool scriptNumber(std::string_view word, double& out) {
    const auto r = std::from_chars(word.data(), word.data() + word.size(), out);
    return r.ec == std::errc() && r.ptr == word.data() + word.size();
}

Status forEachScriptLine(std::string_view text, std::string_view fileName, std::string_view usage,
                         const std::function<Status(const ScriptLine&)>& each) {
    ScriptLine line;
    std::size_t pos = 0;
    while (pos <= text.size()) {
        const std::size_t nl = text.find('\n', pos);
        std::string_view raw = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
        ++line.number;
        if (const auto hash = raw.find('#'); hash != std::string_view::npos) raw = raw.substr(0, hash);
        line.words = words(raw);
        if (line.words.empty()) continue;
        line.where = std::string(fileName) + ":" + std::to_string(line.number) + ": ";
        const std::string_view t = line.words[0];
        if (!scriptNumber(t, line.time) || !std::isfinite(line.time) || line.time < 0)
            return makeError(line.where + "'" + std::string(t) + "' is not a time in seconds >= 0 (" + std::string(usage) + ")");
        if (line.words.size() < 2) return makeError(line.where + "a time without a command");
        if (Status s = each(line); !s) return s;
    }
    return {};
}

}  // namespace fray::player
