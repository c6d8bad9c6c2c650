#pragma once
// A stage of actors playing motions: poses them at a time (sampling + forward
// kinematics into reused buffers) and hands the renderer CharacterInstances.
// The CLI, fray-play and fray use it for motion files; a scene timeline can
// fill CharacterInstances itself the same way.
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "fray/core/motion.h"
#include "fray/render/camera.h"
#include "fray/render/frame.h"

namespace fray::render {

// A named frame range of an actor's motion (an action), shown as its label.
struct ActionSpan {
    int firstFrame = 0;  // inclusive
    int lastFrame = 0;   // inclusive
    std::string name;
};

struct StageActor {
    const Motion* motion = nullptr;  // not owned; must outlive the stage's use of it
    std::string name;                // take or character name
    glm::vec3 offset{0.0f};          // added to every joint (placing takes side by side)
    glm::vec3 tint{0.75f, 0.75f, 0.75f};
    std::vector<ActionSpan> actions;  // label by frame; empty: the label is the name
    int firstFrame = 0;              // the actor's time 0 is this frame of its motion
    int lastFrame = -1;              // last frame played; -1: the motion's last frame
    bool selected = false;
};

class MotionStage {
public:
    void clear();
    int add(StageActor actor);  // index of the new actor
    std::vector<StageActor>& actors() { return actors_; }
    const std::vector<StageActor>& actors() const { return actors_; }

    // Poses every actor at time t seconds from its first frame: clamped at its
    // last frame, or wrapped when loop is set.
    void pose(double t, bool loop = false);
    // Poses every actor at frame firstFrame + offset (clamped to its range).
    void poseFrame(int offset);

    std::span<const CharacterInstance> instances() const { return instances_; }
    int frameOf(int actor) const;               // motion frame last posed
    std::string_view actionOf(int actor) const;  // action at that frame ("" when none)
    double duration() const;                    // longest actor, seconds
    int longestFrameCount() const;              // frames of the longest actor's range
    Bounds bounds() const;                      // joints as last posed

private:
    void poseActor(std::size_t i, double localTime, bool exactFrame, int frame);

    struct Posed {
        Pose local;
        std::vector<glm::vec3> positions;
        std::vector<glm::quat> rotations;
        int frame = 0;
    };
    std::vector<StageActor> actors_;
    std::vector<Posed> posed_;
    std::vector<CharacterInstance> instances_;
};

// Pelvis (or root) path on the floor over frames [first, last] every step frames.
std::vector<glm::vec3> floorTrail(const Motion& motion, int first, int last, int step, glm::vec3 offset = glm::vec3(0.0f));

// A colour per team / character index, distinct for the first eight.
glm::vec3 teamColor(int index);

// A scene character's colour by its side: side 0 in reds, side 1 in blues
// (a setup's "red" and "blue" boxers), side 2 greens, side 3 ambers, then
// teamColor; `member` (its place among the characters of its side) picks
// one of three shades, the first the side's plain colour. The viewports, the
// character lists' swatches and fray-play all take a character's tint from here.
glm::vec3 sideColor(int side, int member);

}  // namespace fray::render
