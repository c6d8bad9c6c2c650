// The scene file: its reader and writer (sceneToJson, sceneFromJson, saveScene)
// and the spec's shared readers (parseCheckpoints, parseArena). The poser and
// the creatures' keys are in scene.cpp.
#include "fray/sim/scene.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>
#include <tbb/parallel_for.h>

#include "fray/core/atomic_file.h"
#include "fray/core/kinematics.h"
#include "fray/prep/json_reader.h"
#include "scene_bodies.h"

namespace fray::sim {

using detail::BodyKind;
using detail::bodyKind;
using detail::kBodyKinds;

namespace {

using json = nlohmann::ordered_json;
using prep::JsonReader;

json actionRef(const ActionLibrary& lib, int action) {
    const auto& a = lib.actions()[static_cast<std::size_t>(action)];
    return json{{"motion", a.motionId}, {"first", a.firstFrame}, {"last", a.lastFrame}, {"name", a.name}};
}

json checkpointsToJson(const std::vector<Checkpoint>& path) {
    json out = json::array();
    for (const auto& c : path) {
        json j{{"x", c.pos.x}, {"z", c.pos.y}};
        if (c.time) j["time"] = *c.time;
        if (!c.action.empty()) j["action"] = c.action;
        out.push_back(std::move(j));
    }
    return out;
}

class ActionIndex {
public:
    explicit ActionIndex(const ActionLibrary& lib) {
        for (int i = 0; i < lib.size(); ++i) {
            const auto& a = lib.actions()[static_cast<std::size_t>(i)];
            map_[{a.motionId, a.firstFrame, a.lastFrame}] = i;
        }
    }
    Result<int> resolve(const JsonReader& rd, const json& v, const std::string& path) const {
        if (!v.is_object()) return rd.error(path, "must be an object {motion, first, last}");
        FRAY_TRY(motion, rd.stringAt(v, path, "motion"));
        FRAY_TRY(first, rd.integerAt(v, path, "first"));
        FRAY_TRY(last, rd.integerAt(v, path, "last"));
        const auto it = map_.find({motion, first, last});
        if (it == map_.end()) {
            return rd.error(path, "action " + motion + " frames " + std::to_string(first) + "-" + std::to_string(last) +
                                      " is not in the project any more (were its cuts edited? simulate the scene again)");
        }
        return it->second;
    }

private:
    std::map<std::tuple<std::string, int, int>, int> map_;
};

Result<std::vector<Checkpoint>> checkpointsFromJson(const JsonReader& rd, const json& v, const std::string& path) {
    if (!v.is_array()) return rd.error(path, "must be an array of checkpoints");
    std::vector<Checkpoint> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const std::string p = path + "/" + std::to_string(i);
        if (!v[i].is_object()) return rd.error(p, "must be an object {x, z[, time][, action]}");
        Checkpoint c;
        FRAY_TRY(xf, rd.field(v[i], p, "x"));
        FRAY_TRY(x, rd.numberIn(*xf, p + "/x", -kMaxCoordinate, kMaxCoordinate));
        FRAY_TRY(zf, rd.field(v[i], p, "z"));
        FRAY_TRY(z, rd.numberIn(*zf, p + "/z", -kMaxCoordinate, kMaxCoordinate));
        c.pos = {static_cast<float>(x), static_cast<float>(z)};
        FRAY_TRY(tf, rd.field(v[i], p, "time", false));
        if (tf) {
            // Seconds from the start of the scene.
            FRAY_TRY(t, rd.numberIn(*tf, p + "/time", 0.0, kMaxSceneSeconds));
            c.time = t;
        }
        FRAY_TRY(af, rd.field(v[i], p, "action", false));
        if (af) {
            FRAY_TRY(a, rd.string(*af, p + "/action"));
            c.action = a;
        }
        out.push_back(std::move(c));
    }
    return out;
}

}  // namespace

// Exposed for the spec reader.
Result<std::vector<Checkpoint>> parseCheckpoints(const JsonReader& rd, const json& v, const std::string& path) {
    return checkpointsFromJson(rd, v, path);
}

