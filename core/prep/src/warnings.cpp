#include "fray/prep/warnings.h"

#include <algorithm>
#include <map>
#include <set>

namespace fray::prep {

std::vector<PrepWarning> projectWarnings(const Project& project, const std::vector<AnnotationUse>& uses) {
    std::vector<PrepWarning> out;
    std::set<std::string> confirmed;
    std::map<std::string, int> proposed;
    int actions = 0;
    for (const auto& m : project.motions) {
        for (const auto& a : m.actions.actions) {
            ++actions;
            confirmed.insert(a.annotations.begin(), a.annotations.end());
            for (const auto& w : a.proposed) ++proposed[w];
        }
    }
    if (actions == 0) return out;
    auto seen = [&](const char* w) { return confirmed.count(w) > 0 || proposed.count(w) > 0; };
    if ((seen("punch") || seen("kick")) && !confirmed.count("pushed") && !confirmed.count("falling")) {
        std::string msg = "no reaction clips: the project has attacks but no action annotated \"pushed\" or "
                          "\"falling\", so duels and patches plan with no one ever reacting";
        const int maybe = (proposed.count("falling") ? proposed.at("falling") : 0) +
                          (proposed.count("pushed") ? proposed.at("pushed") : 0);
        if (maybe > 0) {
            msg += " (" + std::to_string(maybe) + " action" + (maybe == 1 ? " has" : "s have") +
                   " a falling?/pushed? proposal to review)";
        } else {
            msg += "; import falls or pushes, or annotate the reactions you have";
        }
        out.push_back({"no-reactions", msg});
    }
    std::vector<AnnotationUse> all = uses;
    for (const auto& r : project.combos.records()) {
        for (const std::string* side : {&r.mine, &r.theirs}) {
            if (side->size() > 1 && (*side)[0] == '@') {
                all.push_back({side->substr(1), "combination record (" + r.mine + ", " + r.theirs + ")"});
            }
        }
    }
    std::set<std::pair<std::string, std::string>> reported;
    for (const auto& u : all) {
        if (confirmed.count(u.word) || !reported.insert({u.word, u.where}).second) continue;
        std::string msg = "annotation \"" + u.word + "\" is used by " + u.where + " but no action has it";
        if (proposed.count(u.word)) {
            msg += " confirmed (" + std::to_string(proposed.at(u.word)) + " proposed; confirm them with fray-cli annotate)";
        }
        out.push_back({"unknown-annotation", msg});
    }
    if (confirmed.empty() && !proposed.empty()) {
        std::string words;
        for (const auto& [w, n] : proposed) words += (words.empty() ? "" : ", ") + w + "? x" + std::to_string(n);
        out.push_back({"proposals-only", "the " + std::to_string(actions) +
                                             " actions carry proposals only (" + words +
                                             "), none confirmed: the planners read confirmed annotations; review "
                                             "them (fray-cli render --contact-sheet --action WORD, fray-cli annotate)"});
    }
    return out;
}

}  // namespace fray::prep
