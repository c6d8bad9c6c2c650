#include "fray/demo/ground_truth.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

namespace fray::demo {

using Json = nlohmann::ordered_json;

bool TruthAction::has(std::string_view annotation) const {
    return std::any_of(annotations.begin(), annotations.end(), [&](const std::string& a) { return a == annotation; });
}

const std::vector<std::string>& annotationVocabulary() {
    static const std::vector<std::string> v = {"punch", "kick",  "avoid", "dodge",   "block", "step",
                                               "transition", "falling", "pushed", "run", "jump", "tackle",
                                               "carry", "walk", "hand", "receive", "turn", "idle"};
    return v;
}

namespace {

double round4(double x) { return std::round(x * 1e4) / 1e4; }

Json optionalString(const std::optional<std::string>& s) { return s ? Json(*s) : Json(nullptr); }

}  // namespace

std::string toJson(const GroundTruth& t) {
    Json j;
    j["format"] = "fray-demo-truth";
    j["version"] = 1;
    j["take"] = t.take;
    j["motion"] = t.motionFile;
    j["kind"] = t.kind;
    j["style"] = t.style;
    j["seed"] = t.seed;
    j["fps"] = t.fps;
    j["frame_count"] = t.frameCount;
    j["axes"] = "metres, Y up; heading frame: x left, y up, z forward";
    Json actions = Json::array();
    for (const TruthAction& a : t.actions) {
        Json o;
        o["name"] = a.name;
        o["first_frame"] = a.firstFrame;
        o["last_frame"] = a.lastFrame;
        o["style"] = a.style;
        o["annotations"] = a.annotations;
        o["joints"] = a.joints;
        o["attack_direction"] = optionalString(a.attackDirection);
        if (a.attackVector) {
            const auto& v = *a.attackVector;
            o["attack_vector"] = Json::array({round4(v[0]), round4(v[1]), round4(v[2])});
        } else {
            o["attack_vector"] = nullptr;
        }
        o["peak_speed"] = a.peakSpeed ? Json(round4(*a.peakSpeed)) : Json(nullptr);
        o["target_part"] = optionalString(a.targetPart);
        o["defended_part"] = optionalString(a.defendedPart);
        actions.push_back(std::move(o));
    }
    j["actions"] = std::move(actions);
    // Per-frame arrays are long: keep each on one line.
    j["foot_contact"] = {{"left", "@LEFT@"}, {"right", "@RIGHT@"}};
    std::string text = j.dump(2);
    auto line = [](const std::vector<std::uint8_t>& v) {
        std::string s = "[";
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (i) s += ',';
            s += v[i] ? '1' : '0';
        }
        return s + "]";
    };
    for (const auto& [tag, values] : {std::pair{"\"@LEFT@\"", &t.leftContact}, std::pair{"\"@RIGHT@\"", &t.rightContact}}) {
        const auto pos = text.find(tag);
        if (pos != std::string::npos) text.replace(pos, std::string(tag).size(), line(*values));
    }
    return text + "\n";
}

Result<GroundTruth> groundTruthFromJson(std::string_view text, std::string_view name) {
    const Json j = Json::parse(text.begin(), text.end(), nullptr, false);
    if (j.is_discarded()) return makeError(std::string(name) + ": not valid JSON");
    auto err = [&](const std::string& m) { return makeError(std::string(name) + ": " + m); };
    if (!j.is_object() || j.value("format", "") != "fray-demo-truth") return err("not a fray demo ground-truth file");
    if (j.value("version", 0) != 1) return err("unsupported version " + std::to_string(j.value("version", 0)));
    try {
        GroundTruth t;
        t.take = j.at("take").get<std::string>();
        t.motionFile = j.at("motion").get<std::string>();
        t.kind = j.at("kind").get<std::string>();
        t.style = j.at("style").get<std::string>();
        t.seed = j.at("seed").get<std::uint64_t>();
        t.fps = j.at("fps").get<double>();
        t.frameCount = j.at("frame_count").get<int>();
        for (const auto& o : j.at("actions")) {
            TruthAction a;
            a.name = o.at("name").get<std::string>();
            a.firstFrame = o.at("first_frame").get<int>();
            a.lastFrame = o.at("last_frame").get<int>();
            a.style = o.at("style").get<std::string>();
            a.annotations = o.at("annotations").get<std::vector<std::string>>();
            a.joints = o.at("joints").get<std::vector<std::string>>();
            if (!o.at("attack_direction").is_null()) a.attackDirection = o.at("attack_direction").get<std::string>();
            if (!o.at("attack_vector").is_null()) a.attackVector = o.at("attack_vector").get<std::array<double, 3>>();
            if (!o.at("peak_speed").is_null()) a.peakSpeed = o.at("peak_speed").get<double>();
            if (!o.at("target_part").is_null()) a.targetPart = o.at("target_part").get<std::string>();
            if (!o.at("defended_part").is_null()) a.defendedPart = o.at("defended_part").get<std::string>();
            t.actions.push_back(std::move(a));
        }
        t.leftContact = j.at("foot_contact").at("left").get<std::vector<std::uint8_t>>();
        t.rightContact = j.at("foot_contact").at("right").get<std::vector<std::uint8_t>>();
        if (auto bad = validate(t)) return err(*bad);
        return t;
    } catch (const nlohmann::json::exception& e) {
        return err(std::string("bad field: ") + e.what());
    }
}

std::optional<std::string> validate(const GroundTruth& t) {
    if (t.frameCount <= 0) return "no frames";
    if (!(t.fps > 0)) return "fps must be positive";
    if (t.leftContact.size() != static_cast<std::size_t>(t.frameCount) ||
        t.rightContact.size() != static_cast<std::size_t>(t.frameCount))
        return "foot contact arrays must have frame_count entries";
    for (auto v : t.leftContact)
        if (v > 1) return "foot contact values must be 0 or 1";
    for (auto v : t.rightContact)
        if (v > 1) return "foot contact values must be 0 or 1";
    int next = 0;
    const auto& vocab = annotationVocabulary();
    for (const TruthAction& a : t.actions) {
        const std::string where = "action '" + a.name + "' at frame " + std::to_string(a.firstFrame);
        if (a.firstFrame != next) return where + ": actions must be contiguous (expected first frame " + std::to_string(next) + ")";
        if (a.lastFrame < a.firstFrame) return where + ": last frame before first frame";
        if (a.annotations.empty()) return where + ": no annotation";
        for (const auto& an : a.annotations)
            if (std::find(vocab.begin(), vocab.end(), an) == vocab.end()) return where + ": unknown annotation '" + an + "'";
        next = a.lastFrame + 1;
    }
    if (next != t.frameCount) return "actions cover " + std::to_string(next) + " of " + std::to_string(t.frameCount) + " frames";
    return std::nullopt;
}

}  // namespace fray::demo
