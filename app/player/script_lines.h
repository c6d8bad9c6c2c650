#pragma once
// The line format shared by fray-play's scripts (--duel/--teams and --carry
// --input FILE): one timed event a line, "SECONDS COMMAND [ARGUMENT...]",
// '#' starts a comment, blank lines are skipped. Each mode's parser reads
// the commands it knows from the lines this one hands it.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"

namespace fray::player {

struct ScriptLine {
    int number = 0;                       // 1-based line in the file
    double time = 0;                      // SECONDS: finite, >= 0
    std::vector<std::string_view> words;  // the line's words: [0] the time, [1] the command, then its arguments
    std::string where;                    // "FILE:LINE: ", to start an error with
};

// Calls `each` on every line that holds an event, in file order, after
// checking that it starts with a time and has a command; `usage` ends the
// error for a line that does not ("expected SECONDS COMMAND"). Stops at the
// first error, from here or from `each`.
Status forEachScriptLine(std::string_view text, std::string_view fileName, std::string_view usage,
                         const std::function<Status(const ScriptLine&)>& each);

// The whole word as a number (no trailing characters).
bool scriptInt(std::string_view word, int& out);
bool scriptNumber(std::string_view word, double& out);

}  // namespace fray::player
