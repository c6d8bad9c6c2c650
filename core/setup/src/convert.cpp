// Setup <-> spec conversions (convert.h): the one place that knows how a
// setup's fields map onto the --spec formats of simulate and compose.
#include "fray/setup/convert.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/prep/json_reader.h"
#include "fray/sim/compose/domino.h"
#include "fray/setup/graph_setup.h"

namespace fray::setup {
namespace {

using json = nlohmann::ordered_json;
using prep::JsonReader;

void putNumber(json& slot, double v) {
    if (slot.is_number() && slot.get<double>() == v) return;
    if (std::floor(v) == v && std::fabs(v) < 1e15) slot = static_cast<std::int64_t>(v);
    else slot = v;
}

double mm(double x) { return std::round(x * 1000.0) / 1000.0; }

std::string what(const SceneSetup& s) { return "setup '" + s.name + "'"; }

// A trajectory as the planner's checkpoint path: the shape sampled every
// metre, the user's checkpoints inserted where they lie along it (waypoints
// closer than 0.3 m to a checkpoint are dropped).
Result<json> pathJson(const Trajectory& t) {
    FRAY_TRY(line, sampleTrajectory(t, 1.0));
    std::vector<double> along(line.size(), 0);
    for (std::size_t i = 1; i < line.size(); ++i) along[i] = along[i - 1] + std::hypot(line[i].x - line[i - 1].x, line[i].z - line[i - 1].z);
    struct Item {
        double s;
        int order;  // waypoints before checkpoints at the same place
        json value;
    };
    std::vector<Item> items;
    std::vector<double> cps;
    for (const auto& c : t.checkpoints) {
        const double s = trajectoryParameter(line, c.pos);
        cps.push_back(s);
        json j{{"x", mm(c.pos.x)}, {"z", mm(c.pos.z)}};
        if (c.time) j["time"] = *c.time;
        if (!c.action.empty()) j["action"] = c.action;
        items.push_back({s, 1, j});
    }
    for (std::size_t i = 0; i < line.size(); ++i) {
        const bool near = std::any_of(cps.begin(), cps.end(), [&](double s) { return std::fabs(s - along[i]) < 0.3; });
        if (near) continue;
        items.push_back({along[i], 0, json{{"x", mm(line[i].x)}, {"z", mm(line[i].z)}}});
    }
    std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.s < b.s || (a.s == b.s && a.order < b.order); });
    json path = json::array();
    for (auto& it : items) path.push_back(std::move(it.value));
    return path;
}

}  // namespace

