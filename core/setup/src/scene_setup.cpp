#include "fray/setup/scene_setup.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <nlohmann/json.hpp>
#include <zlib.h>

#include "fray/prep/json_reader.h"

namespace fray::setup {
namespace {

using json = nlohmann::ordered_json;
using prep::JsonReader;

constexpr int kSectionVersion = 2;  // written only when a graph kind is present (else 1)

struct KindName {
    SetupKind kind;
    const char* name;
};
constexpr KindName kKindNames[] = {{SetupKind::Duel, "duel"},         {SetupKind::Chase, "chase"},
                                   {SetupKind::OneVsMany, "one-vs-many"}, {SetupKind::OneVsOne, "one-vs-one"},
                                   {SetupKind::Domino, "domino"},     {SetupKind::Luggage, "luggage"},
                                   {SetupKind::Football, "football"}, {SetupKind::Rat, "rat"},
                                   {SetupKind::GraphDuel, "graph-duel"}, {SetupKind::GraphTeams, "graph-teams"},
                                   {SetupKind::GraphCarry, "graph-carry"}};

// The setup's parameters as a JSON object (a setup always holds one: the
// reader and checkSetup see to it).
json specObject(const SceneSetup& s) {
    json j = json::parse(s.spec, nullptr, false);
    return j.is_object() ? j : json::object();
}
void storeSpec(SceneSetup& s, const json& j) { s.spec = prep::dumpJson(j); }

// Writes a number into a slot unless it already holds that value (so numbers
// keep the spelling they were written in: 30 stays 30, 1.0 stays 1.0).
void putNumber(json& slot, double v) {
    if (slot.is_number() && slot.get<double>() == v) return;
    if (std::floor(v) == v && std::fabs(v) < 1e15) slot = static_cast<std::int64_t>(v);
    else slot = v;
}

bool finite(double x) { return std::isfinite(x); }

// The optional floor point "at": [x, z] of a direction or a command.
std::optional<Point> readAt(const json& q) {
    const auto a = q.find("at");
    if (a == q.end() || !a->is_array() || a->size() != 2 || !(*a)[0].is_number() || !(*a)[1].is_number()) return std::nullopt;
    return Point{(*a)[0].get<double>(), (*a)[1].get<double>()};
}
bool atOk(const std::optional<Point>& at) {
    return !at || (finite(at->x) && finite(at->z) && std::fabs(at->x) <= 1e5 && std::fabs(at->z) <= 1e5);
}
void putAt(json& q, const std::optional<Point>& at) {
    if (!at) {
        q.erase("at");
        return;
    }
    json& a = q["at"];
    if (!a.is_array() || a.size() != 2) a = json::array({0, 0});
    putNumber(a[0], at->x);
    putNumber(a[1], at->z);
}

// ---- base64 ----
constexpr char kB64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string base64(const std::vector<unsigned char>& in) {
    std::string out;
    out.reserve((in.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < in.size(); i += 3) {
        const unsigned v = (unsigned(in[i]) << 16) | (i + 1 < in.size() ? unsigned(in[i + 1]) << 8 : 0u) |
                           (i + 2 < in.size() ? unsigned(in[i + 2]) : 0u);
        out += kB64[(v >> 18) & 63];
        out += kB64[(v >> 12) & 63];
        out += i + 1 < in.size() ? kB64[(v >> 6) & 63] : '=';
        out += i + 2 < in.size() ? kB64[v & 63] : '=';
    }
    return out;
}

std::optional<std::vector<unsigned char>> unbase64(std::string_view in) {
    if (in.size() % 4 != 0) return std::nullopt;
    std::vector<unsigned char> out;
    out.reserve(in.size() / 4 * 3);
    auto val = [](char c) -> int {
        const char* p = std::find(kB64, kB64 + 64, c);
        return p == kB64 + 64 ? -1 : static_cast<int>(p - kB64);
    };
    for (std::size_t i = 0; i < in.size(); i += 4) {
        int v[4];
        int pad = 0;
        for (int k = 0; k < 4; ++k) {
            const char c = in[i + static_cast<std::size_t>(k)];
            if (c == '=' && i + 4 == in.size() && k >= 2) {
                v[k] = 0;
                ++pad;
            } else {
                if (pad > 0) return std::nullopt;
                v[k] = val(c);
                if (v[k] < 0) return std::nullopt;
            }
        }
        const unsigned x = (unsigned(v[0]) << 18) | (unsigned(v[1]) << 12) | (unsigned(v[2]) << 6) | unsigned(v[3]);
        out.push_back(static_cast<unsigned char>(x >> 16));
        if (pad < 2) out.push_back(static_cast<unsigned char>((x >> 8) & 255));
        if (pad < 1) out.push_back(static_cast<unsigned char>(x & 255));
    }
    return out;
}

json pointJson(const Point& p) { return json::array({p.x, p.z}); }

Result<Point> pointFrom(const JsonReader& rd, const json& v, const std::string& path) {
    if (!v.is_array() || v.size() != 2) return rd.error(path, "must be [x, z]");
    FRAY_TRY(x, rd.numberIn(v[0], path + "/0", -1e5, 1e5));
    FRAY_TRY(z, rd.numberIn(v[1], path + "/1", -1e5, 1e5));
    return Point{x, z};
}

json setupToJson(const SceneSetup& s) {
    json j;
    j["name"] = s.name;
    j["kind"] = setupKindName(s.kind);
    j["spec"] = specObject(s);
    json trajectories = json::array();
    for (const auto& t : s.trajectories) {
        json jt;
        jt["character"] = t.character;
        jt["shape"] = trajectoryShapeName(t.shape);
        json pts = json::array();
        for (const auto& p : t.points) pts.push_back(pointJson(p));
        jt["points"] = pts;
        if (t.shape == TrajectoryShape::Circle) jt["clockwise"] = t.clockwise;
        jt["loop"] = t.loop;
        json cps = json::array();
        for (const auto& c : t.checkpoints) {
            json jc{{"x", c.pos.x}, {"z", c.pos.z}};
            if (c.time) jc["time"] = *c.time;
            if (!c.action.empty()) jc["action"] = c.action;
            cps.push_back(jc);
        }
        jt["checkpoints"] = cps;
        trajectories.push_back(jt);
    }
    j["trajectories"] = trajectories;
    if (s.floor) {
        const FloorPaint& f = *s.floor;
        j["floor"] = json{{"width", f.width},
                          {"height", f.height},
                          {"metres_per_pixel", f.metresPerPixel},
                          {"origin", pointJson(f.origin)},
                          {"encoding", "zlib-base64"},
                          {"data", encodeFloor(f)}};
    }
    json pins = json::array();
    for (const auto& p : s.pins) pins.push_back(json{{"character", p.character}, {"time", p.time}, {"action", p.action}});
    j["pins"] = pins;
    j["patches"] = json{{"kept", s.patches.kept}, {"rejected", s.patches.rejected}};
    return j;
}

Result<std::vector<int>> idList(const JsonReader& rd, const json& v, const std::string& path) {
    if (!v.is_array()) return rd.error(path, "must be an array of patch indices");
    std::vector<int> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
        FRAY_TRY(id, rd.integer(v[i], path + "/" + std::to_string(i)));
        if (id < 0) return rd.error(path + "/" + std::to_string(i), "must not be negative");
        if (!out.empty() && id <= out.back()) return rd.error(path + "/" + std::to_string(i), "indices must be ascending, without repeats");
        out.push_back(id);
    }
    return out;
}

Result<SceneSetup> setupFromJson(const JsonReader& rd, const json& v, const std::string& path) {
    if (!v.is_object()) return rd.error(path, "must be an object");
    SceneSetup s;
    FRAY_TRY(name, rd.stringAt(v, path, "name"));
    if (auto st = checkSetupName(name); !st) return rd.error(path + "/name", st.error().message);
    s.name = name;
    FRAY_TRY(kindS, rd.stringAt(v, path, "kind"));
    const auto kind = setupKindFromName(kindS);
    if (!kind) {
        std::string names;
        for (const auto& k : kKindNames) names += std::string(names.empty() ? "" : ", ") + k.name;
        return rd.error(path + "/kind", "unknown setup kind '" + kindS + "' (expected " + names + ")");
    }
    s.kind = *kind;
    FRAY_TRY(spec, rd.field(v, path, "spec"));
    if (!spec->is_object()) return rd.error(path + "/spec", "must be an object (the parameters, in the --spec format)");
    s.spec = prep::dumpJson(*spec);
    if (auto it = v.find("trajectories"); it != v.end()) {
        if (!it->is_array()) return rd.error(path + "/trajectories", "must be an array");
        for (std::size_t i = 0; i < it->size(); ++i) {
            const std::string tp = path + "/trajectories/" + std::to_string(i);
            const json& jt = (*it)[i];
            if (!jt.is_object()) return rd.error(tp, "must be an object");
            Trajectory t;
            FRAY_TRY(ch, rd.stringAt(jt, tp, "character"));
            if (ch.empty()) return rd.error(tp + "/character", "must name a character");
            t.character = ch;
            FRAY_TRY(shape, rd.stringAt(jt, tp, "shape"));
            if (shape == "polyline") t.shape = TrajectoryShape::Polyline;
            else if (shape == "arc") t.shape = TrajectoryShape::Arc;
            else if (shape == "circle") t.shape = TrajectoryShape::Circle;
            else return rd.error(tp + "/shape", "unknown shape '" + shape + "' (polyline, arc or circle)");
            FRAY_TRY(pts, rd.field(jt, tp, "points"));
            if (!pts->is_array()) return rd.error(tp + "/points", "must be an array of [x, z]");
            for (std::size_t k = 0; k < pts->size(); ++k) {
                FRAY_TRY(p, pointFrom(rd, (*pts)[k], tp + "/points/" + std::to_string(k)));
                t.points.push_back(p);
            }
            if (auto c = jt.find("clockwise"); c != jt.end()) {
                FRAY_TRY(b, rd.boolean(*c, tp + "/clockwise"));
                t.clockwise = b;
            }
            if (auto c = jt.find("loop"); c != jt.end()) {
                FRAY_TRY(b, rd.boolean(*c, tp + "/loop"));
                t.loop = b;
            }
            if (auto c = jt.find("checkpoints"); c != jt.end()) {
                if (!c->is_array()) return rd.error(tp + "/checkpoints", "must be an array");
                for (std::size_t k = 0; k < c->size(); ++k) {
                    const std::string cp = tp + "/checkpoints/" + std::to_string(k);
                    const json& jc = (*c)[k];
                    if (!jc.is_object()) return rd.error(cp, "must be an object {x, z[, time][, action]}");
                    SetupCheckpoint ck;
                    FRAY_TRY(xf, rd.field(jc, cp, "x"));
                    FRAY_TRY(x, rd.numberIn(*xf, cp + "/x", -1e5, 1e5));
                    FRAY_TRY(zf, rd.field(jc, cp, "z"));
                    FRAY_TRY(z, rd.numberIn(*zf, cp + "/z", -1e5, 1e5));
                    ck.pos = {x, z};
                    if (auto tf = jc.find("time"); tf != jc.end() && !tf->is_null()) {
                        FRAY_TRY(tm, rd.numberIn(*tf, cp + "/time", 0, 3600));
                        ck.time = tm;
                    }
                    if (auto af = jc.find("action"); af != jc.end() && !af->is_null()) {
                        FRAY_TRY(a, rd.string(*af, cp + "/action"));
                        ck.action = a;
                    }
                    t.checkpoints.push_back(ck);
                }
            }
            s.trajectories.push_back(std::move(t));
        }
    }
    if (auto it = v.find("floor"); it != v.end() && !it->is_null()) {
        const std::string fp = path + "/floor";
        if (!it->is_object()) return rd.error(fp, "must be an object {width, height, metres_per_pixel, origin, encoding, data}");
        FRAY_TRY(w, rd.integerAt(*it, fp, "width"));
        FRAY_TRY(h, rd.integerAt(*it, fp, "height"));
        if (w < 1 || w > kMaxFloorPixels) return rd.error(fp + "/width", "must be 1 to " + std::to_string(kMaxFloorPixels));
        if (h < 1 || h > kMaxFloorPixels) return rd.error(fp + "/height", "must be 1 to " + std::to_string(kMaxFloorPixels));
        FRAY_TRY(mf, rd.field(*it, fp, "metres_per_pixel"));
        FRAY_TRY(mpp, rd.number(*mf, fp + "/metres_per_pixel"));
        if (!(mpp > 0.001) || mpp > 10) return rd.error(fp + "/metres_per_pixel", "must be in (0.001, 10]");
        FRAY_TRY(of, rd.field(*it, fp, "origin"));
        FRAY_TRY(origin, pointFrom(rd, *of, fp + "/origin"));
        FRAY_TRY(enc, rd.stringAt(*it, fp, "encoding"));
        if (enc != "zlib-base64") return rd.error(fp + "/encoding", "must be \"zlib-base64\"");
        FRAY_TRY(data, rd.stringAt(*it, fp, "data"));
        auto paint = decodeFloor(data, w, h, rd.error(fp + "/data", "").message);
        if (!paint) return paint.error();
        paint->metresPerPixel = mpp;
        paint->origin = origin;
        s.floor = std::move(*paint);
    }
    if (auto it = v.find("pins"); it != v.end()) {
        if (!it->is_array()) return rd.error(path + "/pins", "must be an array");
        for (std::size_t i = 0; i < it->size(); ++i) {
            const std::string pp = path + "/pins/" + std::to_string(i);
            const json& jp = (*it)[i];
            if (!jp.is_object()) return rd.error(pp, "must be an object {character, time, action}");
            Pin p;
            FRAY_TRY(ch, rd.stringAt(jp, pp, "character"));
            FRAY_TRY(tf, rd.field(jp, pp, "time"));
            FRAY_TRY(tm, rd.numberIn(*tf, pp + "/time", 0, 3600));
            FRAY_TRY(a, rd.stringAt(jp, pp, "action"));
            if (ch.empty()) return rd.error(pp + "/character", "must name a character");
            if (a.empty()) return rd.error(pp + "/action", "must name an action");
            p.character = ch, p.time = tm, p.action = a;
            s.pins.push_back(p);
        }
    }
    if (auto it = v.find("patches"); it != v.end()) {
        if (!it->is_object()) return rd.error(path + "/patches", "must be an object {kept, rejected}");
        if (auto k = it->find("kept"); k != it->end()) {
            FRAY_TRY(ids, idList(rd, *k, path + "/patches/kept"));
            s.patches.kept = ids;
        }
        if (auto k = it->find("rejected"); k != it->end()) {
            FRAY_TRY(ids, idList(rd, *k, path + "/patches/rejected"));
            s.patches.rejected = ids;
        }
        for (int id : s.patches.rejected) {
            if (std::binary_search(s.patches.kept.begin(), s.patches.kept.end(), id)) {
                return rd.error(path + "/patches", "patch " + std::to_string(id) + " is both kept and rejected");
            }
        }
    }
    return s;
}

Status updateSpec(SceneSetup& s, const std::function<Status(json&)>& change) {
    json j = specObject(s);
    if (auto st = change(j); !st) return st;
    storeSpec(s, j);
    return {};
}

Error setupError(const SceneSetup& s, const std::string& what) { return makeError("setup '" + s.name + "': " + what); }

}  // namespace

const char* setupKindName(SetupKind kind) {
    for (const auto& k : kKindNames) {
        if (k.kind == kind) return k.name;
    }
    return "duel";
}

std::optional<SetupKind> setupKindFromName(std::string_view name) {
    for (const auto& k : kKindNames) {
        if (name == k.name) return k.kind;
    }
    return std::nullopt;
}

const std::vector<SetupKind>& allSetupKinds() {
    static const std::vector<SetupKind> kinds = [] {
        std::vector<SetupKind> out;
        for (const auto& k : kKindNames) out.push_back(k.kind);
        return out;
    }();
    return kinds;
}

const char* trajectoryShapeName(TrajectoryShape shape) {
    switch (shape) {
    case TrajectoryShape::Arc: return "arc";
    case TrajectoryShape::Circle: return "circle";
    case TrajectoryShape::Polyline: break;
    }
    return "polyline";
}

Status checkSetupName(std::string_view name) {
    if (name.empty()) return makeError("a setup name must not be empty");
    if (name.size() > 64) return makeError("a setup name must be at most 64 bytes");
    if (!prep::isValidUtf8(name)) return makeError("a setup name must be UTF-8 text");
    for (unsigned char c : name) {
        if (c < 0x20 || c == 0x7f) return makeError("a setup name must not hold control characters");
    }
    return {};
}

Result<std::vector<SceneSetup>> projectSetups(const prep::Project& project, std::string_view fileName) {
    std::vector<SceneSetup> out;
    const auto it = project.laterSections.find(kSetupSection);
    if (it == project.laterSections.end()) return out;
    const JsonReader rd(fileName);
    const std::string base = std::string("/") + kSetupSection;
    auto parsed = prep::parseJson(it->second, fileName);
    if (!parsed) return parsed.error();
    const json& j = *parsed;
    if (!j.is_object()) return rd.error(base, "must be an object {version, setups}");
    if (auto v = j.find("version"); v != j.end()) {
        FRAY_TRY(version, rd.integer(*v, base + "/version"));
        if (version < 1 || version > kSectionVersion) {
            return rd.error(base + "/version", "version " + std::to_string(version) + " is not supported (this build reads 1 and 2)");
        }
    }
    if (auto s = j.find("setups"); s != j.end()) {
        if (!s->is_array()) return rd.error(base + "/setups", "must be an array");
        for (std::size_t i = 0; i < s->size(); ++i) {
            const std::string path = base + "/setups/" + std::to_string(i);
            FRAY_TRY(setup, setupFromJson(rd, (*s)[i], path));
            if (findSetup(out, setup.name)) return rd.error(path + "/name", "'" + setup.name + "' is used by another setup");
            out.push_back(std::move(setup));
        }
    }
    return out;
}

std::string setupsToJson(const std::vector<SceneSetup>& setups) {
    json j;
    // Version 2 only with a graph kind, so projects without one keep their bytes.
    const bool graph = std::any_of(setups.begin(), setups.end(), [](const SceneSetup& s) {
        return s.kind == SetupKind::GraphDuel || s.kind == SetupKind::GraphTeams || s.kind == SetupKind::GraphCarry;
    });
    j["version"] = graph ? kSectionVersion : 1;
    json arr = json::array();
    for (const auto& s : setups) arr.push_back(setupToJson(s));
    j["setups"] = arr;
    return prep::dumpJson(j);
}

void setProjectSetups(prep::Project& project, const std::vector<SceneSetup>& setups) {
    if (setups.empty()) {
        project.laterSections.erase(kSetupSection);
        return;
    }
    project.laterSections[kSetupSection] = setupsToJson(setups);
}

Status checkSetup(const SceneSetup& setup, std::string_view fileName, const std::string& path) {
    const JsonReader rd(fileName);
    if (!prep::parseJson(setup.spec, fileName)) return rd.error(path + "/spec", "is not valid JSON");
    if (!json::parse(setup.spec, nullptr, false).is_object()) return rd.error(path + "/spec", "must be an object");
    if (setup.floor) {
        const FloorPaint& f = *setup.floor;
        if (f.width < 1 || f.height < 1 || f.width > kMaxFloorPixels || f.height > kMaxFloorPixels) {
            return rd.error(path + "/floor", "must be 1 to " + std::to_string(kMaxFloorPixels) + " pixels a side");
        }
        if (static_cast<std::size_t>(f.width) * static_cast<std::size_t>(f.height) != f.painted.size()) {
            return rd.error(path + "/floor", "holds " + std::to_string(f.painted.size()) + " pixels, not width x height");
        }
        if (std::any_of(f.painted.begin(), f.painted.end(), [](std::uint8_t b) { return b > 1; })) {
            return rd.error(path + "/floor", "a pixel is neither 0 nor 1");
        }
        if (!(f.metresPerPixel > 0.001) || f.metresPerPixel > 10) return rd.error(path + "/floor/metres_per_pixel", "must be in (0.001, 10]");
        if (!std::isfinite(f.origin.x) || !std::isfinite(f.origin.z) || std::fabs(f.origin.x) > 1e5 || std::fabs(f.origin.z) > 1e5) {
            return rd.error(path + "/floor/origin", "must be finite and within 100 km");
        }
    }
    // The stored form read back must be this setup: what the reader refuses is
    // refused here (the floor, checked above, is left out of the round trip).
    SceneSetup bare = setup;
    bare.floor.reset();
    auto j = prep::parseJson(setupsToJson({bare}), fileName);
    if (!j) return j.error();
    auto back = setupFromJson(rd, (*j)["setups"][0], path);
    if (!back) return back.error();
    for (const auto& t : setup.trajectories) {
        if (auto line = sampleTrajectory(t); !line) return rd.error(path + "/trajectories", line.error().message);
    }
    return {};
}

const SceneSetup* findSetup(const std::vector<SceneSetup>& setups, std::string_view name) {
    for (const auto& s : setups) {
        if (s.name == name) return &s;
    }
    return nullptr;
}
SceneSetup* findSetup(std::vector<SceneSetup>& setups, std::string_view name) {
    for (auto& s : setups) {
        if (s.name == name) return &s;
    }
    return nullptr;
}

SceneSetup makeSetup(std::string name, SetupKind kind) {
    SceneSetup s;
    s.name = std::move(name);
    s.kind = kind;
    json j;
    auto boxer = [](const char* n, int side, int depth, double x, double heading) {
        return json{{"name", n}, {"side", side}, {"preset", "general-boxer"}, {"depth", depth},
                    {"start", {{"x", x}, {"z", 0}, {"heading_deg", heading}}}};
    };
    switch (kind) {
    case SetupKind::Duel:
        j = json{{"version", 1}, {"duration", 20}, {"seed", 1}};
        j["characters"] = json::array({boxer("red", 0, 3, 0, 90), boxer("blue", 1, 2, 1.1, -90)});
        break;
    case SetupKind::Chase: {
        j = json{{"version", 1}, {"duration", 30}, {"seed", 1}, {"stop_on_catch", true}};
        j["arena"] = json{{"x", 1}, {"z", 0}, {"radius", 6}};
        auto runner = [](const char* n, int side, const char* preset, double x, double z) {
            return json{{"name", n}, {"side", side}, {"preset", preset}, {"depth", 2},
                        {"start", {{"x", x}, {"z", z}, {"heading_deg", 90}}}};
        };
        j["characters"] = json::array({runner("runaway", 1, "runaway", 2, 0), runner("chaser1", 0, "chaser", 0, -0.6),
                                       runner("chaser2", 0, "chaser", 0, 0.6)});
        break;
    }
    case SetupKind::OneVsMany:
        j = json{{"kind", "one-vs-many"}, {"duration", 120}, {"seed", 1}, {"enemies", 8}, {"entry_radius", 8}};
        j["commands"] = json::array({json{{"time", 0}, {"action", "punch"}}});
        break;
    case SetupKind::OneVsOne: j = json{{"kind", "one-vs-one"}, {"duration", 40}, {"seed", 1}}; break;
    case SetupKind::Domino: {
        // A duration, so the people left standing stand that long however the chain ends.
        j = json{{"kind", "domino"}, {"seed", 1}, {"duration", 20}};
        j["floor"] = json{{"bitmap", "(painted)"}, {"metres_per_pixel", 0.1}, {"origin", {-10, -6}}};
        j["starts"] = json::array({json{{"time", 0.5}, {"x", 0}, {"z", 0}}});
        j["background"] = 30;
        j["max_characters"] = 300;
        FloorPaint f;
        f.width = 200, f.height = 120, f.metresPerPixel = 0.1, f.origin = {-10, -6};
        f.painted.assign(static_cast<std::size_t>(f.width * f.height), 0);
        s.floor = std::move(f);
        break;
    }
    case SetupKind::Luggage: j = json{{"kind", "luggage"}, {"seed", 1}, {"porters", 4}, {"handoffs", 8}, {"duration", 300}}; break;
    case SetupKind::Football:
        j = json{{"kind", "football"}, {"seed", 1}, {"tacklers", 6}, {"goal", 45}, {"duration", 60}, {"entry_radius", 8}};
        j["directions"] = json::array({json{{"time", 0}, {"heading_deg", 0}}});
        break;
    case SetupKind::Rat:
        j = json{{"kind", "rat"}, {"seed", 1}};
        j["rat"] = json{{"path", json::array({json::array({-7, 0}), json::array({7, 0})})}, {"speed", 2.5}, {"start", 1.0}};
        j["crowd"] = 60;
        break;
    // The Interaction Graph kinds: `fray-cli igraph play`'s defaults
    // (docs/IGRAPH.md), so a new setup plays what `igraph play` plays.
    case SetupKind::GraphDuel:
        j = json{{"version", 1}, {"duration", 20}, {"seed", 1}, {"you", "graph"}, {"style", "general"}, {"depth", 3},
                 {"opponent", "graph"}, {"opponent_style", "general"}, {"opponent_depth", 3}, {"distance", 1.3}, {"jitter", 0.3},
                 {"graph_states", 80000}};
        break;
    case SetupKind::GraphTeams:
        j = json{{"version", 1}, {"duration", 20}, {"seed", 1}, {"red", 10}, {"blue", 10}, {"style", "general"}, {"depth", 3},
                 {"opponent_style", "general"}, {"opponent_depth", 3}, {"jitter", 0.2}, {"graph_states", 80000}};
        break;
    case SetupKind::GraphCarry: {
        j = json{{"version", 1}, {"duration", 60}, {"seed", 1}, {"depth", 3}, {"carry_states", 20000}};
        // The box's path: a circle of 3 m about the origin (igraph play --path circle:3).
        Trajectory t;
        t.character = "box";
        t.shape = TrajectoryShape::Circle;
        t.points = {{0, 0}, {3, 0}};
        t.loop = true;
        s.trajectories.push_back(std::move(t));
        break;
    }
    }
    storeSpec(s, j);
    return s;
}

// ---- typed access -------------------------------------------------------------

std::vector<SetupCharacter> characters(const SceneSetup& setup) {
    std::vector<SetupCharacter> out;
    if (setup.kind == SetupKind::GraphCarry) {
        // The box (its middle follows the setup's trajectory): what the trajectory tools draw for.
        SetupCharacter box;
        box.name = "box";
        for (const auto& t : setup.trajectories) {
            // Where the path starts: a circle's point on the rim, else its first point.
            if (t.character != box.name || t.points.empty()) continue;
            const Point& p = t.shape == TrajectoryShape::Circle && t.points.size() > 1 ? t.points[1] : t.points[0];
            box.start = {p.x, p.z, 0};
        }
        out.push_back(box);
        return out;
    }
    if (setup.kind == SetupKind::GraphDuel || setup.kind == SetupKind::GraphTeams) return out;  // seeded placements
    const json j = specObject(setup);
    const auto cs = j.find("characters");
    if (cs == j.end() || !cs->is_array()) return out;
    int i = 0;
    for (const json& c : *cs) {
        SetupCharacter sc;
        sc.side = i++;
        if (!c.is_object()) {
            out.push_back(sc);
            continue;
        }
        if (auto v = c.find("name"); v != c.end() && v->is_string()) sc.name = v->get<std::string>();
        if (auto v = c.find("side"); v != c.end() && v->is_number_integer()) sc.side = v->get<int>();
        if (auto v = c.find("preset"); v != c.end() && v->is_string()) sc.preset = v->get<std::string>();
        if (auto v = c.find("depth"); v != c.end() && v->is_number_integer()) sc.depth = v->get<int>();
        if (auto st = c.find("start"); st != c.end() && st->is_object()) {
            for (auto [key, outp] : {std::pair<const char*, double*>{"x", &sc.start.x}, {"z", &sc.start.z}, {"heading_deg", &sc.start.headingDeg}}) {
                if (auto f = st->find(key); f != st->end() && f->is_number()) *outp = f->get<double>();
            }
        }
        out.push_back(sc);
    }
    return out;
}

int characterIndex(const SceneSetup& setup, std::string_view name) {
    const auto cs = characters(setup);
    for (std::size_t i = 0; i < cs.size(); ++i) {
        if (cs[i].name == name) return static_cast<int>(i);
    }
    return -1;
}

Status setCharacterStart(SceneSetup& setup, std::string_view character, const Placement& start) {
    if (!finite(start.x) || !finite(start.z) || !finite(start.headingDeg) || std::fabs(start.x) > 1e5 || std::fabs(start.z) > 1e5 ||
        std::fabs(start.headingDeg) > 1e6) {
        return setupError(setup, "the start of '" + std::string(character) + "' must be finite and within 100 km");
    }
    if (setup.kind == SetupKind::GraphDuel || setup.kind == SetupKind::GraphTeams || setup.kind == SetupKind::GraphCarry) {
        return setupError(setup, std::string("a ") + setupKindName(setup.kind) +
                                     " setup places its characters by its seed and parameters (distance, jitter; the carry path)");
    }
    const int index = characterIndex(setup, character);
    if (index < 0) return setupError(setup, "no character named '" + std::string(character) + "'");
    return updateSpec(setup, [&](json& j) -> Status {
        json& c = j["characters"][static_cast<std::size_t>(index)];
        json& st = c["start"];
        if (!st.is_object()) st = json::object();
        putNumber(st["x"], start.x);
        putNumber(st["z"], start.z);
        putNumber(st["heading_deg"], start.headingDeg);
        return {};
    });
}

Status moveTeam(SceneSetup& setup, int side, double dx, double dz) {
    if (!finite(dx) || !finite(dz)) return setupError(setup, "a team move must be finite");
    const auto cs = characters(setup);
    bool any = false;
    for (const auto& c : cs) {
        if (c.side != side) continue;
        any = true;
        Placement p = c.start;
        p.x += dx, p.z += dz;
        if (auto st = setCharacterStart(setup, c.name, p); !st) return st;
    }
    if (!any) return setupError(setup, "no character is on side " + std::to_string(side));
    return {};
}

std::vector<Point> ratPath(const SceneSetup& setup) {
    std::vector<Point> out;
    const json j = specObject(setup);
    const auto r = j.find("rat");
    if (r == j.end() || !r->is_object()) return out;
    const auto p = r->find("path");
    if (p == r->end() || !p->is_array()) return out;
    for (const json& q : *p) {
        if (q.is_array() && q.size() == 2 && q[0].is_number() && q[1].is_number()) out.push_back({q[0].get<double>(), q[1].get<double>()});
    }
    return out;
}

Status setRatPath(SceneSetup& setup, const std::vector<Point>& path) {
    if (setup.kind != SetupKind::Rat) return setupError(setup, "only a rat setup has a rat trajectory");
    if (path.size() < 2) return setupError(setup, "the rat's trajectory needs at least 2 points");
    for (const auto& p : path) {
        if (!finite(p.x) || !finite(p.z) || std::fabs(p.x) > 1e5 || std::fabs(p.z) > 1e5) {
            return setupError(setup, "the rat's trajectory points must be finite and within 100 km");
        }
    }
    return updateSpec(setup, [&](json& j) -> Status {
        json& r = j["rat"];
        if (!r.is_object()) r = json::object();
        json& old = r["path"];
        json arr = json::array();
        for (std::size_t i = 0; i < path.size(); ++i) {
            json q = old.is_array() && i < old.size() && old[i].is_array() && old[i].size() == 2 ? old[i] : json::array({0, 0});
            putNumber(q[0], path[i].x);
            putNumber(q[1], path[i].z);
            arr.push_back(q);
        }
        old = arr;
        return {};
    });
}

std::vector<RunDirection> runDirections(const SceneSetup& setup) {
    std::vector<RunDirection> out;
    const json j = specObject(setup);
    const auto d = j.find("directions");
    if (d == j.end() || !d->is_array()) return out;
    for (const json& q : *d) {
        RunDirection r;
        if (!q.is_object()) continue;
        if (auto t = q.find("time"); t != q.end() && t->is_number()) r.time = t->get<double>();
        if (auto h = q.find("heading_deg"); h != q.end() && h->is_number()) r.headingDeg = h->get<double>();
        r.at = readAt(q);
        out.push_back(r);
    }
    return out;
}

Status setRunDirections(SceneSetup& setup, const std::vector<RunDirection>& directions) {
    if (setup.kind != SetupKind::Football) return setupError(setup, "only a football setup has running directions");
    for (std::size_t i = 0; i < directions.size(); ++i) {
        if (!finite(directions[i].time) || directions[i].time < 0 || !finite(directions[i].headingDeg)) {
            return setupError(setup, "running direction " + std::to_string(i + 1) + ": time must be >= 0 and the heading finite");
        }
        if (!(std::fabs(directions[i].headingDeg) < 80)) {
            return setupError(setup, "running direction " + std::to_string(i + 1) +
                                         ": the heading must be within 80 degrees of the goal direction (0 = +Z)");
        }
        if (!atOk(directions[i].at)) {
            return setupError(setup, "running direction " + std::to_string(i + 1) + ": its place must be finite and within 100 km");
        }
        if (i > 0 && directions[i].time < directions[i - 1].time) return setupError(setup, "running directions must be in time order");
    }
    return updateSpec(setup, [&](json& j) -> Status {
        json& old = j["directions"];
        json arr = json::array();
        for (std::size_t i = 0; i < directions.size(); ++i) {
            json q = old.is_array() && i < old.size() && old[i].is_object() ? old[i] : json::object();
            putNumber(q["time"], directions[i].time);
            putNumber(q["heading_deg"], directions[i].headingDeg);
            putAt(q, directions[i].at);
            arr.push_back(q);
        }
        old = arr;
        return {};
    });
}

std::vector<TimedCommand> timedCommands(const SceneSetup& setup) {
    std::vector<TimedCommand> out;
    const json j = specObject(setup);
    const auto d = j.find("commands");
    if (d == j.end() || !d->is_array()) return out;
    for (const json& q : *d) {
        TimedCommand c;
        if (!q.is_object()) continue;
        if (auto t = q.find("time"); t != q.end() && t->is_number()) c.time = t->get<double>();
        if (auto a = q.find("action"); a != q.end() && a->is_string()) c.action = a->get<std::string>();
        c.at = readAt(q);
        out.push_back(c);
    }
    return out;
}

Status setTimedCommands(SceneSetup& setup, const std::vector<TimedCommand>& commands) {
    if (setup.kind != SetupKind::OneVsMany && setup.kind != SetupKind::OneVsOne) {
        return setupError(setup, "timed commands belong to one-vs-many (and one-vs-one) setups");
    }
    static const char* const verbs[] = {"move", "punch", "kick", "avoid", "attack", "defence", "block"};
    for (std::size_t i = 0; i < commands.size(); ++i) {
        const auto& c = commands[i];
        if (std::find_if(std::begin(verbs), std::end(verbs), [&](const char* v) { return c.action == v; }) == std::end(verbs)) {
            return setupError(setup, "command " + std::to_string(i + 1) + ": unknown command '" + c.action +
                                         "' (move, punch, kick, avoid, attack, defence, block)");
        }
        if (!finite(c.time) || c.time < 0 || c.time > 3600) return setupError(setup, "command " + std::to_string(i + 1) + ": time must be in [0, 3600] s");
        if (i > 0 && c.time < commands[i - 1].time) return setupError(setup, "commands must be in time order");
        if (!atOk(c.at)) return setupError(setup, "command " + std::to_string(i + 1) + ": its place must be finite and within 100 km");
        if (c.action == "move" && !c.at) {
            return setupError(setup, "command " + std::to_string(i + 1) + ": a move command needs the place to move to");
        }
        if (c.action == "move" && setup.kind != SetupKind::OneVsMany) {
            return setupError(setup, "command " + std::to_string(i + 1) + ": move commands belong to one-vs-many setups");
        }
    }
    return updateSpec(setup, [&](json& j) -> Status {
        json& old = j["commands"];
        json arr = json::array();
        for (std::size_t i = 0; i < commands.size(); ++i) {
            json q = old.is_array() && i < old.size() && old[i].is_object() ? old[i] : json::object();
            putNumber(q["time"], commands[i].time);
            q["action"] = commands[i].action;
            putAt(q, commands[i].at);
            arr.push_back(q);
        }
        old = arr;
        return {};
    });
}

std::vector<DominoStartPoint> dominoStarts(const SceneSetup& setup) {
    std::vector<DominoStartPoint> out;
    const json j = specObject(setup);
    const auto d = j.find("starts");
    if (d == j.end() || !d->is_array()) return out;
    for (const json& q : *d) {
        DominoStartPoint s;
        if (!q.is_object()) continue;
        if (auto t = q.find("time"); t != q.end() && t->is_number()) s.time = t->get<double>();
        if (auto x = q.find("x"); x != q.end() && x->is_number()) s.pos.x = x->get<double>();
        if (auto z = q.find("z"); z != q.end() && z->is_number()) s.pos.z = z->get<double>();
        out.push_back(s);
    }
    return out;
}

Status setDominoStarts(SceneSetup& setup, const std::vector<DominoStartPoint>& starts) {
    if (setup.kind != SetupKind::Domino) return setupError(setup, "only a domino setup has chain starts");
    for (std::size_t i = 0; i < starts.size(); ++i) {
        const auto& s = starts[i];
        if (!finite(s.time) || s.time < 0 || s.time > 3600 || !finite(s.pos.x) || !finite(s.pos.z)) {
            return setupError(setup, "start " + std::to_string(i + 1) + ": time must be in [0, 3600] s and the position finite");
        }
    }
    return updateSpec(setup, [&](json& j) -> Status {
        json& old = j["starts"];
        json arr = json::array();
        for (std::size_t i = 0; i < starts.size(); ++i) {
            json q = old.is_array() && i < old.size() && old[i].is_object() ? old[i] : json::object();
            putNumber(q["time"], starts[i].time);
            putNumber(q["x"], starts[i].pos.x);
            putNumber(q["z"], starts[i].pos.z);
            arr.push_back(q);
        }
        old = arr;
        return {};
    });
}

Status setFloorScale(SceneSetup& setup, double metresPerPixel) {
    if (!setup.floor) return setupError(setup, "has no painted floor (paint it or import a bitmap first)");
    if (!(metresPerPixel > 0.001) || metresPerPixel > 10) {
        return setupError(setup, "/floor/metres_per_pixel: must be in (0.001, 10] (the painted floor's metres per pixel)");
    }
    const double ratio = metresPerPixel / setup.floor->metresPerPixel;
    const Point origin = setup.floor->origin;
    setup.floor->metresPerPixel = metresPerPixel;
    return updateSpec(setup, [&](json& j) -> Status {
        if (auto f = j.find("floor"); f != j.end() && f->is_object() && f->contains("metres_per_pixel")) {
            putNumber((*f)["metres_per_pixel"], metresPerPixel);
        }
        // A domino's chain starts stay on the pixels they were put on.
        if (auto st = j.find("starts"); setup.kind == SetupKind::Domino && st != j.end() && st->is_array()) {
            for (json& q : *st) {
                if (!q.is_object()) continue;
                for (auto [key, o] : {std::pair<const char*, double>{"x", origin.x}, {"z", origin.z}}) {
                    if (auto v = q.find(key); v != q.end() && v->is_number()) putNumber(*v, o + (v->get<double>() - o) * ratio);
                }
            }
        }
        return {};
    });
}

Status setParameter(SceneSetup& setup, std::string_view pointer, std::string_view value) {
    if (pointer.empty() || pointer[0] != '/') return setupError(setup, "parameter '" + std::string(pointer) + "' must be a JSON pointer (\"/duration\")");
    if (pointer == "/kind" || pointer.starts_with("/kind/")) return setupError(setup, "the kind is set on the setup, not as a parameter");
    if (pointer == "/floor" || pointer.starts_with("/floor/")) {
        return setupError(setup, "the floor's bitmap, scale and origin are edited with the bitmap tools");
    }
    auto v = prep::parseJson(value, "value");
    if (!v) return setupError(setup, std::string(pointer) + ": " + v.error().message);
    json::json_pointer ptr;
    try {
        ptr = json::json_pointer(std::string(pointer));
    } catch (const std::exception&) {
        return setupError(setup, "parameter '" + std::string(pointer) + "' is not a valid JSON pointer");
    }
    return updateSpec(setup, [&](json& j) -> Status {
        try {
            if (v->is_null()) {
                if (!j.contains(ptr)) return {};
                j.at(ptr.parent_pointer()).erase(ptr.back());
                return {};
            }
            j[ptr] = *v;
        } catch (const std::exception& e) {
            return setupError(setup, std::string(pointer) + ": cannot be set here (" + e.what() + ")");
        }
        return {};
    });
}

std::optional<std::string> parameter(const SceneSetup& setup, std::string_view pointer) {
    const json j = specObject(setup);
    try {
        const json::json_pointer ptr{std::string(pointer)};
        if (!j.contains(ptr)) return std::nullopt;
        return prep::dumpJson(j.at(ptr));
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

// ---- trajectories --------------------------------------------------------------

Result<std::vector<Point>> sampleTrajectory(const Trajectory& t, double spacing) {
    if (!(spacing > 0.01)) spacing = 0.5;
    std::vector<Point> out;
    const auto& p = t.points;
    switch (t.shape) {
    case TrajectoryShape::Polyline: {
        if (p.empty()) return makeError("the trajectory of '" + t.character + "' is empty: give at least one point");
        out.push_back(p[0]);
        for (std::size_t i = 1; i < p.size(); ++i) {
            const double dx = p[i].x - p[i - 1].x, dz = p[i].z - p[i - 1].z;
            const double len = std::hypot(dx, dz);
            const int n = std::max(1, static_cast<int>(std::ceil(len / spacing)));
            for (int k = 1; k <= n; ++k) {
                const double f = static_cast<double>(k) / n;
                out.push_back({p[i - 1].x + dx * f, p[i - 1].z + dz * f});
            }
        }
        return out;
    }
    case TrajectoryShape::Arc: {
        if (p.size() != 3) return makeError("the arc of '" + t.character + "' needs 3 points (start, through, end)");
        // Circumcentre of the three points.
        const double ax = p[0].x, az = p[0].z, bx = p[1].x, bz = p[1].z, cx = p[2].x, cz = p[2].z;
        const double d = 2 * (ax * (bz - cz) + bx * (cz - az) + cx * (az - bz));
        if (std::fabs(d) < 1e-9) return makeError("the arc of '" + t.character + "': its three points are on a line");
        const double a2 = ax * ax + az * az, b2 = bx * bx + bz * bz, c2 = cx * cx + cz * cz;
        const double ux = (a2 * (bz - cz) + b2 * (cz - az) + c2 * (az - bz)) / d;
        const double uz = (a2 * (cx - bx) + b2 * (ax - cx) + c2 * (bx - ax)) / d;
        const double r = std::hypot(ax - ux, az - uz);
        const double a0 = std::atan2(az - uz, ax - ux), a1 = std::atan2(bz - uz, bx - ux), a2n = std::atan2(cz - uz, cx - ux);
        auto ccw = [](double from, double to) {
            double d2 = to - from;
            while (d2 < 0) d2 += 2 * std::numbers::pi;
            while (d2 >= 2 * std::numbers::pi) d2 -= 2 * std::numbers::pi;
            return d2;
        };
        // Counter-clockwise from start to end passes the middle point, or the arc runs clockwise.
        double sweep = ccw(a0, a2n);
        if (ccw(a0, a1) > sweep) sweep = sweep - 2 * std::numbers::pi;
        const int n = std::max(2, static_cast<int>(std::ceil(std::fabs(sweep) * r / spacing)));
        for (int k = 0; k <= n; ++k) {
            const double a = a0 + sweep * k / n;
            out.push_back({ux + r * std::cos(a), uz + r * std::sin(a)});
        }
        out.front() = p[0];
        out.back() = p[2];
        return out;
    }
    case TrajectoryShape::Circle: {
        if (p.size() != 2) return makeError("the circle of '" + t.character + "' needs 2 points (centre, a point on it)");
        const double r = std::hypot(p[1].x - p[0].x, p[1].z - p[0].z);
        if (r < 0.05) return makeError("the circle of '" + t.character + "' has no radius (its two points coincide)");
        const double a0 = std::atan2(p[1].z - p[0].z, p[1].x - p[0].x);
        const int n = std::max(8, static_cast<int>(std::ceil(2 * std::numbers::pi * r / spacing)));
        for (int k = 0; k < n; ++k) {
            const double a = a0 + (t.clockwise ? -1.0 : 1.0) * 2 * std::numbers::pi * k / n;
            out.push_back({p[0].x + r * std::cos(a), p[0].z + r * std::sin(a)});
        }
        out.front() = p[1];
        if (!t.loop) out.push_back(p[1]);  // once round, back to the start
        return out;
    }
    }
    return out;
}

double trajectoryParameter(const std::vector<Point>& line, Point p, double* distance) {
    double best = std::numeric_limits<double>::max(), bestS = 0, s = 0;
    if (line.size() == 1) {
        if (distance) *distance = std::hypot(p.x - line[0].x, p.z - line[0].z);
        return 0;
    }
    for (std::size_t i = 1; i < line.size(); ++i) {
        const double dx = line[i].x - line[i - 1].x, dz = line[i].z - line[i - 1].z;
        const double len2 = dx * dx + dz * dz;
        double f = len2 > 0 ? ((p.x - line[i - 1].x) * dx + (p.z - line[i - 1].z) * dz) / len2 : 0;
        f = std::clamp(f, 0.0, 1.0);
        const double qx = line[i - 1].x + dx * f, qz = line[i - 1].z + dz * f;
        const double d = std::hypot(p.x - qx, p.z - qz);
        if (d < best - 1e-12) best = d, bestS = s + f * std::sqrt(len2);
        s += std::sqrt(len2);
    }
    if (distance) *distance = best;
    return bestS;
}

// ---- bitmap --------------------------------------------------------------------

sim::FloorBitmap toFloorBitmap(const FloorPaint& paint) {
    sim::FloorBitmap f;
    f.width = paint.width, f.height = paint.height;
    f.painted = paint.painted;
    f.origin = {static_cast<float>(paint.origin.x), static_cast<float>(paint.origin.z)};
    f.metresPerPixel = paint.metresPerPixel;
    return f;
}

FloorPaint fromFloorBitmap(const sim::FloorBitmap& floor) {
    FloorPaint p;
    p.width = floor.width, p.height = floor.height;
    p.painted = floor.painted;
    for (auto& b : p.painted) b = b ? 1 : 0;
    p.origin = {floor.origin.x, floor.origin.y};
    p.metresPerPixel = floor.metresPerPixel;
    return p;
}

std::string encodeFloor(const FloorPaint& paint) {
    // Eight pixels a byte, the first in the high bit, row after row (the last byte padded with 0).
    std::vector<unsigned char> bits((paint.painted.size() + 7) / 8, 0);
    for (std::size_t i = 0; i < paint.painted.size(); ++i) {
        if (paint.painted[i]) bits[i / 8] |= static_cast<unsigned char>(0x80u >> (i % 8));
    }
    uLongf size = compressBound(static_cast<uLong>(bits.size()));
    std::vector<unsigned char> out(size);
    const int rc = compress2(out.data(), &size, bits.data(), static_cast<uLong>(bits.size()), 6);
    if (rc != Z_OK) return {};
    out.resize(size);
    return base64(out);
}

Result<FloorPaint> decodeFloor(std::string_view data, int width, int height, std::string_view what) {
    std::string w(what);
    while (!w.empty() && (w.back() == ' ' || w.back() == ':')) w.pop_back();
    if (width < 1 || height < 1 || width > kMaxFloorPixels || height > kMaxFloorPixels) return makeError(w + ": bad size");
    const auto bytes = unbase64(data);
    if (!bytes) return makeError(w + ": not base64 text");
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    std::vector<unsigned char> bits((pixels + 7) / 8, 0);
    uLongf size = static_cast<uLongf>(bits.size());
    const int rc = uncompress(bits.data(), &size, bytes->data(), static_cast<uLong>(bytes->size()));
    if (rc != Z_OK || size != bits.size()) {
        return makeError(w + ": damaged (does not inflate to " + std::to_string(width) + " x " + std::to_string(height) + " pixels)");
    }
    if (pixels % 8 != 0 && (bits.back() & (0xffu >> (pixels % 8))) != 0) return makeError(w + ": damaged (padding bits are set)");
    FloorPaint p;
    p.width = width, p.height = height;
    p.painted.resize(pixels);
    for (std::size_t i = 0; i < pixels; ++i) p.painted[i] = (bits[i / 8] >> (7 - i % 8)) & 1u;
    return p;
}

}  // namespace fray::setup
