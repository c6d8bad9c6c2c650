#include "fray/prep/project.h"


#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/prep/json_reader.h"
#include "fray/prep/annotations.h"

namespace fray::prep {
namespace {

using json = nlohmann::ordered_json;
using Reader = fray::prep::JsonReader;

const char* const kLaterSections[] = {"pattern_lists", "paintings", "trajectories", "scene", "planner_presets", "hand_made_patches"};

Result<std::optional<std::string>> optionalString(const Reader& rd, const json& obj, const std::string& path,
                                                  const char* key) {
    const auto it = obj.find(key);
    if (it == obj.end() || it->is_null()) return std::optional<std::string>{};
    FRAY_TRY(s, rd.string(*it, path + "/" + key));
    return std::optional<std::string>{std::move(s)};
}

json conditionsToJson(const InitialConditions& c) {
    return json{{"distance", {c.minDistance, c.maxDistance}},
                {"angle", {c.minAngle, c.maxAngle}},
                {"facing", {c.minFacing, c.maxFacing}},
                {"timing", {c.minTiming, c.maxTiming}}};
}

Result<InitialConditions> conditionsFromJson(const Reader& rd, const json& v, const std::string& path) {
    if (!v.is_object()) return rd.error(path, "must be an object");
    InitialConditions c;
    struct Range {
        const char* key;
        double* lo;
        double* hi;
    };
    const Range ranges[] = {{"distance", &c.minDistance, &c.maxDistance},
                            {"angle", &c.minAngle, &c.maxAngle},
                            {"facing", &c.minFacing, &c.maxFacing},
                            {"timing", &c.minTiming, &c.maxTiming}};
    for (const auto& r : ranges) {
        const std::string p = path + "/" + r.key;
        FRAY_TRY(f, rd.field(v, path, r.key));
        if (!f->is_array() || f->size() != 2) return rd.error(p, "must be [min, max]");
        FRAY_TRY(lo, rd.number((*f)[0], p + "/0"));
        FRAY_TRY(hi, rd.number((*f)[1], p + "/1"));
        if (hi < lo) return rd.error(p, "max is below min");
        *r.lo = lo;
        *r.hi = hi;
    }
    return c;
}

json actionToJson(const ActionInfo& a) {
    json j;
    j["name"] = a.name;
    j["annotations"] = a.annotations;
    j["proposed"] = a.proposed;
    j["joints"] = a.joints;
    j["attack_direction"] = a.attackDirection ? json(*a.attackDirection) : json(nullptr);
    j["defended_part"] = a.defendedPart ? json(*a.defendedPart) : json(nullptr);
    j["initial_conditions"] = a.initialConditions ? conditionsToJson(*a.initialConditions) : json(nullptr);
    return j;
}

Result<ActionInfo> actionFromJson(const Reader& rd, const json& v, const std::string& path,
                                  const std::vector<std::string>& vocabulary) {
    if (!v.is_object()) return rd.error(path, "must be an object");
    ActionInfo a;
    if (auto it = v.find("name"); it != v.end()) {
        FRAY_TRY(s, rd.string(*it, path + "/name"));
        a.name = std::move(s);
    }
    struct List {
        const char* key;
        std::vector<std::string>* out;
        bool vocab;
    };
    const List lists[] = {{"annotations", &a.annotations, true}, {"proposed", &a.proposed, true},
                          {"joints", &a.joints, false}};
    for (const auto& l : lists) {
        const auto it = v.find(l.key);
        if (it == v.end()) continue;
        FRAY_TRY(s, rd.strings(*it, path + "/" + l.key));
        if (l.vocab) {
            for (std::size_t i = 0; i < s.size(); ++i) {
                if (std::find(vocabulary.begin(), vocabulary.end(), s[i]) == vocabulary.end()) {
                    return rd.error(path + "/" + l.key + "/" + std::to_string(i),
                                    "\"" + s[i] + "\" is not in the project vocabulary");
                }
            }
        }
        *l.out = std::move(s);
    }
    FRAY_TRY(dir, optionalString(rd, v, path, "attack_direction"));
    a.attackDirection = std::move(dir);
    FRAY_TRY(part, optionalString(rd, v, path, "defended_part"));
    a.defendedPart = std::move(part);
    if (auto it = v.find("initial_conditions"); it != v.end() && !it->is_null()) {
        FRAY_TRY(c, conditionsFromJson(rd, *it, path + "/initial_conditions"));
        a.initialConditions = c;
    }
    return a;
}

Result<ProjectMotion> motionFromJson(const Reader& rd, const json& v, const std::string& path,
                                     const std::vector<std::string>& vocabulary) {
    if (!v.is_object()) return rd.error(path, "must be an object");
    ProjectMotion m;
    FRAY_TRY(idS, rd.stringAt(v, path, "id"));
    if (idS.empty()) return rd.error(path + "/id", "must not be empty");
    m.id = std::move(idS);
    FRAY_TRY(pS, rd.stringAt(v, path, "path"));
    if (pS.empty()) return rd.error(path + "/path", "must not be empty");
    m.path = std::move(pS);
    FRAY_TRY(units, optionalString(rd, v, path, "units"));
    m.units = units.value_or("");
    static const char* const kUnits[] = {"", "m", "cm", "mm", "inch", "cmu"};
    if (std::find(std::begin(kUnits), std::end(kUnits), m.units) == std::end(kUnits)) {
        return rd.error(path + "/units", "\"" + m.units + "\" must be one of m, cm, mm, inch, cmu or null");
    }
    FRAY_TRY(up, optionalString(rd, v, path, "up"));
    m.up = up.value_or("");
    if (m.up != "" && m.up != "y" && m.up != "z") return rd.error(path + "/up", "must be \"y\", \"z\" or null");

    FRAY_TRY(frames, rd.integerAt(v, path, "frame_count"));
    if (frames < 1) return rd.error(path + "/frame_count", "must be at least 1");
    m.actions.frameCount = frames;
    if (auto it = v.find("cuts"); it != v.end()) {
        if (!it->is_array()) return rd.error(path + "/cuts", "must be an array of frames");
        int prev = 0;
        for (std::size_t i = 0; i < it->size(); ++i) {
            const std::string cp = path + "/cuts/" + std::to_string(i);
            FRAY_TRY(c, rd.integer((*it)[i], cp));
            if (c <= prev || c >= frames) {
                return rd.error(cp, "cut " + std::to_string(c) + " must be after " + std::to_string(prev) +
                                        " and before frame_count " + std::to_string(frames));
            }
            prev = c;
            m.actions.cuts.push_back(c);
        }
    }
    m.actions.actions.resize(m.actions.cuts.size() + 1);
    if (auto it = v.find("actions"); it != v.end()) {
        if (!it->is_array()) return rd.error(path + "/actions", "must be an array");
        if (it->size() != m.actions.cuts.size() + 1) {
            return rd.error(path + "/actions", "holds " + std::to_string(it->size()) + " actions but " +
                                                   std::to_string(m.actions.cuts.size()) + " cuts make " +
                                                   std::to_string(m.actions.cuts.size() + 1));
        }
        for (std::size_t i = 0; i < it->size(); ++i) {
            FRAY_TRY(a, actionFromJson(rd, (*it)[i], path + "/actions/" + std::to_string(i), vocabulary));
            m.actions.actions[i] = std::move(a);
        }
    }
    if (auto it = v.find("contact_labels"); it != v.end()) {
        if (!it->is_array()) return rd.error(path + "/contact_labels", "must be an array");
        for (std::size_t i = 0; i < it->size(); ++i) {
            const std::string lp = path + "/contact_labels/" + std::to_string(i);
            const json& l = (*it)[i];
            if (!l.is_object()) return rd.error(lp, "must be an object");
            ContactLabel label;
            FRAY_TRY(first, rd.integerAt(l, lp, "first_frame"));
            FRAY_TRY(last, rd.integerAt(l, lp, "last_frame"));
            if (first < 0 || last < first || last >= frames) {
                return rd.error(lp, "frames " + std::to_string(first) + ".." + std::to_string(last) +
                                        " are outside the motion's 0.." + std::to_string(frames - 1));
            }
            label.firstFrame = first;
            label.lastFrame = last;
            for (const char* side : {"left", "right"}) {
                const auto s = l.find(side);
                if (s == l.end() || s->is_null()) continue;
                if (!s->is_boolean()) return rd.error(lp + "/" + side, "must be true, false or null");
                (std::string(side) == "left" ? label.left : label.right) = s->get<bool>();
            }
            m.contactLabels.push_back(label);
        }
    }
    return m;
}

}  // namespace

ProjectMotion* Project::findMotion(std::string_view id) {
    for (auto& m : motions) {
        if (m.id == id) return &m;
    }
    return nullptr;
}
const ProjectMotion* Project::findMotion(std::string_view id) const {
    return const_cast<Project*>(this)->findMotion(id);
}

Project makeProject(std::string name) {
    Project p;
    p.name = std::move(name);
    p.vocabulary = defaultVocabulary();
    return p;
}

std::string projectToJson(const Project& project) {
    json j;
    j["format"] = "fray-project";
    j["version"] = kProjectVersion;
    j["name"] = project.name;
    j["vocabulary"] = project.vocabulary;
    json settings;
    settings["graph_preset"] = project.settings.graphPreset;
    settings["graph_threshold"] =
        project.settings.graphThreshold ? json(*project.settings.graphThreshold) : json(nullptr);
    settings["segment_threshold_factor"] =
        project.settings.segmentThresholdFactor ? json(*project.settings.segmentThresholdFactor) : json(nullptr);
    j["settings"] = settings;
    json motions = json::array();
    for (const auto& m : project.motions) {
        json jm;
        jm["id"] = m.id;
        jm["path"] = m.path;
        jm["units"] = m.units.empty() ? json(nullptr) : json(m.units);
        jm["up"] = m.up.empty() ? json(nullptr) : json(m.up);
        jm["frame_count"] = m.actions.frameCount;
        jm["cuts"] = m.actions.cuts;
        json actions = json::array();
        for (const auto& a : m.actions.actions) actions.push_back(actionToJson(a));
        jm["actions"] = actions;
        json labels = json::array();
        for (const auto& l : m.contactLabels) {
            labels.push_back(json{{"first_frame", l.firstFrame},
                                  {"last_frame", l.lastFrame},
                                  {"left", l.left ? json(*l.left) : json(nullptr)},
                                  {"right", l.right ? json(*l.right) : json(nullptr)}});
        }
        jm["contact_labels"] = labels;
        motions.push_back(jm);
    }
    j["motions"] = motions;
    json combos = json::array();
    for (const auto& r : project.combos.records()) {
        combos.push_back(json{{"mine", r.mine}, {"theirs", r.theirs}, {"suitability", r.suitability}});
    }
    j["combos"] = combos;
    for (const char* key : kLaterSections) {
        const auto it = project.laterSections.find(key);
        if (it == project.laterSections.end()) continue;
        // Sections hold what projectFromJson (or a later issue's writer) made:
        // valid JSON. Should one not be, it is kept as a string, not dropped.
        json section = json::parse(it->second, nullptr, false);
        j[key] = section.is_discarded() ? json(it->second) : std::move(section);
    }
    return dumpJson(j, 2) + "\n";
}

Result<Project> projectFromJson(std::string_view text, std::string_view fileName) {
    auto parsed = parseJson(text, fileName);
    if (!parsed) return parsed.error();
    const json& j = *parsed;
    const Reader rd(fileName);
    if (!j.is_object()) return rd.error("", "the project must be a JSON object");
    FRAY_TRY(format, rd.field(j, "", "format"));
    if (!format->is_string() || format->get<std::string>() != "fray-project") {
        return rd.error("/format", "must be \"fray-project\" (is this a Fray project file?)");
    }
    FRAY_TRY(v, rd.integerAt(j, "", "version"));
    if (v < 1 || v > kProjectVersion) {
        return rd.error("/version", "version " + std::to_string(v) + " is not supported (this build reads 1.." +
                                        std::to_string(kProjectVersion) + "; a newer Fray wrote it?)");
    }
    Project p;
    if (auto it = j.find("name"); it != j.end()) {
        FRAY_TRY(name, rd.string(*it, "/name"));
        p.name = std::move(name);
    }
    if (auto it = j.find("vocabulary"); it != j.end()) {
        FRAY_TRY(words, rd.strings(*it, "/vocabulary"));
        for (std::size_t i = 0; i < words.size(); ++i) {
            if (!isValidAnnotation(words[i])) {
                return rd.error("/vocabulary/" + std::to_string(i),
                                "\"" + words[i] + "\" must be 1-32 lower-case letters, digits, '_' or '-'");
            }
        }
        p.vocabulary = std::move(words);
    } else {
        p.vocabulary = defaultVocabulary();
    }
    if (auto it = j.find("settings"); it != j.end()) {
        if (!it->is_object()) return rd.error("/settings", "must be an object");
        FRAY_TRY(preset, optionalString(rd, *it, "/settings", "graph_preset"));
        if (preset) {
            if (*preset != "fighting" && *preset != "locomotion") {
                return rd.error("/settings/graph_preset", "\"" + *preset + "\" must be \"fighting\" or \"locomotion\"");
            }
            p.settings.graphPreset = *preset;
        }
        // The same bounds as fray-cli's --threshold and --threshold-factor.
        struct Setting {
            const char* key;
            std::optional<double>* out;
            double max;
        };
        for (const Setting& st : {Setting{"graph_threshold", &p.settings.graphThreshold, 1e6},
                                  Setting{"segment_threshold_factor", &p.settings.segmentThresholdFactor, 1000.0}}) {
            const auto f = it->find(st.key);
            if (f == it->end() || f->is_null()) continue;
            FRAY_TRY(x, rd.number(*f, std::string("/settings/") + st.key));
            if (!(x > 0) || x > st.max) {
                return rd.error(std::string("/settings/") + st.key, "must be positive and at most " + Reader::fmt(st.max));
            }
            *st.out = x;
        }
    }
    FRAY_TRY(motions, rd.field(j, "", "motions"));
    if (!motions->is_array()) return rd.error("/motions", "must be an array");
    for (std::size_t i = 0; i < motions->size(); ++i) {
        const std::string path = "/motions/" + std::to_string(i);
        FRAY_TRY(m, motionFromJson(rd, (*motions)[i], path, p.vocabulary));
        if (p.findMotion(m.id)) return rd.error(path + "/id", "\"" + m.id + "\" is used by another motion");
        p.motions.push_back(std::move(m));
    }
    if (auto it = j.find("combos"); it != j.end()) {
        if (!it->is_array()) return rd.error("/combos", "must be an array");
        for (std::size_t i = 0; i < it->size(); ++i) {
            const std::string cp = "/combos/" + std::to_string(i);
            const json& c = (*it)[i];
            if (!c.is_object()) return rd.error(cp, "must be an object");
            ComboRecord r;
            FRAY_TRY(mineS, rd.stringAt(c, cp, "mine"));
            FRAY_TRY(theirsS, rd.stringAt(c, cp, "theirs"));
            FRAY_TRY(sf, rd.field(c, cp, "suitability"));
            FRAY_TRY(suitV, rd.numberIn(*sf, cp + "/suitability", -kMaxSuitability, kMaxSuitability));
            if (mineS.empty() || theirsS.empty()) return rd.error(cp, "mine and theirs must not be empty");
            if (p.combos.find(mineS, theirsS)) return rd.error(cp, "the pair appears twice");
            p.combos.set({mineS, theirsS, suitV});
        }
    }
    for (const char* key : kLaterSections) {
        if (auto it = j.find(key); it != j.end()) p.laterSections[key] = dumpJson(*it);
    }
    return p;
}

Result<Project> loadProject(const std::filesystem::path& file) {
    auto text = readWholeFile(file, "the project file");
    if (!text) return text.error();
    return projectFromJson(*text, file.string());
}

Status saveProject(const Project& project, const std::filesystem::path& file) {
    return writeFileAtomically(file, projectToJson(project));
}

std::filesystem::path resolveMotionPath(const std::filesystem::path& projectFile, const ProjectMotion& motion) {
    const std::filesystem::path p(motion.path);
    if (p.is_absolute()) return p;
    return (projectFile.parent_path().empty() ? std::filesystem::path(".") : projectFile.parent_path()) / p;
}

std::string relativeMotionPath(const std::filesystem::path& projectFile, const std::filesystem::path& motionFile) {
    std::error_code ec;
    const auto base = std::filesystem::weakly_canonical(
        std::filesystem::absolute(projectFile, ec).parent_path(), ec);
    const auto target = std::filesystem::weakly_canonical(std::filesystem::absolute(motionFile, ec), ec);
    if (!ec) {
        const auto rel = target.lexically_relative(base);
        if (!rel.empty()) return rel.generic_string();
    }
    return std::filesystem::absolute(motionFile).generic_string();
}

}  // namespace fray::prep