Result<std::string> setupSpecJson(const SceneSetup& setup) {
    json j = json::parse(setup.spec, nullptr, false);
    if (!j.is_object()) return makeError(what(setup) + ": the parameters are not a JSON object");
    if (isGraphKind(setup.kind)) {
        // The parameters with "kind" first and, for carry, the box's "path"
        // (the form `fray-cli setup import` reads back).
        json out;
        out["kind"] = setupKindName(setup.kind);
        for (auto it = j.begin(); it != j.end(); ++it) {
            if (it.key() != "kind" && it.key() != "path") out[it.key()] = it.value();
        }
        if (const Trajectory* t = carryTrajectory(setup)) {
            if (t->shape == TrajectoryShape::Circle && t->points.size() == 2 && t->points[0] == Point{0, 0} && t->points[1].z == 0 &&
                t->points[1].x > 0 && !t->clockwise && t->loop) {
                char buf[64];
                std::snprintf(buf, sizeof buf, "circle:%.17g", t->points[1].x);
                // The shortest spelling that reads back the same.
                for (int prec = 1; prec <= 17; ++prec) {
                    char b[64];
                    std::snprintf(b, sizeof b, "circle:%.*g", prec, t->points[1].x);
                    if (std::strtod(b + 7, nullptr) == t->points[1].x) {
                        std::snprintf(buf, sizeof buf, "%s", b);
                        break;
                    }
                }
                out["path"] = buf;
            } else {
                FRAY_TRY(line, sampleTrajectory(*t, 0.1));
                json pts = json::array();
                for (const auto& p : line) pts.push_back(json::array({mm(p.x), mm(p.z)}));
                out["path"] = json{{"loop", t->loop}, {"points", pts}};
            }
        }
        return prep::dumpJson(out, 2);
    }
    if (isTreeExpansion(setup.kind)) {
        j.erase("kind");
        for (const auto& t : setup.trajectories) {
            auto cs = j.find("characters");
            json* target = nullptr;
            if (cs != j.end() && cs->is_array()) {
                for (auto& c : *cs) {
                    if (c.is_object() && c.value("name", std::string()) == t.character) target = &c;
                }
            }
            if (!target) return makeError(what(setup) + ": a trajectory follows '" + t.character + "', who is not a character of the setup");
            // Timed checkpoints make a schedule for one lap (a time is passed
            // once), so a looped trajectory (the Circle tool's) with any is
            // followed once round by that schedule, back to where it starts;
            // without times it keeps looping (the thesis' next-checkpoint term).
            Trajectory followed = t;
            if (t.loop && std::any_of(t.checkpoints.begin(), t.checkpoints.end(), [](const SetupCheckpoint& c) { return c.time.has_value(); }))
                followed.loop = false;
            auto path = pathJson(followed);
            if (!path) return makeError(what(setup) + ": " + path.error().message);
            (*target)["path"] = std::move(*path);
            if (followed.loop || target->contains("loop_path")) (*target)["loop_path"] = followed.loop;
            // A drawn trajectory is followed: unless the character's weights
            // say how much (w_path), with kDrawnPathWeight (the presets
            // without "-path" weigh no path at all).
            if (!target->contains("weights")) (*target)["weights"] = json::object();
            if (auto& w = (*target)["weights"]; w.is_object() && !w.contains("w_path")) w["w_path"] = kDrawnPathWeight;
        }
        // Pins of edited generated interactions (docs/TREE_EXPANSION.md "Pins"); none:
        // no field, so a setup without pins plans the bytes it always did.
        if (!setup.pins.empty()) {
            json pins = json::array();
            for (const auto& p : setup.pins) {
                json jp{{"character", p.character}, {"time", 0}, {"action", p.action}};
                putNumber(jp["time"], p.time);
                pins.push_back(std::move(jp));
            }
            j["pins"] = std::move(pins);
        }
    } else {
        if (!setup.trajectories.empty()) {
            return makeError(what(setup) + ": trajectories with checkpoints belong to duel and chase setups (a " +
                             setupKindName(setup.kind) + " setup keeps its own paths in its parameters)");
        }
        if (auto k = j.find("kind"); k != j.end()) {
            *k = setupKindName(setup.kind);
        } else {
            json withKind;
            withKind["kind"] = setupKindName(setup.kind);
            for (auto it = j.begin(); it != j.end(); ++it) withKind[it.key()] = it.value();
            j = std::move(withKind);
        }
        if (setup.floor) {
            json& fl = j["floor"];
            if (!fl.is_object()) fl = json::object();
            if (!fl.contains("bitmap") || !fl["bitmap"].is_string() || fl["bitmap"].get<std::string>().empty()) fl["bitmap"] = "(painted)";
            putNumber(fl["metres_per_pixel"], setup.floor->metresPerPixel);
            json& o = fl["origin"];
            if (!o.is_array() || o.size() != 2) o = json::array({0, 0});
            putNumber(o[0], setup.floor->origin.x);
            putNumber(o[1], setup.floor->origin.z);
        }
    }
    return prep::dumpJson(j, 2);
}

Result<sim::SceneSpec> toSceneSpec(const SceneSetup& setup, const sim::ActionLibrary& lib, const std::vector<sim::Preset>& presets) {
    if (!isTreeExpansion(setup.kind)) {
        return makeError(what(setup) + " is a " + std::string(setupKindName(setup.kind)) + " setup: run it with compose, not simulate");
    }
    FRAY_TRY(text, setupSpecJson(setup));
    return sim::parseSceneSpec(text, what(setup), lib, presets);
}

