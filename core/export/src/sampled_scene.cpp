#include "sampled_scene.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "fray/export/export.h"

namespace fray::exporter {
namespace {

std::string sanitize(const std::string& name, std::size_t index) {
    std::string out = fileSafeName(name);
    // A leading dot would hide the file.
    if (out.empty() || out.front() == '.') out = "character" + std::to_string(index) + out;
    return out;
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const glm::quat& q) { return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w); }

// Fills every frame of `out`; fails at the first pose that is not finite
// (written as it is, it would make invalid files in every format).
Status sampleCharacter(const sim::ScenePoser& poser, const PoseFn& poses, int c, const SampledScene& s, Motion& out) {
    Pose pose;
    for (int f = 0; f < out.frameCount(); ++f) {
        if (poses) {
            poses(c, s.time(f), pose);
        } else {
            poser.pose(c, s.time(f), pose);
        }
        if (pose.translations.size() != out.translations(f).size() || pose.rotations.size() != pose.translations.size()) {
            return makeError("the pose at " + std::to_string(s.time(f)) + " s has " + std::to_string(pose.translations.size()) +
                             " joints, the skeleton " + std::to_string(out.translations(f).size()));
        }
        auto t = out.translations(f);
        auto r = out.rotations(f);
        for (std::size_t j = 0; j < t.size(); ++j) {
            t[j] = pose.translations[j];
            glm::quat q = glm::normalize(pose.rotations[j]);
            if (f > 0 && glm::dot(q, out.rotations(f - 1)[j]) < 0.0f) q = -q;
            r[j] = q;
            if (!finite(t[j]) || !finite(q)) {
                return makeError("the pose of joint " + out.skeleton().names[j] + " at " + std::to_string(s.time(f)) +
                                 " s is not finite");
            }
        }
    }
    return {};
}

}  // namespace

std::vector<std::string> fileSafeNames(const sim::Scene& scene) {
    std::vector<std::string> names;
    for (std::size_t i = 0; i < scene.characters.size(); ++i) {
        std::string name = sanitize(scene.characters[i].name, i);
        if (std::find(names.begin(), names.end(), name) != names.end()) name += "_" + std::to_string(i);
        names.push_back(std::move(name));
    }
    return names;
}

bool isFileSafe(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.';
}

std::string fileSafeName(std::string_view name) {
    std::string out(name);
    for (char& c : out)
        if (!isFileSafe(c)) c = '_';
    return out;
}

double SampledScene::time(int f) const {
    const double grid = f / fps;
    const bool last = f > 0 && f + 1 == frames;
    return last && duration > (f - 1) / fps && duration < grid ? duration : grid;
}

int exportFrameCount(double duration, double fps) {
    if (!(duration > 0) || !(fps > 0)) return 2;
    // Enough grid steps to reach the duration; a grid time short of it by less
    // than a thousandth of a frame counts as reaching it (so the last two
    // times, stored as floats in glTF, stay apart).
    return std::max(2, static_cast<int>(std::ceil(duration * fps - 1e-3)) + 1);
}

Result<SampledScene> sampleScene(const sim::Scene& scene, const sim::ActionLibrary& lib, double fps,
                                 const ProgressFn& progress, const PoseFn& poses) {
    if (scene.characters.empty()) return makeError("the scene has no characters: nothing to export");
    for (const auto& c : scene.characters) {
        if (c.track.empty() && c.body.empty()) return makeError("character '" + c.name + "' has no action: nothing to export");
    }
    SampledScene out;
    out.fps = fps;
    out.frames = exportFrameCount(scene.duration, fps);
    out.duration = scene.duration;
    const sim::ScenePoser poser(scene, lib);
    const auto names = fileSafeNames(scene);
    const int n = static_cast<int>(scene.characters.size());
    for (int c = 0; c < n; ++c) {
        if (!reportProgress(progress, static_cast<double>(c) / n, "export: sampling")) return cancelled();
        const auto& sc = scene.characters[static_cast<std::size_t>(c)];
        CharacterTake take{sc.name, names[static_cast<std::size_t>(c)], sc.side, sc.group,
                           Motion(poser.skeleton(c), fps, out.frames), nullptr};
        if (auto st = sampleCharacter(poser, poses, c, out, take.motion); !st) {
            return makeError("character '" + sc.name + "': " + st.error().message);
        }
        out.characters.push_back(std::move(take));
    }
    return out;
}

}  // namespace fray::exporter