// {x, z, radius} of a scene spec or a scene file: the centre defaults to the
// origin, the radius is at least 1 m.
Result<Arena> parseArena(const JsonReader& rd, const json& v, const std::string& path) {
    if (!v.is_object()) return rd.error(path, "must be {x, z, radius} (a disc on the floor, metres)");
    for (auto it = v.begin(); it != v.end(); ++it) {
        if (it.key() != "x" && it.key() != "z" && it.key() != "radius") return rd.error(path + "/" + it.key(), "unknown field");
    }
    Arena a;
    for (const char* key : {"x", "z"}) {
        if (auto f = v.find(key); f != v.end()) {
            FRAY_TRY(num, rd.number(*f, path + "/" + key));
            if (!std::isfinite(num)) return rd.error(path + "/" + key, "must be finite");
            (key[0] == 'x' ? a.centre.x : a.centre.y) = static_cast<float>(num);
        }
    }
    FRAY_TRY(radius, rd.numberAt(v, path, "radius"));
    if (!std::isfinite(radius) || radius < 1.0) return rd.error(path + "/radius", "must be at least 1 m");
    a.radius = radius;
    return a;
}

namespace {

// A painted floor in the scene file: one string per image row of run lengths,
// alternating unpainted and painted pixels and starting with unpainted ("3 4 1"
// is 3 unpainted, 4 painted, 1 unpainted).
json floorToJson(const FloorBitmap& f) {
    json rows = json::array();
    for (int y = 0; y < f.height; ++y) {
        std::string row;
        std::uint8_t value = 0;
        int run = 0;
        for (int x = 0; x < f.width; ++x) {
            const std::uint8_t v = f.painted[static_cast<std::size_t>(y) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(x)] != 0;
            if (v != value) {
                row += std::to_string(run) + " ";
                value = v, run = 0;
            }
            ++run;
        }
        rows.push_back(row + std::to_string(run));
    }
    return json{{"width", f.width}, {"height", f.height}, {"origin", {f.origin.x, f.origin.y}},
                {"metres_per_pixel", f.metresPerPixel}, {"rows", std::move(rows)}};
}

Result<FloorBitmap> floorFromJson(const JsonReader& rd, const json& v, const std::string& path) {
    if (!v.is_object()) return rd.error(path, "must be an object {width, height, origin, metres_per_pixel, rows}");
    FloorBitmap f;
    FRAY_TRY(w, rd.integerAt(v, path, "width"));
    FRAY_TRY(h, rd.integerAt(v, path, "height"));
    if (w < 1 || w > 8192) return rd.error(path + "/width", "must be between 1 and 8192 pixels");
    if (h < 1 || h > 8192) return rd.error(path + "/height", "must be between 1 and 8192 pixels");
    f.width = static_cast<int>(w), f.height = static_cast<int>(h);
    FRAY_TRY(of, rd.field(v, path, "origin"));
    if (!of->is_array() || of->size() != 2) return rd.error(path + "/origin", "must be [x, z]");
    FRAY_TRY(ox, rd.number((*of)[0], path + "/origin/0"));
    FRAY_TRY(oz, rd.number((*of)[1], path + "/origin/1"));
    if (!(std::fabs(ox) <= 1e4) || !(std::fabs(oz) <= 1e4)) return rd.error(path + "/origin", "is too far out");
    f.origin = {static_cast<float>(ox), static_cast<float>(oz)};
    FRAY_TRY(m, rd.numberAt(v, path, "metres_per_pixel"));
    if (!(m > 0.001) || m > 10) return rd.error(path + "/metres_per_pixel", "must be in (0.001, 10]");
    f.metresPerPixel = m;
    FRAY_TRY(rf, rd.field(v, path, "rows"));
    if (!rf->is_array() || rf->size() != static_cast<std::size_t>(f.height)) {
        return rd.error(path + "/rows", "must be an array of " + std::to_string(f.height) + " rows (the height)");
    }
    f.painted.reserve(static_cast<std::size_t>(f.width) * static_cast<std::size_t>(f.height));
    for (int y = 0; y < f.height; ++y) {
        const std::string rp = path + "/rows/" + std::to_string(y);
        FRAY_TRY(row, rd.string((*rf)[static_cast<std::size_t>(y)], rp));
        std::uint8_t value = 0;
        long filled = 0;
        const char* p = row.data();
        const char* e = p + row.size();
        while (p < e) {
            while (p < e && *p == ' ') ++p;
            if (p == e) break;
            long run = 0;
            const char* digits = p;
            while (p < e && *p >= '0' && *p <= '9' && run <= 8192) run = run * 10 + (*p++ - '0');
            if (p == digits || (p < e && *p != ' ')) return rd.error(rp, "must be run lengths: whole numbers separated by spaces");
            if (filled + run > f.width) return rd.error(rp, "runs add up to more than the width (" + std::to_string(f.width) + ")");
            f.painted.insert(f.painted.end(), static_cast<std::size_t>(run), value);
            filled += run;
            value ^= 1;
        }
        if (filled != f.width) return rd.error(rp, "runs add up to " + std::to_string(filled) + ", not the width (" + std::to_string(f.width) + ")");
    }
    return f;
}

}  // namespace

