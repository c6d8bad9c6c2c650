#pragma once
// Edits of a whole project that more than one tool needs: the editor wraps
// each in an undo command, and the CLI's annotate/cuts verbs can call the same
// functions. Plain C++ (no Qt). Errors say what was refused and why, naming
// the motion, action and field ("motion \"walk\", action 3: annotation
// \"kik\" is not in the project vocabulary").
#include <filesystem>
#include <optional>
#include <string>

#include "fray/core/result.h"
#include "fray/prep/project.h"

namespace fray::prep {

// Vocabulary words reach every action (annotations and proposals) and the
// combination table's "@word" keys, so renaming or removing one edits them all.
Status addVocabularyWord(Project& project, const std::string& word);
// Errors: `from` is not a word, `to` is invalid or already a word, or the
// rename would give two combination records the same (mine, theirs) pair.
Status renameVocabularyWord(Project& project, const std::string& from, const std::string& to);
// Drops the word from the vocabulary, from every action's annotations and
// proposals, and drops the combination records keyed "@word".
Status removeVocabularyWord(Project& project, const std::string& word);
// Actions annotated or proposed with `word`, plus combination records keyed "@word".
int vocabularyWordUses(const Project& project, const std::string& word);

// Checks an action description against its project: annotations and proposals
// from the vocabulary and not repeated, initial-condition ranges with min <= max.
// `where` prefixes the message ("motion \"walk\", action 3").
std::optional<std::string> checkActionInfo(const Project& project, const ActionInfo& info, const std::string& where);
// A contact label inside the motion's frames.
std::optional<std::string> checkContactLabel(const ProjectMotion& motion, const ContactLabel& label);
// The values projectFromJson accepts: a known graph preset, positive thresholds.
std::optional<std::string> checkSettings(const ProjectSettings& settings);

// The path to store for a motion when its project file moves from
// `fromProjectFile` to `toProjectFile` (Save As): absolute paths and paths of a
// project that stays in its folder are kept as written; relative ones are
// re-expressed from the new folder. An empty `fromProjectFile` means the
// current directory (an untitled project).
std::string rebaseMotionPath(const std::filesystem::path& fromProjectFile, const std::filesystem::path& toProjectFile,
                             const std::string& path);

}  // namespace fray::prep
