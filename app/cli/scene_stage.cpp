#include "scene_stage.h"

#include <cmath>
#include <numbers>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "fray/core/kinematics.h"
#include "fray/render/motion_stage.h"

namespace fray::cli {

SceneStage::SceneStage(pipeline::LoadedScene scene) : loaded_(std::move(scene)) {
    poser_ = std::make_unique<sim::ScenePoser>(loaded_.scene, loaded_.session->library);
    const auto n = loaded_.scene.characters.size();
    poses_.resize(n);
    positions_.resize(n);
    rotations_.resize(n);
    labels_.resize(n);
    present_.assign(n, 0);
    shown_.reserve(n);
    shownIndex_.reserve(n);
    // Every character's colour, once (its shade counts the characters of its side before it).
    tints_.resize(n);
    for (std::size_t c = 0; c < n; ++c) tints_[c] = characterTint(loaded_.scene, static_cast<int>(c));

    const sim::Scene& sc = loaded_.scene;
    for (std::size_t c = 0; c < n; ++c) {
        const auto& ch = sc.characters[c];
        if (ch.path.empty()) continue;
        std::vector<glm::vec3> pts;
        for (const auto& cp : ch.path) pts.emplace_back(cp.pos.x, 0.0f, cp.pos.y);
        if (ch.loopPath) pts.push_back(pts.front());
        linePoints_.push_back(std::move(pts));
        const glm::vec3 col = tint(static_cast<int>(c));
        for (const auto& cp : ch.path) marks_.push_back({glm::vec3(cp.pos.x, 0.0f, cp.pos.y), glm::vec4(col, 1.0f), 0.25f, {}});
    }
    const std::size_t paths = linePoints_.size();
    if (sc.arena.bounded()) {
        constexpr int kSegments = 96;
        const glm::vec2 c = sc.arena.centre;
        const auto r = static_cast<float>(sc.arena.radius);
        std::vector<glm::vec3> circle;
        for (int k = 0; k <= kSegments; ++k) {
            const float a = 2.0f * std::numbers::pi_v<float> * static_cast<float>(k) / kSegments;
            circle.emplace_back(c.x + r * std::cos(a), 0.0f, c.y + r * std::sin(a));
        }
        linePoints_.push_back(std::move(circle));
    }
    const std::size_t staged = linePoints_.size();
    // Composed scenes' floor marks: a goal line in white, arrows in amber, a rat's trail in red.
    std::vector<render::Polyline> markStyles;
    for (const auto& m : sc.marks) {
        std::vector<glm::vec3> pts;
        for (const auto& p : m.points) pts.emplace_back(p.x, 0.0f, p.y);
        linePoints_.push_back(std::move(pts));
        markStyles.push_back(m.kind == "arrow"   ? render::Polyline{{}, glm::vec4(1.0f, 0.62f, 0.1f, 0.9f), 0.10f}
                             : m.kind == "trail" ? render::Polyline{{}, glm::vec4(0.85f, 0.25f, 0.2f, 0.7f), 0.05f}
                                                 : render::Polyline{{}, glm::vec4(0.97f, 0.97f, 0.97f, 0.9f), 0.12f});
    }
    if (const sim::FloorBitmap& f = sc.floor; !f.empty()) {
        floorPixels_.assign(f.painted.size() * 4, 0);
        for (std::size_t i = 0; i < f.painted.size(); ++i) {
            if (!f.painted[i]) continue;  // unpainted: transparent
            std::uint8_t* px = &floorPixels_[i * 4];
            px[0] = 205, px[1] = 72, px[2] = 52, px[3] = 150;
        }
        floorImage_.rgba = floorPixels_.data();
        floorImage_.width = f.width;
        floorImage_.height = f.height;
        floorImage_.min = f.extentMin();
        floorImage_.max = f.extentMax();
    }
    // Spans into linePoints_, which no longer changes.
    for (std::size_t i = 0; i < linePoints_.size(); ++i) {
        render::Polyline line = i < paths    ? render::Polyline{{}, glm::vec4(1.0f, 0.8f, 0.2f, 0.8f), 0.04f}
                                : i < staged ? render::Polyline{{}, glm::vec4(0.95f, 0.95f, 0.95f, 0.85f), 0.08f}
                                             : markStyles[i - staged];
        line.points = linePoints_[i];
        lines_.push_back(line);
    }
}

Status SceneStage::setPosture(posture::Mode mode, const ProgressFn& progress, const posture::Options& options) {
    if (mode == posture::Mode::Kinematic) {
        physics_.reset();
        return {};
    }
    auto poses = posture::ScenePoses::make(mode, loaded_.scene, loaded_.session->library, options, progress);
    if (!poses) return poses.error();
    physics_ = std::make_unique<posture::ScenePoses>(std::move(*poses));
    return {};
}

render::Bounds SceneStage::stageBounds() const {
    render::Bounds b;
    const sim::Arena& a = loaded_.scene.arena;
    if (a.bounded()) {
        const auto r = static_cast<float>(a.radius);
        b.add(glm::vec3(a.centre.x - r, 0.0f, a.centre.y - r));
        b.add(glm::vec3(a.centre.x + r, 0.0f, a.centre.y + r));
    }
    return b;
}

std::vector<const Skeleton*> SceneStage::skeletons() const {
    std::vector<const Skeleton*> out;
    for (int c = 0; c < characterCount(); ++c) out.push_back(&skeleton(c));
    return out;
}

glm::vec3 characterTint(const sim::Scene& scene, int c) {
    if (scene.isCreature(c)) {
        // A brown rat, a khaki bag and a leather-brown ball among the teams' colours.
        const std::string& body = scene.characters[static_cast<std::size_t>(c)].body;
        if (body == "ball") return glm::vec3(0.55f, 0.25f, 0.10f);
        return body == "rat" ? glm::vec3(0.35f, 0.27f, 0.22f) : glm::vec3(0.52f, 0.46f, 0.28f);
    }
    const int side = scene.characters[static_cast<std::size_t>(c)].side;
    int member = 0;
    for (int k = 0; k < c; ++k) member += !scene.isCreature(k) && scene.characters[static_cast<std::size_t>(k)].side == side ? 1 : 0;
    return render::sideColor(side, member);
}

std::string SceneStage::currentAction(int c) const {
    if (loaded_.scene.isCreature(c)) return loaded_.scene.characters[static_cast<std::size_t>(c)].body == "rat" ? "running" : "carried";
    const int i = loaded_.scene.instanceAt(c, time_);
    if (i < 0) return {};
    const auto& inst = loaded_.scene.characters[static_cast<std::size_t>(c)].track[static_cast<std::size_t>(i)];
    return library().action(inst.action).label() + (inst.forced ? " (hit)" : "");
}

void SceneStage::pose(double t, Labels labels, int selected) {
    time_ = t;
    shown_.clear();
    shownIndex_.clear();
    // Poses and forward kinematics in parallel over characters: each writes
    // only its own slots, so the result does not depend on the threads.
    tbb::parallel_for(tbb::blocked_range<int>(0, characterCount(), 32), [&](const tbb::blocked_range<int>& range) {
        for (int c = range.begin(); c != range.end(); ++c) {
            const auto k = static_cast<std::size_t>(c);
            present_[k] = loaded_.scene.present(c, t) || loaded_.scene.isCreature(c) ? 1 : 0;
            if (!present_[k]) continue;
            if (physics_) {
                physics_->world(c, t, positions_[k], rotations_[k]);  // const: safe from any thread
                continue;
            }
            poser_->pose(c, t, poses_[k]);
            positions_[k].resize(poses_[k].translations.size());
            rotations_[k].resize(poses_[k].translations.size());
            forwardKinematics(poser_->skeleton(c), poses_[k].translations, poses_[k].rotations, positions_[k], rotations_[k]);
        }
    });
    for (int c = 0; c < characterCount(); ++c) {
        const auto k = static_cast<std::size_t>(c);
        if (!present_[k]) continue;
        const Skeleton& sk = poser_->skeleton(c);
        const bool labelled = labels == Labels::All || (labels == Labels::Auto && characterCount() <= kAutoLabels) || c == selected;
        labels_[k] = labelled ? loaded_.scene.characters[k].name + ": " + currentAction(c) : std::string();
        shown_.push_back({&sk, positions_[k], rotations_[k], tint(c), labels_[k], c == selected});
        shownIndex_.push_back(c);
    }
}

render::Bounds SceneStage::bounds(double t0, double t1, int samples) {
    render::Bounds b;
    for (int k = 0; k <= samples; ++k) {
        pose(t0 + (t1 - t0) * k / samples, Labels::None);
        if (!shown_.empty()) b.add(render::characterBounds(shown_));
    }
    return b;
}

}  // namespace fray::cli
