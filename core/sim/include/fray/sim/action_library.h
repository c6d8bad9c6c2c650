#pragma once
// The built, immutable form of a prepared project that every planner reads
// (tree expansion now; the Interaction Graph and patches later): per action
// its duration, how it moves the character on the floor, its body-segment
// boxes over time, what it attacks with, and Next() from the motion graph.
// Everything is relative to the action's own first-frame placement, so a
// planner puts an action anywhere by composing one RootXf.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fray/core/joint_guess.h"
#include "fray/core/motion.h"
#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/prep/motion_graph.h"
#include "fray/prep/pipeline.h"
#include "fray/prep/project.h"
#include "fray/prep/signals.h"
#include "fray/sim/geometry.h"

namespace fray::sim {

// Samples per second of the per-action tracks (roots, boxes, effector speed).
inline constexpr double kSampleRate = 30.0;

// Body segments, one oriented box each.
enum Segment : int {
    kPelvis, kTorso, kHead,
    kLeftUpperArm, kLeftForearm, kRightUpperArm, kRightForearm,
    kLeftThigh, kLeftShin, kLeftFoot, kRightThigh, kRightShin, kRightFoot,
    kSegmentCount
};
const char* segmentName(int segment);
// The far joint of a limb segment's box (the hand of a forearm, the ankle of
// a shin): its axis 0 runs from the near joint to the far one, padded.
glm::vec3 segmentTip(const Obb& box, int segment);
// Segments that count as "the body" for penetration (SPEC 2.4 criterion 1).
inline constexpr std::array<int, 5> kCoreSegments = {kPelvis, kTorso, kHead, kLeftThigh, kRightThigh};
// Segments an attack can land on.
inline constexpr std::array<int, 3> kTargetSegments = {kHead, kTorso, kPelvis};

// Action categories from the annotations (SPEC 1.4 vocabulary).
enum ActionFlag : std::uint32_t {
    kPunch = 1u << 0, kKick = 1u << 1, kBlock = 1u << 2, kAvoid = 1u << 3,  // avoid or dodge
    kPushed = 1u << 4, kFalling = 1u << 5, kStep = 1u << 6, kIdle = 1u << 7,
    kWalk = 1u << 8, kRun = 1u << 9, kTurn = 1u << 10, kTransition = 1u << 11, kTackle = 1u << 12,
    // Anything that lands on the other with an effector (a tackle's hands too).
    kAttack = kPunch | kKick | kTackle, kDefence = kBlock | kAvoid, kReactive = kPushed | kFalling,
};

struct LibraryAction {
    int motion = 0;                 // index in the loaded motions
    int firstFrame = 0, lastFrame = 0;
    std::string motionId;           // project motion id
    std::string name;               // action name ("" when unnamed)
    std::vector<std::string> annotations;
    std::uint32_t flags = 0;
    double duration = 0;            // s, frameCount / fps
    RootXf source;                  // placement (pelvis on the floor, heading) of its first frame in its motion
    RootXf end;                     // placement where the next action starts, relative to this one's start
    int sampleBegin = 0;            // first sample in ActionLibrary's tracks
    int sampleCount = 0;            // samples at kSampleRate covering [0, duration]
    int effector = -1;              // attacks: the segment that lands (forearm, shin, foot, thigh)
    double peakSpeed = 0;           // attacks: peak speed of the effector's far end (m/s)
    int activeBegin = 0, activeEnd = 0;  // attacks: samples [begin, end) where a hit can land
    double reach = 0;               // attacks: farthest the effector gets in front of the start pelvis (m)
    int defended = -1;              // blocks: the segment protected (head or torso); -1 none
    std::string label() const;      // name, or "motion:first-last" when unnamed
    bool is(std::uint32_t flag) const { return (flags & flag) != 0; }
    bool has(const std::string& annotation) const;
};

// Pose-matching data of one sample of a reactive action (forced reactions
// start at the best-matching frame of the best-matching clip).
struct ReactionEntry {
    int action = 0;
    int sample = 0;  // sample index within the action
    prep::PoseFeature feature;
};

namespace detail {
class ReactionMemo;
class InteractionEngine;
}  // namespace detail

// Built once by buildActionLibrary and immutable afterwards: every planner
// reads it through these accessors. It shares ownership of the motions it was
// built from, so it stays complete and valid however long it is kept.
class ActionLibrary {
public:
    int size() const { return static_cast<int>(actions_.size()); }
    const LibraryAction& action(int a) const { return actions_[static_cast<std::size_t>(a)]; }
    const std::vector<LibraryAction>& actions() const { return actions_; }
    // Next() of each action in the motion graph, ascending.
    const std::vector<std::vector<int>>& next() const { return next_; }
    const std::vector<std::uint8_t>& inLargestScc() const { return inLargestScc_; }
    // Motion-graph nodes each action starts and ends at.
    const std::vector<int>& startNode() const { return startNode_; }
    const std::vector<int>& endNode() const { return endNode_; }
    // Variant class: actions with the same name (else the same annotations)
    // and the same end node are variants of one choice.
    const std::vector<int>& variantClass() const { return variantClass_; }
    // Per sample (actions()[a].sampleBegin + s): the effector's speed, m/s (attacks; 0 otherwise).
    const std::vector<float>& effectorSpeed() const { return effectorSpeed_; }
    // Reactive clips, first part, every 2nd sample, and their features packed for matching (same order).
    const std::vector<ReactionEntry>& reactions() const { return reactions_; }
    const prep::PoseMatcher& reactionPoses() const { return reactionPoses_; }
    // The source motions (with joints and contacts), shared with whoever built the library.
    int motionCount() const { return static_cast<int>(motions_.size()); }
    const prep::LoadedMotion& motion(int m) const { return *motions_[static_cast<std::size_t>(m)]; }
    const std::vector<std::string>& vocabulary() const { return vocabulary_; }