std::string pinsNotHonoured(const SceneSetup& setup) {
    if (setup.pins.empty() || isTreeExpansion(setup.kind)) return {};
    return what(setup) + " has " + std::to_string(setup.pins.size()) + (setup.pins.size() == 1 ? " pin" : " pins") +
           " that compose does not honour: a " + setupKindName(setup.kind) +
           " scene is composed from Interaction Patches, and only duel and chase setups (tree expansion) plan around pins";
}

Result<sim::ComposeSpec> toComposeSpec(const SceneSetup& setup, const sim::PatchLibrary& patches) {
    if (isTreeExpansion(setup.kind)) {
        return makeError(what(setup) + " is a " + std::string(setupKindName(setup.kind)) + " setup: run it with simulate, not compose");
    }
    FRAY_TRY(text, setupSpecJson(setup));
    FRAY_TRY(spec, sim::parseComposeSpec(text, what(setup), patches));
    if (auto* domino = spec.part<sim::DominoSpec>(); domino && setup.floor) {
        domino->floorFile.clear();  // the pixels are the setup's, not a file's
        domino->floor = toFloorBitmap(*setup.floor);
    }
    return spec;
}

Status checkComposeSetup(const SceneSetup& setup, const std::vector<sim::PatternList>& patterns) {
    if (isTreeExpansion(setup.kind) || isGraphKind(setup.kind)) {
        return makeError(what(setup) + " is a " + std::string(setupKindName(setup.kind)) + " setup: it is not composed");
    }
    FRAY_TRY(text, setupSpecJson(setup));
    FRAY_TRY(spec, sim::parseComposeSpec(text, what(setup), patterns));
    (void)spec;
    return {};
}

namespace {
// An Interaction Graph spec: the parameters as they are (checked by
// graphParams), a carry's "path" ("circle:R" or {"loop", "points"}) made
// the box's trajectory.
Result<SceneSetup> importGraphSpec(SceneSetup s, json j, const JsonReader& rd) {
    j.erase("kind");
    if (auto p = j.find("path"); p != j.end()) {
        if (s.kind != SetupKind::GraphCarry) return rd.error("/path", "only a graph-carry setup has a path");
        Trajectory t;
        t.character = kCarryPathCharacter;
        if (p->is_string()) {
            const std::string text = p->get<std::string>();
            char* end = nullptr;
            const double r = text.rfind("circle:", 0) == 0 ? std::strtod(text.c_str() + 7, &end) : 0;
            if (!end || *end != '\0' || !std::isfinite(r) || r < 0.5 || r > 1000) {
                return rd.error("/path", "'" + text + "' is not circle:R (R in [0.5, 1000] m) or {\"loop\", \"points\"}");
            }
            t.shape = TrajectoryShape::Circle;
            t.points = {{0, 0}, {r, 0}};
            t.loop = true;
        } else if (p->is_object()) {
            if (auto l = p->find("loop"); l != p->end()) {
                FRAY_TRY(b, rd.boolean(*l, "/path/loop"));
                t.loop = b;
            }
            FRAY_TRY(pts, rd.field(*p, "/path", "points"));
            if (!pts->is_array() || pts->size() < 2) return rd.error("/path/points", "must be an array of at least 2 [x, z] points");
            for (std::size_t i = 0; i < pts->size(); ++i) {
                const std::string at = "/path/points/" + std::to_string(i);
                const json& q = (*pts)[i];
                if (!q.is_array() || q.size() != 2) return rd.error(at, "must be [x, z]");
                FRAY_TRY(x, rd.numberIn(q[0], at + "/0", -1e5, 1e5));
                FRAY_TRY(z, rd.numberIn(q[1], at + "/1", -1e5, 1e5));
                t.points.push_back({x, z});
            }
        } else {
            return rd.error("/path", "must be circle:R or {\"loop\", \"points\"}");
        }
        s.trajectories.push_back(std::move(t));
        j.erase("path");
    }
    s.spec = prep::dumpJson(j);
    FRAY_TRY(checked, graphParams(s));
    (void)checked;
    return s;
}
}  // namespace