std::string sceneToJson(const Scene& scene, const ActionLibrary& lib) {
    json j;
    j["format"] = "fray-scene";
    // Version 1 unless an instance loops (version 2) or a body is held
    // (version 3): a scene without either keeps the bytes it had before they
    // existed.
    bool loops = false;
    for (const auto& c : scene.characters) {
        loops = loops || std::any_of(c.track.begin(), c.track.end(), [](const ActionInstance& i) { return i.looped(); });
    }
    const bool held = std::any_of(scene.characters.begin(), scene.characters.end(), [](const SceneCharacter& c) { return c.held(); });
    j["version"] = held ? kSceneVersion : loops ? kSceneVersionLoops : kSceneVersionNoLoops;
    j["project"] = scene.project;
    j["duration"] = scene.duration;
    j["seed"] = scene.seed;
    if (scene.arena.bounded())
        j["arena"] = json{{"x", scene.arena.centre.x}, {"z", scene.arena.centre.y}, {"radius", scene.arena.radius}};
    if (!scene.marks.empty()) {
        json marks = json::array();
        for (const auto& m : scene.marks) {
            json pts = json::array();
            for (const auto& p : m.points) pts.push_back(json::array({p.x, p.y}));
            marks.push_back(json{{"kind", m.kind}, {"points", std::move(pts)}});
        }
        j["marks"] = std::move(marks);
    }
    if (!scene.floor.empty()) j["floor"] = floorToJson(scene.floor);
    // The characters are written in parallel, each on its own: its document
    // built and dumped as the whole document's dump would print it at its
    // depth (two levels in: every line after the first indented two spaces
    // more; a string's line breaks are escaped, so every raw one is
    // structural), then spliced in where a placeholder stands. The same bytes
    // as one dump of everything, without the whole scene's document in memory.
    std::vector<std::string> charText(scene.characters.size());
    tbb::parallel_for(std::size_t{0}, scene.characters.size(), [&](std::size_t n) {
        const SceneCharacter& c = scene.characters[n];
        json cj;
        cj["name"] = c.name;
        if (!c.body.empty()) {
            cj["body"] = c.body;
            // A held body's keys over its hold are its holder's: the reader
            // makes them again (placeHeldBalls); only those outside are stored.
            json keys = json::array();
            for (const auto& k : c.keys) {
                if (c.held() && k.time >= c.heldFrom && k.time <= c.heldTo) continue;
                json key = json::array({k.time, k.at.pos.x, k.at.pos.y, k.at.heading});
                if (k.height >= 0 || k.pitch != 0.0f) key.push_back(k.height);
                if (k.pitch != 0.0f) key.push_back(k.pitch);
                keys.push_back(std::move(key));
            }
            if (!c.held() || !keys.empty()) cj["keys"] = std::move(keys);
            if (c.holder >= 0) {
                cj["holder"] = c.holder;
                cj["hand"] = c.hand == 0 ? "left" : "right";
            }
            if (c.held()) cj["held"] = json::array({c.heldFrom, c.heldTo});
        }
        cj["side"] = c.side;
        cj["group"] = c.group;
        cj["preset"] = c.preset;
        cj["depth"] = c.depth;
        cj["opponent"] = c.opponent;
        cj["fallbacks"] = c.fallbacks;
        cj["path"] = checkpointsToJson(c.path);
        cj["loop_path"] = c.loopPath;
        json track = json::array();
        for (const auto& inst : c.track) {
            json ij;
            ij["action"] = actionRef(lib, inst.action);
            ij["start"] = inst.start;
            ij["offset"] = inst.offset;
            ij["end"] = inst.end;
            if (inst.looped()) ij["loop"] = inst.loop;
            ij["root"] = {inst.root.pos.x, inst.root.pos.y, inst.root.heading};
            ij["forced"] = inst.forced;
            ij["fallback"] = inst.fallback;
            track.push_back(std::move(ij));
        }
        cj["track"] = std::move(track);
        const std::string text = prep::dumpJson(cj, 1);
        std::string& out = charText[n];
        out.reserve(text.size() + text.size() / 8 + 2);
        out += "  ";
        for (const char ch : text) {
            out += ch;
            if (ch == '\n') out += "  ";
        }
    });
    // A value no dump of a real scene has there (the dump escapes control characters).
    constexpr const char* kCharactersHere = "\x01fray-characters\x01";
    j["characters"] = scene.characters.empty() ? json::array() : json(kCharactersHere);
    json hits = json::array();
    for (const auto& h : scene.hits) {
        hits.push_back(json{{"time", h.time},
                            {"attacker", h.attacker},
                            {"defender", h.defender},
                            {"attack", actionRef(lib, h.attackAction)},
                            {"effector", segmentName(h.effector)},
                            {"target", segmentName(h.target)},
                            {"speed", h.speed},
                            {"impulse", h.impulse},
                            {"blocked", h.blocked}});
    }
    j["hits"] = std::move(hits);
    json catches = json::array();
    for (const auto& c : scene.catches) catches.push_back(json{{"time", c.time}, {"chaser", c.chaser}, {"runaway", c.runaway}});
    j["catches"] = std::move(catches);
    // Planning statistics; wall-clock time is left out so a scene is
    // byte-identical for the same inputs and seed.
    const auto& s = scene.stats;
    j["stats"] = json{{"decisions", s.decisions}, {"nodes", s.nodes},       {"leaves", s.leaves},
                      {"choices", s.choices},     {"pruned", s.pruned},     {"cutoffs", s.cutoffs},
                      {"fallbacks", s.fallbacks}, {"forced", s.forced},
                      {"shallower", s.shallower}};
    auto spec = prep::parseJson(scene.spec, "spec");
    j["spec"] = spec ? std::move(*spec) : json(scene.spec);
    std::string text = prep::dumpJson(j, 1);
    if (scene.characters.empty()) return text + "\n";
    // The placeholder as dumped (a control character is written \u0001),
    // replaced by the characters' array as the whole dump prints it.
    const std::string key = "\"characters\": ";
    const std::size_t at = text.find(key + prep::dumpJson(json(kCharactersHere))) + key.size();
    const std::size_t placeholder = prep::dumpJson(json(kCharactersHere)).size();
    std::size_t size = text.size() + 8;
    for (const auto& t : charText) size += t.size() + 2;
    std::string out;
    out.reserve(size);
    out.append(text, 0, at);
    out += "[\n";
    for (std::size_t n = 0; n < charText.size(); ++n) {
        out += charText[n];
        out += n + 1 < charText.size() ? ",\n" : "\n";
    }
    out += " ]";
    out.append(text, at + placeholder, std::string::npos);
    out += "\n";
    return out;
}

