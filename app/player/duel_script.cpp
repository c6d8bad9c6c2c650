#include "duel_script.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "fray/core/atomic_file.h"
#include "fray/igraph/igraph.h"

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

bool toInt(std::string_view s, int& out) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool toDouble(std::string_view s, double& out) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

}  // namespace

Result<std::vector<ScriptEvent>> parseScript(std::string_view text, std::string_view fileName) {
    std::vector<ScriptEvent> out;
    int lineNo = 0;
    std::size_t pos = 0;
    while (pos <= text.size()) {
        const std::size_t nl = text.find('\n', pos);
        std::string_view line = text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
        ++lineNo;
        if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        const auto w = words(line);
        if (w.empty()) continue;
        const std::string where = std::string(fileName) + ":" + std::to_string(lineNo) + ": ";
        ScriptEvent e;
        e.line = lineNo;
        if (!toDouble(w[0], e.time) || !std::isfinite(e.time) || e.time < 0) {
            return makeError(where + "'" + std::string(w[0]) + "' is not a time in seconds >= 0 (expected SECONDS COMMAND [CHARACTER], "
                                                                "SECONDS style NAME or SECONDS depth D)");
        }
        if (w.size() < 2) return makeError(where + "a time without a command");
        if (w[1] == "style") {
            if (w.size() != 3) return makeError(where + "expected SECONDS style NAME (general, infighter, outboxer)");
            if (auto st = igraph::stylePreset(w[2]); !st) return makeError(where + st.error().message);
            e.kind = ScriptEvent::Kind::Style;
            e.style = std::string(w[2]);
        } else if (w[1] == "depth") {
            if (w.size() != 3) return makeError(where + "expected SECONDS depth D");
            if (!toInt(w[2], e.depth) || e.depth < 1 || e.depth > kMaxPolicyDepth) {
                return makeError(where + "depth '" + std::string(w[2]) + "' is not a whole number from 1 to " + std::to_string(kMaxPolicyDepth));
            }
            e.kind = ScriptEvent::Kind::Depth;
        } else {
            auto c = igraph::parseCommand(w[1]);
            if (!c) return makeError(where + c.error().message + ", style or depth");
            e.command = *c;
            if (w.size() > 3) return makeError(where + "expected SECONDS COMMAND [CHARACTER], found more");
            if (w.size() == 3 && (!toInt(w[2], e.character) || e.character < 0)) {
                return makeError(where + "character '" + std::string(w[2]) + "' is not a character index >= 0");
            }
        }
        out.push_back(std::move(e));
    }
    std::stable_sort(out.begin(), out.end(), [](const ScriptEvent& a, const ScriptEvent& b) { return a.time < b.time; });
    return out;
}

Result<std::vector<ScriptEvent>> loadScript(const std::string& file) {
    auto text = readWholeFile(file, "the command file");
    if (!text) return text.error();
    if (std::filesystem::path(file).extension() == ".json") {
        auto commands = igraph::parseCommands(*text, file);
        if (!commands) return commands.error();
        std::vector<ScriptEvent> out;
        for (const auto& c : *commands) {
            ScriptEvent e;
            e.time = c.time;
            e.character = c.character;
            e.command = c.command;
            out.push_back(e);
        }
        return out;
    }
    return parseScript(*text, file);
}

Status checkCharacters(const std::vector<ScriptEvent>& events, int characters, std::string_view fileName) {
    for (const auto& e : events) {
        if (e.kind != ScriptEvent::Kind::Command || e.character < characters) continue;
        const std::string where = e.line > 0 ? std::string(fileName) + ":" + std::to_string(e.line) : std::string(fileName);
        return makeError(where + ": character " + std::to_string(e.character) + ": the match has " + std::to_string(characters) +
                         " characters (0-" + std::to_string(characters - 1) + ")");
    }
    return {};
}

}  // namespace fray::player
