#include "summary.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <nlohmann/json.hpp>

#include "fray/core/atomic_file.h"
#include "fray/prep/pipeline.h"

namespace fray::exporter {
namespace {

using json = nlohmann::ordered_json;

// Derived quantities (degrees, positions) rounded to 0.1 mm / 0.0001 degree, so
// the file reads well; scene times are written as the scene has them.
double rounded(double v) {
    const double r = std::round(v * 1e4) / 1e4;
    return r == 0.0 ? 0.0 : r;  // no "-0.0"
}

json placementJson(const sim::RootXf& xf) {
    return {{"x", rounded(xf.pos.x)}, {"z", rounded(xf.pos.y)}, {"heading_deg", rounded(xf.heading * 180.0 / std::numbers::pi)}};
}

json actionJson(const sim::ActionInstance& inst, const sim::ActionLibrary& lib) {
    const auto& a = lib.actions()[static_cast<std::size_t>(inst.action)];
    json out = {{"label", a.label()},
            {"name", a.name},
            {"annotations", a.annotations},
            {"motion", a.motionId},
            {"first_frame", a.firstFrame},
            {"last_frame", a.lastFrame}};
    // The frames are the source motion's, at its own rate.
    if (a.motion >= 0 && a.motion < lib.motionCount()) {
        out["motion_fps"] = lib.motion(a.motion).motion.fps();
    }
    out.update(json{
            {"start", inst.start},
            {"end", inst.end},
            {"offset", inst.offset},
            {"forced", inst.forced},
            {"fallback", inst.fallback},
            {"root", placementJson(inst.root)}});
    return out;
}

// The root joint's scene position (m) at about every whole second and at the
// last frame, [time, x, y, z] each, from the exported samples: what a reader
// of the file should see (scripts/blender-import-check.py checks it).
json rootPathJson(const SampledScene& sampled, const CharacterTake& take) {
    json out = json::array();
    const int last = sampled.frames - 1;
    for (int s = 0;; ++s) {
        const int f = std::min(last, static_cast<int>(std::lround(s * sampled.fps)));
        const glm::vec3 p = take.motion.rootTranslation(f);
        out.push_back({sampled.time(f), rounded(p.x), rounded(p.y), rounded(p.z)});
        if (f == last) break;
    }
    return out;
}

json characterJson(const sim::SceneCharacter& c, const CharacterTake& take, const SampledScene& sampled,
                   const sim::ActionLibrary& lib) {
    const Skeleton& sk = take.motion.skeleton();
    json actions = json::array();
    for (const auto& inst : c.track) {
        // A looped idle is listed once a time round, each from its clip's
        // start, as a reader of the files sees it played.
        for (int k = 0; k < inst.repeats(); ++k) {
            sim::ActionInstance once = inst;
            once.loop = 0;
            once.start = inst.repeatStart(k);
            if (inst.looped()) once.end = std::min(inst.end, inst.repeatStart(k + 1));
            actions.push_back(actionJson(once, lib));
        }
    }
    json out = {{"name", c.name},
            {"file_name", take.fileName},
            {"side", c.side},
            {"group", c.group},
            {"joints", sk.jointCount()},
            {"root_joint", sk.jointCount() > 0 ? sk.names.front() : std::string()},
            // Composed scenes bring newcomers in later; before this time the
            // files hold the character in its first pose where it enters.
            {"enter", c.track.empty() ? 0.0 : c.track.front().start},
            {"actions", std::move(actions)},
            {"root_path", rootPathJson(sampled, take)}};
    // A one-joint body (a rat, a bag) plays no action: its root follows its keys.
    if (!c.body.empty()) out["body"] = c.body;
    return out;
}

// Where a hit landed: the centre of the attacker's effector box at that time.
std::optional<glm::vec3> hitPosition(const sim::Scene& scene, const sim::ActionLibrary& lib, const sim::HitEvent& h) {
    for (const auto& inst : scene.characters[static_cast<std::size_t>(h.attacker)].track) {
        if (inst.action != h.attackAction || h.time < inst.start - 1e-9 || h.time > inst.end + 1e-9) continue;
        const int sample = lib.sampleAt(inst.action, inst.offset + (h.time - inst.repeatStart(inst.repeatAt(h.time))));
        return lib.boxesAt(inst.action, sample)[h.effector].placed(inst.root).centre;
    }
    return std::nullopt;
}

json hitsJson(const sim::Scene& scene, const sim::ActionLibrary& lib) {
    auto name = [&](int c) { return scene.characters[static_cast<std::size_t>(c)].name; };
    json out = json::array();
    for (const auto& h : scene.hits) {
        json j = {{"time", h.time},
                  {"attacker", name(h.attacker)},
                  {"defender", name(h.defender)},
                  {"action", lib.actions()[static_cast<std::size_t>(h.attackAction)].label()},
                  {"effector", sim::segmentName(h.effector)},
                  {"target", sim::segmentName(h.target)},
                  {"speed", h.speed},
                  {"impulse", h.impulse},
                  {"blocked", h.blocked}};
        if (const auto p = hitPosition(scene, lib, h)) j["position"] = {rounded(p->x), rounded(p->y), rounded(p->z)};
        out.push_back(std::move(j));
    }
    return out;
}

}  // namespace

std::string summaryJson(const sim::Scene& scene, const sim::ActionLibrary& lib, const SampledScene& sampled,
                        const ExportOptions& options, const SummaryFiles& files) {
    json j;
    j["format"] = kSummaryFormat;
    j["version"] = kSummaryVersion;
    j["name"] = options.name;
    if (!options.source.empty()) j["source"] = options.source;
    j["export_format"] = toString(options.format);
    j["units"] = "m";  // of this summary's positions; the exported file's are in file_units
    j["file_units"] = options.format == Format::Fbx ? "cm" : "m";
    j["up"] = "Y";
    j["duration"] = scene.duration;
    j["fps"] = sampled.fps;
    j["frames"] = sampled.frames;
    j["last_frame_time"] = sampled.time(sampled.frames - 1);
    j["files"] = files.files;
    j["earlier_files"] = files.earlier;
    json chars = json::array();
    for (std::size_t c = 0; c < scene.characters.size(); ++c) {
        chars.push_back(characterJson(scene.characters[c], sampled.characters[c], sampled, lib));
    }
    j["characters"] = std::move(chars);
    j["hits"] = hitsJson(scene, lib);
    json catches = json::array();
    for (const auto& c : scene.catches) {
        catches.push_back({{"time", c.time},
                           {"chaser", scene.characters[static_cast<std::size_t>(c.chaser)].name},
                           {"runaway", scene.characters[static_cast<std::size_t>(c.runaway)].name}});
    }
    j["catches"] = std::move(catches);
    return j.dump(1) + "\n";
}

Result<std::vector<std::string>> earlierExportFiles(const std::filesystem::path& summary) {
    std::error_code ec;
    if (!std::filesystem::exists(summary, ec)) return std::vector<std::string>{};
    const std::string refuse = summary.string() + ": exists and is not a Fray export summary; refusing to overwrite it";
    auto text = readWholeFile(summary, "the earlier export summary");
    if (!text) return makeError(refuse);
    const json j = json::parse(*text, nullptr, false);
    if (!j.is_object() || j.value("format", "") != kSummaryFormat) return makeError(refuse);
    std::vector<std::string> out;
    for (const char* key : {"files", "earlier_files"}) {
        const auto it = j.find(key);
        if (it == j.end() || !it->is_array()) continue;
        for (const auto& f : *it) {
            // Plain names in the folder only: a hand-edited summary cannot reach elsewhere.
            if (!f.is_string()) continue;
            const std::string name = f.get<std::string>();
            if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos) continue;
            out.push_back(name);
        }
    }
    return out;
}

}  // namespace fray::exporter
