#include "fray/prep/project_edits.h"

#include <algorithm>

#include "fray/prep/annotations.h"

namespace fray::prep {
namespace {

namespace fs = std::filesystem;

bool contains(const std::vector<std::string>& list, const std::string& s) {
    return std::find(list.begin(), list.end(), s) != list.end();
}

void eraseWord(std::vector<std::string>& list, const std::string& word) {
    list.erase(std::remove(list.begin(), list.end(), word), list.end());
}

void renameWord(std::vector<std::string>& list, const std::string& from, const std::string& to) {
    std::replace(list.begin(), list.end(), from, to);
}

std::string inQuotes(const std::string& s) { return "\"" + s + "\""; }

fs::path folderOf(const fs::path& projectFile) {
    std::error_code ec;
    const fs::path parent = fs::absolute(projectFile.empty() ? fs::path("untitled") : projectFile, ec).parent_path();
    const fs::path canonical = fs::weakly_canonical(parent, ec);
    return ec ? parent.lexically_normal() : canonical;
}

}  // namespace

Status addVocabularyWord(Project& project, const std::string& word) {
    if (!isValidAnnotation(word)) {
        return makeError("vocabulary: " + inQuotes(word) + " must be 1-32 lower-case letters, digits, '_' or '-'");
    }
    if (contains(project.vocabulary, word)) return makeError("vocabulary: " + inQuotes(word) + " is already a word");
    project.vocabulary.push_back(word);
    return {};
}

Status renameVocabularyWord(Project& project, const std::string& from, const std::string& to) {
    if (!contains(project.vocabulary, from)) return makeError("vocabulary: " + inQuotes(from) + " is not a word");
    if (!isValidAnnotation(to)) {
        return makeError("vocabulary: " + inQuotes(to) + " must be 1-32 lower-case letters, digits, '_' or '-'");
    }
    if (contains(project.vocabulary, to)) {
        return makeError("vocabulary: cannot rename " + inQuotes(from) + " to " + inQuotes(to) + ": " + inQuotes(to) +
                         " is already a word");
    }
    const std::string fromKey = "@" + from, toKey = "@" + to;
    ComboTable combos;
    for (ComboRecord r : project.combos.records()) {
        if (r.mine == fromKey) r.mine = toKey;
        if (r.theirs == fromKey) r.theirs = toKey;
        if (combos.find(r.mine, r.theirs)) {
            return makeError("vocabulary: cannot rename " + inQuotes(from) + " to " + inQuotes(to) +
                             ": the combination table would hold (" + r.mine + ", " + r.theirs + ") twice");
        }
        combos.set(r);
    }
    renameWord(project.vocabulary, from, to);
    for (auto& m : project.motions) {
        for (auto& a : m.actions.actions) {
            renameWord(a.annotations, from, to);
            renameWord(a.proposed, from, to);
        }
    }
    project.combos = std::move(combos);
    return {};
}

Status removeVocabularyWord(Project& project, const std::string& word) {
    if (!contains(project.vocabulary, word)) return makeError("vocabulary: " + inQuotes(word) + " is not a word");
    const std::string key = "@" + word;
    ComboTable combos;
    for (const auto& r : project.combos.records()) {
        if (r.mine != key && r.theirs != key) combos.set(r);
    }
    eraseWord(project.vocabulary, word);
    for (auto& m : project.motions) {
        for (auto& a : m.actions.actions) {
            eraseWord(a.annotations, word);
            eraseWord(a.proposed, word);
        }
    }
    project.combos = std::move(combos);
    return {};
}

int vocabularyWordUses(const Project& project, const std::string& word) {
    int uses = 0;
    for (const auto& m : project.motions) {
        for (const auto& a : m.actions.actions) {
            if (contains(a.annotations, word) || contains(a.proposed, word)) ++uses;
        }
    }
    const std::string key = "@" + word;
    for (const auto& r : project.combos.records()) {
        if (r.mine == key || r.theirs == key) ++uses;
    }
    return uses;
}

std::optional<std::string> checkActionInfo(const Project& project, const ActionInfo& info, const std::string& where) {
    struct List {
        const char* field;
        const std::vector<std::string>* words;
    };
    for (const List& l : {List{"annotation", &info.annotations}, List{"proposal", &info.proposed}}) {
        for (std::size_t i = 0; i < l.words->size(); ++i) {
            const std::string& w = (*l.words)[i];
            if (!contains(project.vocabulary, w)) {
                return where + ": " + l.field + " " + inQuotes(w) + " is not in the project vocabulary";
            }
            if (std::find(l.words->begin(), l.words->begin() + static_cast<std::ptrdiff_t>(i), w) !=
                l.words->begin() + static_cast<std::ptrdiff_t>(i)) {
                return where + ": " + l.field + " " + inQuotes(w) + " appears twice";
            }
        }
    }
    for (std::size_t i = 0; i < info.joints.size(); ++i) {
        if (info.joints[i].empty()) return where + ": joint " + std::to_string(i) + " has no name";
    }
    if (const auto& c = info.initialConditions) {
        struct Range {
            const char* name;
            double lo, hi;
        };
        for (const Range& r : {Range{"distance", c->minDistance, c->maxDistance}, Range{"angle", c->minAngle, c->maxAngle},
                               Range{"facing", c->minFacing, c->maxFacing}, Range{"timing", c->minTiming, c->maxTiming}}) {
            if (!(r.lo <= r.hi)) {
                return where + ": initial-condition " + r.name + " range [" + std::to_string(r.lo) + ", " +
                       std::to_string(r.hi) + "] has its max below its min";
            }
        }
    }
    return std::nullopt;
}

std::optional<std::string> checkContactLabel(const ProjectMotion& motion, const ContactLabel& label) {
    const int frames = motion.actions.frameCount;
    if (label.firstFrame < 0 || label.lastFrame < label.firstFrame || label.lastFrame >= frames) {
        return "motion " + inQuotes(motion.id) + ": contact label frames " + std::to_string(label.firstFrame) + ".." +
               std::to_string(label.lastFrame) + " are outside the motion's 0.." + std::to_string(frames - 1);
    }
    return std::nullopt;
}

std::optional<std::string> checkSettings(const ProjectSettings& settings) {
    if (settings.graphPreset != "fighting" && settings.graphPreset != "locomotion") {
        return "graph preset " + inQuotes(settings.graphPreset) + " must be \"fighting\" or \"locomotion\"";
    }
    if (settings.graphThreshold && !(*settings.graphThreshold > 0)) return "graph threshold must be positive";
    if (settings.segmentThresholdFactor && !(*settings.segmentThresholdFactor > 0)) {
        return "segmentation threshold factor must be positive";
    }
    return std::nullopt;
}

std::string rebaseMotionPath(const fs::path& fromProjectFile, const fs::path& toProjectFile, const std::string& path) {
    const fs::path p(path);
    if (p.is_absolute()) return path;
    const fs::path from = folderOf(fromProjectFile);
    if (from == folderOf(toProjectFile)) return path;
    return relativeMotionPath(toProjectFile, (from / p).lexically_normal());
}

}  // namespace fray::prep
