#pragma once
// Warnings that save time (docs/DATA_PREP.md): problems of a project's action
// set that make later steps plan nonsense without failing. Plain data; the CLI
// prints them (segment, graph) and the editor can list them.
#include <string>
#include <utility>
#include <vector>

#include "fray/prep/project.h"

namespace fray::prep {

struct PrepWarning {
    // no-reactions, unknown-annotation, proposals-only
    std::string code;
    std::string message;  // one line, names the words and where they are used
};

// An annotation a later step relies on, and where (e.g. "duel.json: /a/actions").
struct AnnotationUse {
    std::string word;
    std::string where;
};

// Checks the project's actions:
//  - no-reactions: the set has attacks (punch, kick: confirmed or proposed)
//    but no reaction clip (an action with "pushed" or "falling", confirmed),
//    so duels and patches plan with no one ever reacting;
//  - unknown-annotation: an annotation used by a combination record ("@word")
//    or by `uses` that no action has confirmed;
//  - proposals-only: the actions carry proposals but no confirmed annotation,
//    and the planners read confirmed annotations only.
std::vector<PrepWarning> projectWarnings(const Project& project, const std::vector<AnnotationUse>& uses = {});

}  // namespace fray::prep
