#include "fray/setup/hand_made.h"

#include <cmath>
#include <numbers>

#include <nlohmann/json.hpp>

#include "fray/prep/json_reader.h"

namespace fray::setup {
namespace {

using json = nlohmann::ordered_json;
using prep::JsonReader;
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr int kSectionVersion = 1;

double rounded(double v, double unit) { return std::round(v / unit) * unit; }

}  // namespace

Result<std::vector<HandMadePatch>> projectHandMadePatches(const prep::Project& project, std::string_view fileName) {
    std::vector<HandMadePatch> out;
    const auto it = project.laterSections.find(kHandMadeSection);
    if (it == project.laterSections.end()) return out;
    const JsonReader rd(fileName);
    const std::string base = std::string("/") + kHandMadeSection;
    auto parsed = prep::parseJson(it->second, fileName);
    if (!parsed) return parsed.error();
    const json& j = *parsed;
    if (!j.is_object()) return rd.error(base, "must be an object {version, patches}");
    if (auto v = j.find("version"); v != j.end()) {
        FRAY_TRY(version, rd.integer(*v, base + "/version"));
        if (version != kSectionVersion) return rd.error(base + "/version", "version " + std::to_string(version) + " is not supported (this build reads 1)");
    }
    const auto ps = j.find("patches");
    if (ps == j.end()) return out;
    if (!ps->is_array()) return rd.error(base + "/patches", "must be an array");
    for (std::size_t i = 0; i < ps->size(); ++i) {
        const std::string p = base + "/patches/" + std::to_string(i);
        const json& h = (*ps)[i];
        if (!h.is_object()) return rd.error(p, "must be an object {pattern, r, theta1_deg, theta2_deg, delay, actions}");
        HandMadePatch m;
        FRAY_TRY(pattern, rd.stringAt(h, p, "pattern"));
        if (pattern.empty()) return rd.error(p + "/pattern", "must not be empty");
        m.pattern = pattern;
        FRAY_TRY(rField, rd.field(h, p, "r"));
        FRAY_TRY(r, rd.numberIn(*rField, p + "/r", 0, 10));
        m.initial.r = r;
        for (auto [key, slot] : {std::pair<const char*, double*>{"theta1_deg", &m.initial.theta1}, {"theta2_deg", &m.initial.theta2}}) {
            FRAY_TRY(f, rd.field(h, p, key));
            FRAY_TRY(deg, rd.numberIn(*f, p + "/" + key, -360, 360));
            *slot = deg * kDeg;
        }
        if (auto d = h.find("delay"); d != h.end()) {
            FRAY_TRY(delay, rd.numberIn(*d, p + "/delay", 0, 10));
            m.initial.delay = delay;
        }
        FRAY_TRY(acts, rd.field(h, p, "actions"));
        if (!acts->is_array() || acts->size() != 2) return rd.error(p + "/actions", "must be [[character 1's actions], [character 2's actions]]");
        for (std::size_t c = 0; c < 2; ++c) {
            FRAY_TRY(names, rd.strings((*acts)[c], p + "/actions/" + std::to_string(c)));
            m.actions[c] = std::move(names);
        }
        if (m.actions[0].empty()) return rd.error(p + "/actions/0", "character 1 needs at least one action");
        out.push_back(std::move(m));
    }
    return out;
}

std::string handMadePatchesToJson(const std::vector<HandMadePatch>& patches) {
    json j;
    j["version"] = kSectionVersion;
    json arr = json::array();
    for (const HandMadePatch& m : patches) {
        json h;
        h["pattern"] = m.pattern;
        h["r"] = rounded(m.initial.r, 1e-4);
        h["theta1_deg"] = rounded(m.initial.theta1 / kDeg, 1e-3);
        h["theta2_deg"] = rounded(m.initial.theta2 / kDeg, 1e-3);
        h["delay"] = rounded(m.initial.delay, 1e-4);
        h["actions"] = json::array({m.actions[0], m.actions[1]});
        arr.push_back(std::move(h));
    }
    j["patches"] = std::move(arr);
    return prep::dumpJson(j, 2);
}

void setProjectHandMadePatches(prep::Project& project, const std::vector<HandMadePatch>& patches) {
    if (patches.empty()) {
        project.laterSections.erase(kHandMadeSection);
        return;
    }
    project.laterSections[kHandMadeSection] = handMadePatchesToJson(patches);
}

Result<sim::PatternList> handMadePattern(const sim::PatternSet& set, const std::string& name) {
    for (const sim::PatternList& p : set.patterns)
        if (p.name == name) return p;
    for (const sim::PatternList& p : sim::defaultPatterns())
        if (p.name == name) return p;
    return makeError("hand-made patch: no PatternList '" + name + "' in the project or the defaults");
}

Status buildHandMadePatch(const sim::ActionLibrary& lib, const sim::PatternSet& set, const HandMadePatch& recipe, sim::PatchLibrary& out) {
    FRAY_TRY(pattern, handMadePattern(set, recipe.pattern));
    std::array<std::vector<int>, 2> actions;
    for (std::size_t c = 0; c < 2; ++c) {
        for (const std::string& label : recipe.actions[c]) {
            int found = -1;
            for (int a = 0; a < lib.size() && found < 0; ++a)
                if (lib.actions()[static_cast<std::size_t>(a)].label() == label) found = a;
            if (found < 0) {
                return makeError("hand-made patch (" + recipe.pattern + "): character " + std::to_string(c + 1) + "'s action '" + label +
                                 "' is not in the action library");
            }
            actions[c].push_back(found);
        }
    }
    auto st = sim::addHandMadePatch(lib, pattern, recipe.initial, actions, out, {});
    if (!st) return makeError(st.error().message + " (pattern " + recipe.pattern + ")");
    return {};
}

}  // namespace fray::setup