namespace {

// The parsed document and its project path, once the format is checked.
Result<std::string> projectOf(const JsonReader& rd, const json& j) {
    if (j.is_discarded()) return rd.error("", "not valid JSON");
    if (!j.is_object()) return rd.error("", "must be a JSON object");
    const auto fmt = j.find("format");
    if (fmt == j.end() || *fmt != "fray-scene") return rd.error("/format", "not a Fray scene file (expected \"fray-scene\")");
    return rd.stringAt(j, "", "project");
}

}  // namespace

Result<std::string> sceneProjectPath(std::string_view text, std::string_view fileName) {
    FRAY_TRY(j, prep::parseJson(text, fileName));
    return projectOf(JsonReader(fileName), j);
}

// One character's track: its actions in time order, each within its clip.
Result<std::vector<ActionInstance>> trackFromJson(const JsonReader& rd, const ActionIndex& index, const ActionLibrary& lib,
                                                  const json& track, const std::string& path, int version) {
    std::vector<ActionInstance> out;
    if (!track.is_array()) return rd.error(path, "must be an array");
    double previousStart = -1;
    for (std::size_t k = 0; k < track.size(); ++k) {
        const std::string ip = path + "/" + std::to_string(k);
        const json& ij = track[k];
        if (!ij.is_object()) return rd.error(ip, "must be an object");
        ActionInstance inst;
        FRAY_TRY(af, rd.field(ij, ip, "action"));
        FRAY_TRY(action, index.resolve(rd, *af, ip + "/action"));
        inst.action = action;
        FRAY_TRY(start, rd.numberAt(ij, ip, "start"));
        FRAY_TRY(offset, rd.numberAt(ij, ip, "offset"));
        FRAY_TRY(end, rd.numberAt(ij, ip, "end"));
        if (start < previousStart) return rd.error(ip + "/start", "actions must be in time order");
        if (end < start) return rd.error(ip + "/end", "ends before it starts");
        const double dur = lib.actions()[static_cast<std::size_t>(action)].duration;
        if (offset < 0 || offset > dur) return rd.error(ip + "/offset", "must lie within the action (0.." + std::to_string(dur) + " s)");
        previousStart = start;
        inst.start = start, inst.offset = offset, inst.end = end;
        if (const auto lf = ij.find("loop"); lf != ij.end()) {
            if (version < 2) return rd.error(ip + "/loop", "looped instances need scene version 2 (this file says version " + std::to_string(version) + ")");
            FRAY_TRY(loop, rd.number(*lf, ip + "/loop"));
            // At least a sample long (so a loop over an hour stays a few
            // hundred thousand repetitions at most) and within the clip from the offset.
            if (!(loop >= 1.0 / kSampleRate - 1e-9) || loop > dur - offset + 1e-9) {
                return rd.error(ip + "/loop", "must be between " + std::to_string(1.0 / kSampleRate) + " s and the rest of the clip after the offset (" +
                                                  std::to_string(dur - offset) + " s)");
            }
            if (!(end - start <= kMaxSceneSeconds)) return rd.error(ip + "/end", "a looped instance lasts at most 3600 s");
            inst.loop = loop;
        }
        FRAY_TRY(rf, rd.field(ij, ip, "root"));
        if (!rf->is_array() || rf->size() != 3) return rd.error(ip + "/root", "must be [x, z, heading]");
        FRAY_TRY(rx, rd.number((*rf)[0], ip + "/root/0"));
        FRAY_TRY(rz, rd.number((*rf)[1], ip + "/root/1"));
        FRAY_TRY(rh, rd.number((*rf)[2], ip + "/root/2"));
        inst.root = {{static_cast<float>(rx), static_cast<float>(rz)}, rh};
        FRAY_TRY(forced, rd.booleanAt(ij, ip, "forced"));
        FRAY_TRY(fallback, rd.booleanAt(ij, ip, "fallback"));
        inst.forced = forced, inst.fallback = fallback;
        out.push_back(inst);
    }
    return out;
}