Result<SceneSetup> importSpec(std::string name, std::string_view text, const std::filesystem::path& specFile,
                              const FloorLoader& loadFloor) {
    if (auto st = checkSetupName(name); !st) return st.error();
    const std::string file = specFile.string();
    FRAY_TRY(j, prep::parseJson(text, file));
    const JsonReader rd(file);
    if (!j.is_object()) return rd.error("", "must be a JSON object (a scene spec)");
    SceneSetup s;
    s.name = std::move(name);
    if (auto k = j.find("kind"); k != j.end()) {
        FRAY_TRY(kindName, rd.string(*k, "/kind"));
        const auto kind = setupKindFromName(kindName);
        if (!kind || isTreeExpansion(*kind)) {
            return rd.error("/kind", "unknown scene kind '" + kindName + "' (one-vs-many, one-vs-one, domino, luggage, football, rat, "
                                     "graph-duel, graph-teams, graph-carry; a simulate spec has no kind)");
        }
        s.kind = *kind;
        if (isGraphKind(*kind)) return importGraphSpec(std::move(s), j, rd);
    } else {
        FRAY_TRY(cs, rd.field(j, "", "characters"));
        if (!cs->is_array() || cs->empty()) return rd.error("/characters", "must be a non-empty array");
        bool chase = j.contains("stop_on_catch");
        for (const auto& c : *cs) {
            if (!c.is_object()) continue;
            const std::string preset = c.value("preset", std::string());
            if (preset.starts_with("chaser") || preset.starts_with("runaway")) chase = true;
        }
        s.kind = chase ? SetupKind::Chase : SetupKind::Duel;
    }
    if (auto f = j.find("floor"); f != j.end() && f->is_object()) {
        FRAY_TRY(bitmapName, rd.stringAt(*f, "/floor", "bitmap"));
        if (bitmapName.empty()) return rd.error("/floor/bitmap", "must name a PNG file");
        double mpp = 0.1;
        glm::vec2 origin(0.0f);
        if (auto m = f->find("metres_per_pixel"); m != f->end()) {
            FRAY_TRY(x, rd.number(*m, "/floor/metres_per_pixel"));
            if (!(x > 0.001) || x > 10) return rd.error("/floor/metres_per_pixel", "must be in (0.001, 10]");
            mpp = x;
        }
        if (auto o = f->find("origin"); o != f->end()) {
            if (!o->is_array() || o->size() != 2) return rd.error("/floor/origin", "must be [x, z]");
            FRAY_TRY(ox, rd.number((*o)[0], "/floor/origin/0"));
            FRAY_TRY(oz, rd.number((*o)[1], "/floor/origin/1"));
            origin = {static_cast<float>(ox), static_cast<float>(oz)};
        }
        std::filesystem::path bitmap(bitmapName);
        if (bitmap.is_relative()) bitmap = specFile.parent_path() / bitmap;  // relative to the spec, as compose --spec reads it
        if (!loadFloor) return rd.error("/floor/bitmap", "no bitmap reader given");
        FRAY_TRY(floor, loadFloor(bitmap, mpp, origin));
        FloorPaint paint = fromFloorBitmap(floor);
        // The parser's float origin is what compose --spec uses; keep the written numbers.
        paint.metresPerPixel = mpp;
        if (auto o = f->find("origin"); o != f->end()) paint.origin = {(*o)[0].get<double>(), (*o)[1].get<double>()};
        if (paint.width > kMaxFloorPixels || paint.height > kMaxFloorPixels) {
            return rd.error("/floor/bitmap", "the bitmap is larger than " + std::to_string(kMaxFloorPixels) + " pixels a side");
        }
        s.floor = std::move(paint);
    }
    s.spec = prep::dumpJson(j);
    return s;
}

Result<sim::PatchLibrary> withoutRejected(const sim::PatchLibrary& patches, const std::vector<int>& rejected) {
    return sim::withoutPatches(patches, rejected);
}

}  // namespace fray::setup
