#pragma once
// Quality and outcome metrics of a scene (`fray-cli metrics`): per character
// the hits given and received, time to catch, distance to the opponent,
// path-following error, body penetration outside intended hits and foot
// skate, measured on the played-back scene (ScenePoser, transitions included).
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "fray/sim/action_library.h"
#include "fray/sim/scene.h"

namespace fray::sim {

struct CharacterMetrics {
    std::string name;
    int actions = 0;
    int hitsGiven = 0, hitsReceived = 0;        // successful (not blocked)
    int blockedGiven = 0, blockedReceived = 0;  // landed on a block
    double damageGiven = 0, damageReceived = 0; // sum of effector speeds (m/s)
    std::optional<double> timeToCatch;          // first catch it took part in (s)
    std::optional<double> meanOpponentDistance; // m, pelvis to pelvis
    std::optional<double> pathErrorMean, pathErrorMax;  // m, pelvis to its path polyline
    // Per timed checkpoint of its path, in order: when the pelvis first came
    // within kCheckpointReach of it at or after its time, after the previous
    // one was reached (-1: never). Empty without timed checkpoints.
    std::vector<double> checkpointsReached;
    static constexpr double kCheckpointReach = 0.6;  // m, the planner's checkpoint radius
    int penetrationFrames = 0;                  // samples with its body inside another's, outside intended hits
    double footSkateMean = 0, footSkateMax = 0; // cm per 60 Hz frame, feet in contact
    int forcedReactions = 0;
    std::int64_t fallbacks = 0;                 // decisions with no legal action (idle/guard taken)
};

struct SceneMetrics {
    double duration = 0;
    double sampleRate = 30;
    std::vector<CharacterMetrics> characters;
    int penetrationFrames = 0;       // samples where any two bodies penetrate outside intended hits
    int crossGroupPenetrations = 0;  // of which between characters of different groups
    struct Penetration {
        double time = 0;
        int a = 0, b = 0;
    };
    std::vector<Penetration> penetrations;  // the first kMaxListed samples, to find them
    static constexpr std::size_t kMaxListed = 100;
    int hits = 0, blocked = 0, attacks = 0;
    double hitRate = 0;              // successful hits / attacks launched
};

struct MetricsOptions {
    double sampleRate = 30;     // body tests
    double skateRate = 60;      // foot skate
    double hitWindow = 0.3;     // s around a hit where the two bodies may touch
};

SceneMetrics computeMetrics(const Scene& scene, const ActionLibrary& lib, const MetricsOptions& options = {});

// ---- Posture metrics (issue 25) ----------------------------------------------
// Measured on the world joint positions a viewer shows, frame by frame: the
// kinematic playback (ScenePoser) or the physics posture solver
// (fray::posture), so both modes are measured the same way.

// World joint positions of every character at a fixed frame rate.
struct JointTracks {
    double fps = 60;
    int frames = 0;  // frame f is at time f / fps
    // Per character: frames x jointCount positions, frame-major; empty for
    // creatures (rat, bag).
    std::vector<std::vector<glm::vec3>> joints;
    std::vector<int> jointCount;
    bool has(int c) const { return !joints[static_cast<std::size_t>(c)].empty(); }
    std::span<const glm::vec3> at(int c, int frame) const {
        const auto n = static_cast<std::size_t>(jointCount[static_cast<std::size_t>(c)]);
        return {joints[static_cast<std::size_t>(c)].data() + static_cast<std::size_t>(frame) * n, n};
    }
};
// The kinematic playback (today's poses) sampled at fps over [0, duration].
JointTracks kinematicTracks(const Scene& scene, const ActionLibrary& lib, double fps = 60);

// Depth (m) of the overlap of two oriented boxes along their axis of least
// overlap (the 15 separating axes); 0 when they are apart or touch.
double boxPenetration(const Obb& a, const Obb& b);
// Signed distance (m) between two oriented boxes: the gap when apart,
// minus the penetration depth when they overlap. `normal`, when given, gets
// the unit direction from a towards b (apart: along the gap; inside: the
// axis of least overlap), so moving a by normal * distance brings the two
// surfaces together.
double boxSignedDistance(const Obb& a, const Obb& b, glm::vec3* normal = nullptr);

struct PostureCharacterMetrics {
    std::string name;
    int contactFrames = 0;                          // frame pairs with the foot supported at both
    double footSkateMeanCm = 0, footSkateMaxCm = 0; // cm per frame, feet in contact (SPEC 1.3)
    double penetrationMaxCm = 0;                    // deepest segment overlap with another body outside intended contacts
    int boundaries = 0;                             // action boundaries measured
    double boundaryJumpMean = 0, boundaryJumpMax = 0;  // m/s: largest joint-velocity change across a boundary
    int deviationFrames = 0;                        // frames outside hits and reactions
    double deviationMeanCm = 0;                     // mean joint position error to the captured pose there
    double deviationAllMeanCm = 0;                  // the same over every frame it is present
};

// The striking segment against the victim's target segment at a hit.
struct HitContact {
    double time = 0;
    int attacker = 0, defender = 0, effector = 0, target = 0;
    bool blocked = false;
    // The striking limb (the effector segment and the limb segments next to
    // it: a kick's thigh may meet the body before its shin) against the
    // victim's surface (its nearest segment): > 0 the gap, < 0 the depth inside.
    double distanceCm = 0;
    double effectorDistanceCm = 0;  // the same for the effector segment alone
    int met = 0;                    // the victim's segment nearest to the effector
};

// A carried ball (the football carrier's) against its holder's hand.
struct BallHold {
    std::string ball, holder;
    int frames = 0;                    // frames the holder is in the scene
    // Its hand (in the pose shown) to the ball as keyed: where the hand holds
    // it (sim::ballGripAt). The ball shown is not measured against the hand:
    // with physics it is drawn on the hand (0 by construction), and in the
    // kinematic posture it is the ball as keyed.
    double keyedMeanCm = 0, keyedMaxCm = 0;
};

struct PostureMetrics {
    double fps = 60;
    std::vector<BallHold> balls;
    std::vector<PostureCharacterMetrics> characters;
    std::vector<HitContact> hits;
    // Scene-wide: the worst character and the frame-weighted means.
    double footSkateMaxCm = 0, footSkateMeanCm = 0;
    double penetrationMaxCm = 0;
    struct Worst {
        double time = 0;
        int a = -1, b = -1, segmentA = 0, segmentB = 0;
    } worstPenetration;  // where penetrationMaxCm was measured
    double deviationMeanCm = 0;
    double boundaryJumpMax = 0;
    int landed = 0;         // hits not blocked (a blocked blow meets the block, not the body)
    int hitsOnSurface = 0;  // of which the striker is within 2 cm of the surface and at most 3 cm inside
    double hitsOnSurfaceShare() const { return landed == 0 ? 1.0 : static_cast<double>(hitsOnSurface) / landed; }
};

// `shown`: the poses measured; `captured`: the kinematic playback at the same
// rate (the reference for the deviation; pass `shown` itself for the
// kinematic mode). Intended contacts: the two characters of a hit or catch
// within options.hitWindow of it, those of a body blow (pelvis, torso or head:
// a push, a bump, a fall onto someone) until the attacker's action at the
// blow ends (plus the window), and hand-overs (hand/receive actions). A body
// blow's striking limb is the whole body.
PostureMetrics computePostureMetrics(const Scene& scene, const ActionLibrary& lib, const JointTracks& shown,
                                     const JointTracks& captured, const MetricsOptions& options = {});
std::string postureMetricsToJson(const PostureMetrics& m);
std::string postureMetricsToText(const PostureMetrics& m);

std::string metricsToJson(const SceneMetrics& m);
std::string metricsToText(const SceneMetrics& m);

}  // namespace fray::sim
