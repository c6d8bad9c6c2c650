#include "duel_script.h"

#include <algorithm>
#include <filesystem>

#include "fray/core/atomic_file.h"
#include "fray/igraph/igraph.h"
#include "script_lines.h"

namespace fray::player {

Result<std::vector<ScriptEvent>> parseScript(std::string_view text, std::string_view fileName) {
    std::vector<ScriptEvent> out;
    const Status read = forEachScriptLine(
        text, fileName, "expected SECONDS COMMAND [CHARACTER], SECONDS style NAME or SECONDS depth D", [&](const ScriptLine& l) -> Status {
            const auto& w = l.words;
            const std::string& where = l.where;
            ScriptEvent e;
            e.line = l.number;
            e.time = l.time;
            if (w[1] == "style") {
                if (w.size() != 3) return makeError(where + "expected SECONDS style NAME (general, infighter, outboxer)");
                if (auto st = igraph::stylePreset(w[2]); !st) return makeError(where + st.error().message);
                e.kind = ScriptEvent::Kind::Style;
                e.style = std::string(w[2]);
            } else if (w[1] == "depth") {
                if (w.size() != 3) return makeError(where + "expected SECONDS depth D");
                if (!scriptInt(w[2], e.depth) || e.depth < 1 || e.depth > kMaxPolicyDepth) {
                    return makeError(where + "depth '" + std::string(w[2]) + "' is not a whole number from 1 to " +
                                     std::to_string(kMaxPolicyDepth));
                }
                e.kind = ScriptEvent::Kind::Depth;
            } else {
                auto c = igraph::parseCommand(w[1]);
                if (!c) return makeError(where + c.error().message + ", style or depth");
                e.command = *c;
                if (w.size() > 3) return makeError(where + "expected SECONDS COMMAND [CHARACTER], found more");
                if (w.size() == 3 && (!scriptInt(w[2], e.character) || e.character < 0)) {
                    return makeError(where + "character '" + std::string(w[2]) + "' is not a character index >= 0");
                }
            }
            out.push_back(std::move(e));
            return {};
        });
    if (!read) return read.error();
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
