#pragma once
// A planned or composed scene ready to draw: every character posed by the
// scene poser at a time, as renderer instances (only the characters already in
// the scene then), with its current action as the label. Shared by
// `fray-cli render` and `fray-play`.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/posture/posture.h"
#include "fray/render/camera.h"
#include "fray/render/frame.h"
#include "fray/sim/scene.h"
#include "fray/pipeline/sim_session.h"

namespace fray::cli {

// The colour character c of a scene is drawn in, and shown in beside its
// name in every character list: a creature's own colour, else its side's
// (render::sideColor), the shade by its place among its side's characters.
glm::vec3 characterTint(const sim::Scene& scene, int c);

class SceneStage {
public:
    explicit SceneStage(pipeline::LoadedScene scene);

    const sim::Scene& scene() const { return loaded_.scene; }
    const sim::ActionLibrary& library() const { return loaded_.session->library; }
    int characterCount() const { return static_cast<int>(loaded_.scene.characters.size()); }
    double duration() const { return loaded_.scene.duration; }
    const Skeleton& skeleton(int c) const { return poser_->skeleton(c); }
    // Every character's skeleton, in character order (for --rig).
    std::vector<const Skeleton*> skeletons() const;

    // The posture mode (docs/POSTURE.md): kinematic (the scene poser, the
    // default) or physics (the posture solver runs over the whole scene here,
    // once; poses are then read from its frames). Errors: cancelled.
    Status setPosture(posture::Mode mode, const ProgressFn& progress = {}, const posture::Options& options = {});
    // Installs poses made elsewhere: posture::ScenePoses::make(mode, scene(),
    // library(), options, progress) run in a worker thread (it takes seconds),
    // then this on the thread that calls pose().
    void setPosture(posture::ScenePoses poses) { physics_ = std::make_unique<posture::ScenePoses>(std::move(poses)); }
    posture::Mode postureMode() const { return physics_ ? physics_->mode() : posture::Mode::Kinematic; }
    // What the solver clamped or refused (nullptr in kinematic mode).
    const posture::Report* postureReport() const { return physics_ ? &physics_->report() : nullptr; }

    // Which characters get a "name: action" label: everyone, nobody, or
    // everyone in scenes of up to kAutoLabels characters (a crowd's labels
    // would hide it). The selected character is always labelled.
    enum class Labels { None, All, Auto };
    static constexpr int kAutoLabels = 16;
    // Poses everyone at t (s); the selected character (-1: none) is highlighted.
    void pose(double t, Labels labels = Labels::All, int selected = -1);
    // The characters in the scene at the last pose, in character order.
    std::span<const render::CharacterInstance> shown() const { return shown_; }
    // Scene character of shown()[i].
    int shownCharacter(std::size_t i) const { return shownIndex_[i]; }
    bool present(int c) const { return present_[static_cast<std::size_t>(c)] != 0; }
    // World joint positions of character c at the last pose (empty when absent).
    std::span<const glm::vec3> jointPositions(int c) const {
        return present(c) ? std::span<const glm::vec3>(positions_[static_cast<std::size_t>(c)]) : std::span<const glm::vec3>();
    }
    // The action character c plays at the last pose ("" when none).
    std::string currentAction(int c) const;
    // characterTint(scene(), c), kept for every character.
    glm::vec3 tint(int c) const { return tints_[static_cast<std::size_t>(c)]; }
    // Box around everyone present at a few times over [t0, t1].
    render::Bounds bounds(double t0, double t1, int samples = 24);

    // The scene's marks on the floor, fixed for the scene, for a
    // FrameDescription: each path-following character's path (a ribbon) and
    // checkpoints (in its tint), the stage it was planned on (a white
    // circle; see sim::Scene::arena) and a composed scene's floor marks (a
    // football goal line in white, the running arrows in amber).
    std::span<const render::Polyline> trajectories() const { return lines_; }
    std::span<const render::Checkpoint> checkpoints() const { return marks_; }
    // The painted floor area of a domino scene (a translucent red where
    // painted), for FrameDescription::floorBitmap; nullptr when the scene has none.
    const render::FloorBitmap* floorBitmap() const { return floorImage_.width > 0 ? &floorImage_ : nullptr; }
    // Box around the stage; empty when the scene has none.
    render::Bounds stageBounds() const;

private:
    pipeline::LoadedScene loaded_;
    std::unique_ptr<sim::ScenePoser> poser_;
    std::unique_ptr<posture::ScenePoses> physics_;  // physics mode only
    double time_ = 0;
    std::vector<Pose> poses_;
    std::vector<std::vector<glm::vec3>> positions_;
    std::vector<std::vector<glm::quat>> rotations_;
    std::vector<std::string> labels_;
    std::vector<std::uint8_t> present_;
    std::vector<glm::vec3> tints_;
    std::vector<render::CharacterInstance> shown_;
    std::vector<int> shownIndex_;
    std::vector<std::vector<glm::vec3>> linePoints_;  // lines_ point into these
    std::vector<render::Polyline> lines_;
    std::vector<render::Checkpoint> marks_;
    std::vector<std::uint8_t> floorPixels_;  // floorImage_ points into it
    render::FloorBitmap floorImage_;
};

}  // namespace fray::cli
