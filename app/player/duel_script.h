#pragma once
// fray-play --duel --input FILE: timed commands that make a duel or team
// fight scriptable (tests, demos). A text file, one event a line:
//
//   # comment; blank lines are skipped
//   1.0   punch          # the user's character (0) punches at 1.0 s of match time
//   1.5   kick 2         # character 2 kicks (a team fight)
//   2.0   style outboxer # the opponent's style: general, infighter or outboxer
//   2.0   depth 5        # the opponent's policy depth (1-10)
//
// SECONDS is match time (a finite number >= 0); the commands are forward,
// back, turn-left, turn-right, punch, kick, dodge and avoid (the runtime's
// high-level commands: the best action of that kind in the graph). Events
// are applied in time order (equal times in file order). A FILE ending in
// .json is the runtime's command file instead ({"version": 1, "commands":
// [{"time": 2.0, "command": "punch", "character": 0}]}, docs/IGRAPH.md).
// Every error names the file and the line (or the JSON entry).
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"
#include "fray/igraph/runtime.h"

namespace fray::player {

struct ScriptEvent {
    enum class Kind { Command, Style, Depth };
    double time = 0;
    int line = 0;  // 1-based line in the file (JSON: 0)
    Kind kind = Kind::Command;
    igraph::Command command = igraph::Command::None;
    int character = 0;
    std::string style;
    int depth = 0;
};

inline constexpr int kMaxPolicyDepth = 10;

// Parses a script's text; fileName names it in errors ("FILE:LINE: ...").
Result<std::vector<ScriptEvent>> parseScript(std::string_view text, std::string_view fileName);
// Reads and parses FILE (text, or the runtime's JSON when it ends in .json).
Result<std::vector<ScriptEvent>> loadScript(const std::string& file);
// Every command's character must exist: "FILE:LINE: character 3: the match has 2 characters".
Status checkCharacters(const std::vector<ScriptEvent>& events, int characters, std::string_view fileName);

}  // namespace fray::player