Result<Scene> sceneFromJson(std::string_view text, std::string_view fileName, const ActionLibrary& lib) {
    const JsonReader rd(fileName);
    FRAY_TRY(j, prep::parseJson(text, fileName));
    FRAY_TRY(projectPath, projectOf(rd, j));
    FRAY_TRY(version, rd.integerAt(j, "", "version"));
    if (version < kSceneVersionNoLoops || version > kSceneVersion) {
        return rd.error("/version", "version " + std::to_string(version) + " is not supported (this build reads " +
                                        std::to_string(kSceneVersionNoLoops) + " to " + std::to_string(kSceneVersion) + ")");
    }
    const ActionIndex index(lib);
    Scene scene;
    scene.project = projectPath;
    std::int64_t heldKeys = 0;
    FRAY_TRY(duration, rd.numberAt(j, "", "duration"));
    if (!(duration > 0) || duration > kMaxSceneSeconds) {
        return rd.error("/duration", "must be a positive number of seconds, at most 3600");
    }
    scene.duration = duration;
    FRAY_TRY(sf, rd.field(j, "", "seed"));
    if (!sf->is_number_unsigned() && !sf->is_number_integer()) return rd.error("/seed", "must be an integer");
    scene.seed = sf->get<std::uint64_t>();
    if (const auto ar = j.find("arena"); ar != j.end()) {
        FRAY_TRY(arena, parseArena(rd, *ar, "/arena"));
        scene.arena = arena;
    }
    if (const auto mk = j.find("marks"); mk != j.end()) {
        if (!mk->is_array() || mk->size() > 10000) return rd.error("/marks", "must be an array of {kind, points}");
        for (std::size_t i = 0; i < mk->size(); ++i) {
            const std::string p = "/marks/" + std::to_string(i);
            const json& m = (*mk)[i];
            if (!m.is_object()) return rd.error(p, "must be an object {kind, points}");
            for (auto it = m.begin(); it != m.end(); ++it) {
                if (it.key() != "kind" && it.key() != "points") return rd.error(p + "/" + it.key(), "unknown field");
            }
            FloorMark mark;
            FRAY_TRY(kind, rd.stringAt(m, p, "kind"));
            if (kind.empty()) return rd.error(p + "/kind", "must not be empty");
            mark.kind = kind;
            FRAY_TRY(pf, rd.field(m, p, "points"));
            if (!pf->is_array() || pf->size() < 2 || pf->size() > 10000) {
                return rd.error(p + "/points", "must be an array of 2 to 10000 [x, z] points");
            }
            for (std::size_t k = 0; k < pf->size(); ++k) {
                const std::string pp = p + "/points/" + std::to_string(k);
                const json& q = (*pf)[k];
                if (!q.is_array() || q.size() != 2) return rd.error(pp, "must be [x, z]");
                FRAY_TRY(x, rd.number(q[0], pp + "/0"));
                FRAY_TRY(z, rd.number(q[1], pp + "/1"));
                if (!(std::fabs(x) <= 1e5) || !(std::fabs(z) <= 1e5)) return rd.error(pp, "is too far out");
                mark.points.emplace_back(static_cast<float>(x), static_cast<float>(z));
            }
            scene.marks.push_back(std::move(mark));
        }
    }
    if (const auto fl = j.find("floor"); fl != j.end()) {
        FRAY_TRY(floor, floorFromJson(rd, *fl, "/floor"));
        scene.floor = std::move(floor);
    }
    FRAY_TRY(cf, rd.field(j, "", "characters"));
    if (!cf->is_array()) return rd.error("/characters", "must be an array");
    const int n = static_cast<int>(cf->size());
    for (int i = 0; i < n; ++i) {
        const std::string p = "/characters/" + std::to_string(i);
        const json& c = (*cf)[static_cast<std::size_t>(i)];
        if (!c.is_object()) return rd.error(p, "must be an object");
        SceneCharacter sc;
        FRAY_TRY(name, rd.stringAt(c, p, "name"));
        sc.name = name;
        if (const auto bf = c.find("body"); bf != c.end()) {
            FRAY_TRY(body, rd.string(*bf, p + "/body"));
            if (!bodyKind(body)) {
                std::string known;
                for (const auto& k : kBodyKinds) known += (known.empty() ? "\"" : ", \"") + std::string(k.name) + "\"";
                return rd.error(p + "/body", "unknown body '" + body + "' (this build knows " + known + ")");
            }
            sc.body = body;
            if (const auto hf = c.find("holder"); hf != c.end()) {
                FRAY_TRY(holder, rd.integerAt(c, p, "holder"));
                if (holder < 0 || holder >= n) return rd.error(p + "/holder", "must be a character index");
                sc.holder = holder;
                FRAY_TRY(hand, rd.stringAt(c, p, "hand"));
                if (hand != "left" && hand != "right") return rd.error(p + "/hand", "must be \"left\" or \"right\"");
                sc.hand = hand == "left" ? 0 : 1;
            }
            // A held body (version 3): over [from, to] its holder's keys,
            // made below once every character is read.
            if (const auto hd = c.find("held"); hd != c.end()) {
                if (version < kSceneVersion) {
                    return rd.error(p + "/held", "held bodies need scene version " + std::to_string(kSceneVersion) + " (this file says version " +
                                                     std::to_string(version) + ")");
                }
                if (!hd->is_array() || hd->size() != 2) return rd.error(p + "/held", "must be [from, to] (seconds)");
                FRAY_TRY(from, rd.number((*hd)[0], p + "/held/0"));
                FRAY_TRY(to, rd.number((*hd)[1], p + "/held/1"));
                if (!(from >= 0 && from <= kMaxSceneSeconds)) return rd.error(p + "/held/0", "must be in [0, 3600] s");
                if (!(to >= from && to <= kMaxSceneSeconds)) return rd.error(p + "/held/1", "must be in [from, 3600] s");
                if (sc.holder < 0) return rd.error(p + "/holder", "a held body needs its holder");
                heldKeys += heldKeyCount(from, to);
                if (heldKeys > kMaxHeldKeys) {
                    return rd.error(p + "/held", "the held bodies would make more than " + std::to_string(kMaxHeldKeys) + " keys");
                }
                sc.heldFrom = from, sc.heldTo = to;
            }
            static const json noKeys = json::array();
            const json* kf = &noKeys;  // a held body may store none
            if (!sc.held() || c.contains("keys")) {
                FRAY_TRY(stored, rd.field(c, p, "keys"));
                kf = stored;
            }
            if (!kf->is_array() || (kf->empty() && !sc.held()) || kf->size() > 1'000'000) {
                return rd.error(p + "/keys", "must be an array of [time, x, z, heading(, height(, pitch))] keys, at least one");
            }
            for (std::size_t k = 0; k < kf->size(); ++k) {
                const std::string kp = p + "/keys/" + std::to_string(k);
                const json& q = (*kf)[k];
                if (!q.is_array() || q.size() < 4 || q.size() > 6) {
                    return rd.error(kp, "must be [time, x, z, heading], [time, x, z, heading, height] or [time, x, z, heading, height, pitch]");
                }
                double v[6] = {0, 0, 0, 0, -1, 0};
                for (std::size_t e = 0; e < q.size(); ++e) {
                    FRAY_TRY(num, rd.number(q[e], kp + "/" + std::to_string(e)));
                    if (!(std::fabs(num) <= 1e6)) return rd.error(kp + "/" + std::to_string(e), "is not a finite value in range");
                    v[e] = num;
                }
                if (!sc.keys.empty() && v[0] < sc.keys.back().time) return rd.error(kp + "/0", "keys must be in time order");
                if (q.size() == 5 && !(v[4] >= 0 && v[4] <= 100)) return rd.error(kp + "/4", "height must be in [0, 100] m");
                if (q.size() == 6 && !(v[4] >= -1 && v[4] <= 100)) return rd.error(kp + "/4", "height must be in [0, 100] m (or -1: the body's own)");
                if (!(std::fabs(v[5]) <= std::numbers::pi / 2)) return rd.error(kp + "/5", "pitch must be in [-pi/2, pi/2] rad");
                if (sc.held() && v[0] >= sc.heldFrom && v[0] <= sc.heldTo) {
                    return rd.error(kp + "/0", "a key inside the hold (" + std::to_string(sc.heldFrom) + " to " + std::to_string(sc.heldTo) +
                                                   " s): the holder places the ball there");
                }
                sc.keys.push_back({v[0], {{static_cast<float>(v[1]), static_cast<float>(v[2])}, wrapAngle(v[3])}, static_cast<float>(v[4]),
                                   static_cast<float>(v[5])});
            }
        }
        FRAY_TRY(side, rd.integerAt(c, p, "side"));
        sc.side = side;
        FRAY_TRY(group, rd.integerAt(c, p, "group"));
        sc.group = group;
        FRAY_TRY(preset, rd.stringAt(c, p, "preset"));
        sc.preset = preset;
        FRAY_TRY(depth, rd.integerAt(c, p, "depth"));
        sc.depth = depth;
        FRAY_TRY(opponent, rd.integerAt(c, p, "opponent"));
        if (opponent < -1 || opponent >= n) return rd.error(p + "/opponent", "must be -1 or a character index");
        sc.opponent = opponent;
        FRAY_TRY(fallbacks, rd.integerAt(c, p, "fallbacks"));
        sc.fallbacks = fallbacks;
        FRAY_TRY(pathf, rd.field(c, p, "path"));
        FRAY_TRY(path, checkpointsFromJson(rd, *pathf, p + "/path"));
        sc.path = std::move(path);
        FRAY_TRY(loop, rd.booleanAt(c, p, "loop_path"));
        sc.loopPath = loop;
        FRAY_TRY(tf, rd.field(c, p, "track"));
        FRAY_TRY(track, trackFromJson(rd, index, lib, *tf, p + "/track", static_cast<int>(version)));
        sc.track = std::move(track);
        scene.characters.push_back(std::move(sc));
    }
    // Held bodies: each held by a person with a track and that hand and
    // elbow, its keys over the hold made from the holder's pose.
    for (int i = 0; i < n; ++i) {
        const auto& b = scene.characters[static_cast<std::size_t>(i)];
        if (!b.held()) continue;
        const std::string p = "/characters/" + std::to_string(i);
        if (b.holder == i || scene.isCreature(b.holder) || scene.characters[static_cast<std::size_t>(b.holder)].track.empty()) {
            return rd.error(p + "/holder", "character " + std::to_string(b.holder) + " cannot hold it (a held body's holder is a person with actions)");
        }
        const auto& track = scene.characters[static_cast<std::size_t>(b.holder)].track;
        const int motion = lib.actions()[static_cast<std::size_t>(track.front().action)].motion;
        if (motion < 0 || motion >= lib.motionCount()) {
            return rd.error(p + "/holder", "character " + std::to_string(b.holder) + " has no captured motion to hold it with");
        }
        const auto& joints = lib.motion(motion).joints;
        if ((b.hand == 0 ? joints.leftHand : joints.rightHand) < 0 || (b.hand == 0 ? joints.leftElbow : joints.rightElbow) < 0) {
            return rd.error(p + "/hand", "character " + std::to_string(b.holder) + "'s skeleton has no " + (b.hand == 0 ? "left" : "right") +
                                             " hand and elbow to hold it");
        }
    }
    placeHeldBalls(scene, lib);
    auto character = [&](const json& v, const std::string& path) -> Result<int> {
        FRAY_TRY(k, rd.integer(v, path));
        if (k < 0 || k >= n) return rd.error(path, "is not a character index");
        return k;
    };
    auto segment = [&](const json& v, const std::string& path) -> Result<int> {
        FRAY_TRY(name, rd.string(v, path));
        for (int s = 0; s < kSegmentCount; ++s) {
            if (name == segmentName(s)) return s;
        }
        return rd.error(path, "unknown body segment '" + name + "'");
    };
    FRAY_TRY(hf, rd.field(j, "", "hits"));
    if (!hf->is_array()) return rd.error("/hits", "must be an array");
    for (std::size_t k = 0; k < hf->size(); ++k) {
        const std::string p = "/hits/" + std::to_string(k);
        const json& h = (*hf)[k];
        if (!h.is_object()) return rd.error(p, "must be an object");
        HitEvent e;
        FRAY_TRY(time, rd.numberAt(h, p, "time"));
        FRAY_TRY(a, rd.field(h, p, "attacker"));
        FRAY_TRY(attacker, character(*a, p + "/attacker"));
        FRAY_TRY(d, rd.field(h, p, "defender"));
        FRAY_TRY(defender, character(*d, p + "/defender"));
        FRAY_TRY(af, rd.field(h, p, "attack"));
        FRAY_TRY(attack, index.resolve(rd, *af, p + "/attack"));
        FRAY_TRY(ef, rd.field(h, p, "effector"));
        FRAY_TRY(effector, segment(*ef, p + "/effector"));
        FRAY_TRY(tf, rd.field(h, p, "target"));
        FRAY_TRY(target, segment(*tf, p + "/target"));
        FRAY_TRY(speed, rd.numberAt(h, p, "speed"));
        FRAY_TRY(impulse, rd.numberAt(h, p, "impulse"));
        FRAY_TRY(blocked, rd.booleanAt(h, p, "blocked"));
        e.time = time, e.attacker = attacker, e.defender = defender, e.attackAction = attack;
        e.effector = effector, e.target = target, e.speed = speed, e.impulse = impulse, e.blocked = blocked;
        scene.hits.push_back(e);
    }
    FRAY_TRY(catf, rd.field(j, "", "catches"));
    if (!catf->is_array()) return rd.error("/catches", "must be an array");
    for (std::size_t k = 0; k < catf->size(); ++k) {
        const std::string p = "/catches/" + std::to_string(k);
        const json& c = (*catf)[k];
        if (!c.is_object()) return rd.error(p, "must be an object");
        FRAY_TRY(time, rd.numberAt(c, p, "time"));
        FRAY_TRY(a, rd.field(c, p, "chaser"));
        FRAY_TRY(chaser, character(*a, p + "/chaser"));
        FRAY_TRY(r, rd.field(c, p, "runaway"));
        FRAY_TRY(runaway, character(*r, p + "/runaway"));
        scene.catches.push_back({time, chaser, runaway});
    }
    if (const auto st = j.find("stats"); st != j.end() && st->is_object()) {
        auto get = [&](const char* key) -> std::int64_t {
            const auto it = st->find(key);
            return it != st->end() && it->is_number_integer() ? it->get<std::int64_t>() : 0;
        };
        scene.stats.decisions = get("decisions");
        scene.stats.nodes = get("nodes");
        scene.stats.leaves = get("leaves");
        scene.stats.choices = get("choices");
        scene.stats.pruned = get("pruned");
        scene.stats.cutoffs = get("cutoffs");
        scene.stats.fallbacks = get("fallbacks");
        scene.stats.forced = get("forced");
        scene.stats.shallower = get("shallower");
    }
    if (const auto sp = j.find("spec"); sp != j.end()) scene.spec = sp->is_string() ? sp->get<std::string>() : prep::dumpJson(*sp);
    return scene;
}

Status saveScene(const Scene& scene, const ActionLibrary& lib, const std::filesystem::path& file) {
    return writeFileAtomically(file, sceneToJson(scene, lib));
}

}  // namespace fray::sim