    // Body-segment boxes (kSegmentCount, in the action's frame) at a sample of an action.
    const Obb* boxesAt(int action, int sample) const {
        return &boxes_[static_cast<std::size_t>(actions_[static_cast<std::size_t>(action)].sampleBegin + sample) * kSegmentCount];
    }
    // Sample index for a time (s) into the action, clamped.
    int sampleAt(int action, double t) const;
    // Pelvis placement at time t (s) into the action, interpolated, relative to its start.
    RootXf rootAt(int action, double t) const;
    // Source frame at time t into the action.
    int frameAt(int action, double t) const;
    // Can action `to` (or its variant starting where it starts) follow `from`?
    // The same motion-graph node, or Next(from) holds such a variant (the
    // capture's own continuation, which clustering may have put elsewhere).
    bool continuesInto(int from, int to) const;
    // Finds actions by "@annotation" or name; empty when nothing matches.
    std::vector<int> select(const std::string& key) const;

    // A catalogue of actions only (names, annotations, flags; no tracks,
    // graph or motions): enough to read scene specs and scene files against,
    // as the fuzzers do. Nothing can be planned or posed with it.
    static ActionLibrary catalogue(std::vector<LibraryAction> actions, std::vector<std::string> vocabulary);

private:
    friend Result<ActionLibrary> buildActionLibrary(const prep::Project&, std::vector<std::shared_ptr<const prep::LoadedMotion>>,
                                                    const prep::MotionGraph&, const ProgressFn&);
    std::vector<LibraryAction> actions_;
    std::vector<std::vector<int>> next_;
    std::vector<std::uint8_t> inLargestScc_;
    std::vector<int> startNode_, endNode_;
    std::vector<int> variantClass_;
    // Tracks, sample-major: sample s of action a is index actions_[a].sampleBegin + s.
    std::vector<RootXf> roots_;  // pelvis placement relative to the action's start
    std::vector<Obb> boxes_;     // kSegmentCount per sample, action frame
    std::vector<float> effectorSpeed_;
    std::vector<ReactionEntry> reactions_;
    prep::PoseMatcher reactionPoses_;
    std::vector<std::shared_ptr<const prep::LoadedMotion>> motions_;
    std::vector<std::string> vocabulary_;
    // The forced-reaction choices made over this library so far, by value
    // (fray_sim's interaction engine; a choice is a function of the library
    // and its key, so remembering it changes no result). Copies share it.
    friend class detail::InteractionEngine;
    std::shared_ptr<detail::ReactionMemo> reactionMemo_;
};

// Builds the library from a prepared project: its motions (with contacts),
// and the motion graph over the project's actions in project order.
// The library shares the motions; the second form copies them.
Result<ActionLibrary> buildActionLibrary(const prep::Project& project, std::vector<std::shared_ptr<const prep::LoadedMotion>> motions,
                                         const prep::MotionGraph& graph, const ProgressFn& progress = {});
Result<ActionLibrary> buildActionLibrary(const prep::Project& project, std::span<const prep::LoadedMotion> motions,
                                         const prep::MotionGraph& graph, const ProgressFn& progress = {});

// Actions of a project in graph order (motion by motion, action by action),
// as prep::buildMotionGraph takes them.
std::vector<prep::ActionRef> projectActionRefs(const prep::Project& project);

}  // namespace fray::sim
