#include "fray/sim/patterns.h"

#include <algorithm>

#include "fray/prep/json_reader.h"

namespace fray::sim {

namespace {

using json = nlohmann::ordered_json;
using prep::JsonReader;

constexpr const char* kGroups[] = {"attack", "defence", "fall", "any"};

bool isGroup(const std::string& a) {
    return std::find(std::begin(kGroups), std::end(kGroups), a) != std::end(kGroups);
}

Result<std::pair<double, double>> pairAt(const JsonReader& rd, const json& obj, const std::string& path, const char* key,
                                         std::pair<double, double> fallback) {
    FRAY_TRY(f, rd.field(obj, path, key, false));
    if (!f) return fallback;
    const std::string p = path + "/" + key;
    if (!f->is_array() || f->size() != 2) return rd.error(p, "must be [low, high]");
    FRAY_TRY(lo, rd.number((*f)[0], p + "/0"));
    FRAY_TRY(hi, rd.number((*f)[1], p + "/1"));
    if (lo > hi) return rd.error(p, "low is above high");
    return std::pair{lo, hi};
}

Result<InitialRange> rangeFromJson(const JsonReader& rd, const json& v, const std::string& path, const InitialRange& base) {
    if (!v.is_object()) return rd.error(path, "must be an object");
    for (auto it = v.begin(); it != v.end(); ++it) {
        if (it.key() != "distance" && it.key() != "angle_deg" && it.key() != "delay") {
            return rd.error(path + "/" + it.key(), "unknown field (expected distance, angle_deg, delay)");
        }
    }
    InitialRange r = base;
    FRAY_TRY(d, pairAt(rd, v, path, "distance", {r.minDistance, r.maxDistance}));
    FRAY_TRY(a, pairAt(rd, v, path, "angle_deg", {r.minAngle, r.maxAngle}));
    FRAY_TRY(t, pairAt(rd, v, path, "delay", {r.minDelay, r.maxDelay}));
    if (d.first < 0) return rd.error(path + "/distance", "must not be negative");
    if (a.first < -180 || a.second > 180) return rd.error(path + "/angle_deg", "must lie within [-180, 180]");
    if (t.first < 0) return rd.error(path + "/delay", "must not be negative");
    r.minDistance = d.first, r.maxDistance = d.second;
    r.minAngle = a.first, r.maxAngle = a.second;
    r.minDelay = t.first, r.maxDelay = t.second;
    return r;
}

json rangeToJson(const InitialRange& r) {
    return json{{"distance", {r.minDistance, r.maxDistance}},
                {"angle_deg", {r.minAngle, r.maxAngle}},
                {"delay", {r.minDelay, r.maxDelay}}};
}

Result<PatternList> patternFromJson(const JsonReader& rd, const json& v, const std::string& path,
                                    const std::vector<std::string>& vocabulary) {
    if (!v.is_object()) return rd.error(path, "must be an object");
    for (auto it = v.begin(); it != v.end(); ++it) {
        static const char* const known[] = {"name", "entries", "weights", "threshold", "keep_per_path", "spread"};
        if (std::find_if(std::begin(known), std::end(known), [&](const char* k) { return it.key() == k; }) == std::end(known)) {
            return rd.error(path + "/" + it.key(), "unknown field (expected name, entries, weights, threshold, keep_per_path, spread)");
        }
    }
    PatternList p;
    FRAY_TRY(name, rd.stringAt(v, path, "name"));
    if (name.empty()) return rd.error(path + "/name", "must not be empty");
    p.name = name;
    FRAY_TRY(entries, rd.field(v, path, "entries"));
    if (!entries->is_array() || entries->empty()) return rd.error(path + "/entries", "must be a non-empty array");
    for (std::size_t i = 0; i < entries->size(); ++i) {
        const std::string ep = path + "/entries/" + std::to_string(i);
        const json& e = (*entries)[i];
        if (!e.is_object()) return rd.error(ep, "must be an object {character, annotation}");
        FRAY_TRY(ch, rd.integerAt(e, ep, "character"));
        if (ch != 1 && ch != 2) return rd.error(ep + "/character", "must be 1 or 2");
        FRAY_TRY(ann, rd.stringAt(e, ep, "annotation"));
        if (!isGroup(ann) && std::find(vocabulary.begin(), vocabulary.end(), ann) == vocabulary.end()) {
            return rd.error(ep + "/annotation",
                            "unknown annotation '" + ann + "' (not in the project vocabulary, nor attack/defence/fall/any)");
        }
        p.entries.push_back({ch - 1, ann});
    }
    const bool both = std::any_of(p.entries.begin(), p.entries.end(), [](const PatternEntry& e) { return e.character == 0; }) &&
                      std::any_of(p.entries.begin(), p.entries.end(), [](const PatternEntry& e) { return e.character == 1; });
    if (!both) return rd.error(path + "/entries", "needs entries for both characters 1 and 2");
    FRAY_TRY(w, rd.field(v, path, "weights", false));
    if (w) {
        if (!w->is_object()) return rd.error(path + "/weights", "must be an object");
        for (auto it = w->begin(); it != w->end(); ++it) {
            const std::string wp = path + "/weights/" + it.key();
            FRAY_TRY(x, rd.number(it.value(), wp));
            if (x < 0) return rd.error(wp, "must not be negative");
            if (it.key() == "contact") p.weights.contact = x;
            else if (it.key() == "distance") p.weights.distance = x;
            else if (it.key() == "timing") p.weights.timing = x;
            else return rd.error(wp, "unknown weight (expected contact, distance, timing)");
        }
        if (p.weights.contact + p.weights.distance + p.weights.timing <= 0) {
            return rd.error(path + "/weights", "at least one weight must be positive");
        }
    }
    FRAY_TRY(keep, rd.field(v, path, "keep_per_path", false));
    if (keep) {
        FRAY_TRY(x, rd.integer(*keep, path + "/keep_per_path"));
        if (x < 0 || x > 1000) return rd.error(path + "/keep_per_path", "must be between 0 (all) and 1000");
        p.keepPerPath = x;
    }
    FRAY_TRY(spread, rd.field(v, path, "spread", false));
    if (spread) {
        if (!spread->is_boolean()) return rd.error(path + "/spread", "must be true or false");
        p.spread = spread->get<bool>();
    }
    FRAY_TRY(th, rd.field(v, path, "threshold", false));
    if (th) {
        FRAY_TRY(x, rd.number(*th, path + "/threshold"));
        if (x < 0 || x > 1) return rd.error(path + "/threshold", "must lie within [0, 1]");
        p.threshold = x;
    }
    return p;
}

}  // namespace

const PatternList* PatternSet::find(std::string_view name) const {
    for (const auto& p : patterns) {
        if (p.name == name) return &p;
    }
    return nullptr;
}

InitialRange PatternSet::rangeFor(const std::string& annotation) const {
    for (const auto& [key, r] : ranges) {
        if (key == annotation) return r;
    }
    return defaultRange(annotation);
}

InitialRange defaultRange(const std::string& a) {
    InitialRange r;  // attack / defence / punch defaults
    if (a == "kick") r.minDistance = 0.8, r.maxDistance = 1.6;
    if (a == "attack") r.maxDistance = 1.6;
    if (a == "block" || a == "avoid" || a == "dodge" || a == "defence") r.minDistance = 0.6, r.maxDistance = 1.6;
    // Anyone can be knocked over from any side.
    if (a == "pushed" || a == "falling" || a == "fall") r.minDistance = 0.4, r.maxDistance = 1.4, r.minAngle = -180, r.maxAngle = 160;
    if (a == "carry" || a == "hand" || a == "receive") {
        r.minDistance = 0.6, r.maxDistance = 1.2, r.minAngle = -20, r.maxAngle = 20, r.maxDelay = 0.6;
    }
    if (a == "any" || a == "idle" || a == "walk" || a == "run" || a == "step" || a == "turn" || a == "transition") {
        r.minDistance = 0.6, r.maxDistance = 2.0, r.minAngle = -60, r.maxAngle = 60;
    }
    // A runner meets a tackler coming at it from a few strides away.
    if (a == "run") r.maxDistance = 6.0;
    if (a == "tackle") r.minDistance = 3.0, r.maxDistance = 6.0, r.minAngle = -40, r.maxAngle = 40, r.maxDelay = 0.3;
    return r;
}

std::vector<PatternList> defaultPatterns() {
    auto make = [](std::string name, std::vector<PatternEntry> e) {
        PatternList p;
        p.name = std::move(name);
        p.entries = std::move(e);
        return p;
    };
    // Domino (SPEC 4.5): a falling body knocks the next character down.
    PatternList domino = make("fall-fall", {{0, "fall"}, {1, "fall"}});
    domino.weights = {1.0, 0.0, 0.0};
    domino.keepPerPath = 0;
    // American football (SPEC 4.5): the carrier runs, a tackler dives at it,
    // the carrier cuts away. Judged by how close the tackle came and timing:
    // the two are metres apart for most of it, so distance does not count.
    PatternList football = make("run-tackle-avoid", {{0, "run"}, {1, "tackle"}, {0, "avoid"}});
    football.weights = {1.0, 0.0, 1.0};
    football.keepPerPath = 12;
    football.spread = true;  // tacklers from every distance and side, not the first grid row
    return {
        make("attack-defence-attack-fall", {{0, "attack"}, {1, "defence"}, {0, "attack"}, {1, "fall"}}),
        make("attack-fall", {{0, "attack"}, {1, "fall"}}),
        make("attack-attack-fall", {{0, "attack"}, {0, "attack"}, {1, "fall"}}),
        make("attack-defence", {{0, "attack"}, {1, "defence"}}),
        make("attack-pushed", {{0, "attack"}, {1, "pushed"}}),
        domino,
        // Luggage passing (SPEC 4.5): the thesis' list, and a shorter one.
        make("carry-walk-hand-receive-turn-carry", {{0, "carry"}, {0, "walk"}, {0, "hand"}, {1, "receive"}, {1, "turn"}, {1, "carry"}}),
        make("carry-hand-receive-carry", {{0, "carry"}, {0, "hand"}, {1, "receive"}, {1, "carry"}}),
        football,
    };
}

bool matchesAnnotation(const LibraryAction& action, const std::string& a) {
    // Handing and receiving need a partner: such an action only plays an
    // entry that asks for it (a hand-over is not just "carry").
    for (const char* partnered : {"hand", "receive"}) {
        if (action.has(partnered) && a != partnered) return false;
    }
    if (a == "any") return !action.is(kReactive);
    if (a == "attack") return action.is(kPunch | kKick) && action.effector >= 0;  // SPEC 4.5: punch or kick
    if (a == "defence") return action.has("avoid") || action.has("dodge");
    if (a == "fall") return action.is(kFalling);
    if (a == "punch" || a == "kick") return action.has(a) && action.effector >= 0;
    return action.has(a);
}

bool isReactiveAnnotation(const std::string& a) { return a == "pushed" || a == "falling" || a == "fall"; }

bool isResponse(const PatternList& pattern, std::size_t e) {
    const auto& entry = pattern.entries[e];
    return isReactiveAnnotation(entry.annotation) && !(e == 0 && entry.character == 0);
}

Result<PatternSet> projectPatterns(const prep::Project& project, std::string_view fileName) {
    PatternSet set;
    const auto it = project.laterSections.find(kPatternSection);
    if (it == project.laterSections.end()) return set;
    const JsonReader rd(fileName);
    const std::string base = std::string("/") + kPatternSection;
    const json j = json::parse(it->second, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return rd.error(base, "must be an object {patterns, initial_conditions}");
    for (auto f = j.begin(); f != j.end(); ++f) {
        if (f.key() != "patterns" && f.key() != "initial_conditions") {
            return rd.error(base + "/" + f.key(), "unknown field (expected patterns, initial_conditions)");
        }
    }
    FRAY_TRY(patterns, rd.field(j, base, "patterns", false));
    if (patterns) {
        if (!patterns->is_array()) return rd.error(base + "/patterns", "must be an array");
        for (std::size_t i = 0; i < patterns->size(); ++i) {
            const std::string pp = base + "/patterns/" + std::to_string(i);
            FRAY_TRY(p, patternFromJson(rd, (*patterns)[i], pp, project.vocabulary));
            if (set.find(p.name)) return rd.error(pp + "/name", "pattern '" + p.name + "' appears twice");
            set.patterns.push_back(std::move(p));
        }
    }
    FRAY_TRY(ranges, rd.field(j, base, "initial_conditions", false));
    if (ranges) {
        if (!ranges->is_object()) return rd.error(base + "/initial_conditions", "must be an object keyed by annotation");
        for (auto r = ranges->begin(); r != ranges->end(); ++r) {
            const std::string rp = base + "/initial_conditions/" + r.key();
            if (!isGroup(r.key()) &&
                std::find(project.vocabulary.begin(), project.vocabulary.end(), r.key()) == project.vocabulary.end()) {
                return rd.error(rp, "unknown annotation '" + r.key() + "'");
            }
            FRAY_TRY(range, rangeFromJson(rd, r.value(), rp, defaultRange(r.key())));
            set.ranges.emplace_back(r.key(), range);
        }
    }
    return set;
}

void setProjectPatterns(prep::Project& project, const PatternSet& set) {
    json patterns = json::array();
    for (const auto& p : set.patterns) {
        json entries = json::array();
        for (const auto& e : p.entries) entries.push_back(json{{"character", e.character + 1}, {"annotation", e.annotation}});
        patterns.push_back(json{{"name", p.name},
                                {"entries", entries},
                                {"weights", {{"contact", p.weights.contact}, {"distance", p.weights.distance}, {"timing", p.weights.timing}}},
                                {"threshold", p.threshold},
                                {"keep_per_path", p.keepPerPath},
                                {"spread", p.spread}});
    }
    json ranges = json::object();
    for (const auto& [key, r] : set.ranges) ranges[key] = rangeToJson(r);
    project.laterSections[kPatternSection] = json{{"patterns", patterns}, {"initial_conditions", ranges}}.dump();
}

Status checkPattern(const PatternList& pattern, const PatternSet& set, const ActionLibrary& lib) {
    const std::string who = "pattern '" + pattern.name + "'";
    for (std::size_t i = 0; i < pattern.entries.size(); ++i) {
        const auto& e = pattern.entries[i];
        const bool any = std::any_of(lib.actions().begin(), lib.actions().end(),
                                     [&](const LibraryAction& a) { return matchesAnnotation(a, e.annotation); });
        if (!any) {
            return makeError(who + ", entry " + std::to_string(i + 1) + " (character " + std::to_string(e.character + 1) + ", " +
                             e.annotation + "): no action in the project has this annotation");
        }
        if (isReactiveAnnotation(e.annotation) && !(i == 0 && e.character == 0)) {
            // A response needs a cause: an earlier entry of the other character.
            // (Character 1's first entry may be one: it is already falling or
            // staggering when the patch starts, pushed in the patch before.)
            bool cause = false;
            for (std::size_t k = 0; k < i; ++k) cause = cause || pattern.entries[k].character != e.character;
            if (!cause) {
                return makeError(who + ", entry " + std::to_string(i + 1) + " (character " + std::to_string(e.character + 1) +
                                 ", " + e.annotation + "): a reaction needs an earlier action of the other character to cause it");
            }
        }
    }
    auto first = [&](int c) -> const PatternEntry* {
        for (const auto& e : pattern.entries) {
            if (e.character == c) return &e;
        }
        return nullptr;
    };
    const PatternEntry* f1 = first(0);
    const PatternEntry* f2 = first(1);
    if (!f1 || !f2) return makeError(who + ": needs entries for both characters");
    const InitialRange a = set.rangeFor(f1->annotation), b = set.rangeFor(f2->annotation);
    if (std::max(a.minDistance, b.minDistance) > std::min(a.maxDistance, b.maxDistance) + 1e-9) {
        return makeError(who + ": the distance ranges of the first actions (" + f1->annotation + ", " + f2->annotation +
                         ") do not intersect");
    }
    if (std::max(a.minDelay, b.minDelay) > std::min(a.maxDelay, b.maxDelay) + 1e-9) {
        return makeError(who + ": the delay ranges of the first actions (" + f1->annotation + ", " + f2->annotation +
                         ") do not intersect");
    }
    return {};
}

}  // namespace fray::sim
