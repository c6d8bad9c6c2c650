#pragma once
// The scene timeline every planner writes (SPEC 2, 3, 4): per character the
// sequence of actions with their start times and floor placements, the hits
// and catches, and a pose sampler that plays it back with transitions.
// Saved as versioned JSON ("fray-scene", version 1) that names actions by
// motion id and frame range, so it stays valid while the project's actions
// do, and says clearly when they changed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/geometric.hpp>

#include "fray/core/motion.h"
#include "fray/core/result.h"
#include "fray/sim/action_library.h"
#include "fray/sim/geometry.h"

namespace fray::sim {

// Version 2 adds looped instances (ActionInstance::loop); version 3 held
// bodies (SceneCharacter::held: a ball placed from its holder's pose when
// read, its keys over the hold not stored). A scene is written with the
// lowest version that holds it (one without either as version 1, byte for
// byte as before), and every version is read.
inline constexpr int kSceneVersion = 3;
inline constexpr int kSceneVersionLoops = 2;
inline constexpr int kSceneVersionNoLoops = 1;
// The most keys a scene file's held bodies may make when read (all of them
// together: the 1,430-run football crowd makes 702,160).
inline constexpr std::int64_t kMaxHeldKeys = 4'000'000;
// Limits of scene specs and scene files (docs/FILES.md): a scene lasts at
// most an hour; positions on the floor stay within 10 km of the origin.
inline constexpr double kMaxSceneSeconds = 3600.0;
inline constexpr double kMaxCoordinate = 1e4;

struct ActionInstance {
    int action = 0;       // library index
    double start = 0;     // scene time (s) the action starts
    double offset = 0;    // s into the clip where it starts (forced reactions start at the best-matching frame)
    double end = 0;       // scene time it ends (earlier than start + duration - offset when a hit cut it short)
    RootXf root;          // placement of the clip's first frame in the scene
    bool forced = false;  // a reaction to a hit: no choice was made
    bool fallback = false;  // the planner had no legal action and took an idle/guard one
    // > 0: a looped idle. The clip plays from `offset` for `loop` s, then
    // starts over from `offset` at the same root, and so on until `end`: one
    // instance for someone standing for minutes (repetition k starts at
    // start + k * loop). 0: the clip plays once.
    double loop = 0;
    bool looped() const { return loop > 0; }
    // Placement of the character at clip time tau (s).
    RootXf placementAt(const ActionLibrary& lib, double tau) const { return root * lib.rootAt(action, tau); }
    // How many times the clip starts: 1 unless looped.
    int repeats() const {
        if (!looped() || end <= start) return 1;
        return std::max(1, static_cast<int>(std::ceil((end - start) / loop - 1e-6)));
    }
    // Scene time repetition k (0 <= k < repeats()) starts.
    double repeatStart(int k) const { return looped() ? start + k * loop : start; }
    // The repetition playing at scene time t (clamped to [start, end]; at
    // `end` the one that ends there).
    int repeatAt(double t) const {
        if (!looped()) return 0;
        const int last = repeats() - 1;
        const double c = std::clamp(t, start, end);
        if (c >= end) return last;
        // The repetition whose start (as repeatStart computes it) is at or
        // before c and whose successor's is after it, whatever the rounding of the division.
        int k = std::clamp(static_cast<int>(std::floor((c - start) / loop)), 0, last);
        while (k < last && repeatStart(k + 1) <= c) ++k;
        while (k > 0 && repeatStart(k) > c) --k;
        return k;
    }
    // Clip time at scene time t, held at the instance's ends outside it.
    double clipTimeAt(double t) const {
        const double c = std::clamp(t, start, end);
        if (!looped()) return offset + (c - start);
        return offset + std::min(loop, c - repeatStart(repeatAt(c)));
    }
};

// Index of the instance playing at time t in a time-ordered track (the first
// before it starts, the last after it ends); -1 when the track is empty.
int instanceIndexAt(std::span<const ActionInstance> track, double t);

struct Checkpoint {
    glm::vec2 pos{0.0f};
    std::optional<double> time;  // not to be passed before this time (s)
    std::string action;          // "" or a required action ("@annotation" or a name) at this checkpoint
    friend bool operator==(const Checkpoint&, const Checkpoint&) = default;
};

// A stage: a disc on the floor that characters are kept on (SimOptions::
// arena); radius 0 is unbounded.
struct Arena {
    glm::vec2 centre{0.0f};  // (x, z)
    double radius = 0;       // m
    bool bounded() const { return radius > 0; }
    // Distance of a floor point from the centre (m).
    double distanceFrom(glm::vec2 p) const { return static_cast<double>(glm::length(p - centre)); }
    friend bool operator==(const Arena&, const Arena&) = default;
};

// A line on the floor for viewers, kept in the scene file: a football goal
// line, the user's running arrows.
struct FloorMark {
    std::string kind;               // what it marks ("goal", "arrow")
    std::vector<glm::vec2> points;  // (x, z) polyline, two points or more
    friend bool operator==(const FloorMark&, const FloorMark&) = default;
};

// A painted floor area (domino, SPEC 4.5), kept in the scene file for the
// viewers: pixel (x, y) covers the floor
// square [origin.x + x m, + m) x [origin.y + y m, + m), m = metresPerPixel;
// image rows run along +z.
struct FloorBitmap {
    int width = 0, height = 0;
    std::vector<std::uint8_t> painted;  // row-major, 1 where painted
    glm::vec2 origin{0.0f};
    double metresPerPixel = 0.1;
    bool empty() const { return width <= 0 || height <= 0; }
    bool paintedAt(glm::vec2 floor) const;
    // Is any painted pixel within r metres of q?
    bool paintedWithin(glm::vec2 q, double r) const;
    glm::vec2 extentMin() const { return origin; }
    glm::vec2 extentMax() const {
        return origin + glm::vec2(static_cast<float>(width * metresPerPixel), static_cast<float>(height * metresPerPixel));
    }
    friend bool operator==(const FloorBitmap&, const FloorBitmap&) = default;
};

struct HitEvent {
    double time = 0;
    int attacker = 0, defender = 0;  // character indices
    int attackAction = 0;            // library index of the attack
    int effector = 0;                // segment that landed
    int target = 0;                  // segment hit
    double speed = 0;                // m/s of the effector at contact: the damage
    double impulse = 0;              // N s (speed x effective limb mass)
    bool blocked = false;            // landed on a block defending that part: no damage
};

struct CatchEvent {
    double time = 0;
    int chaser = 0, runaway = 0;
};

struct PlannerStats {
    std::int64_t decisions = 0;   // real choices made
    std::int64_t nodes = 0;       // tree nodes expanded
    std::int64_t leaves = 0;
    std::int64_t choices = 0;     // candidate actions before pruning, over the real decisions (every variant)
    std::int64_t pruned = 0;      // of which pruned
    std::int64_t cutoffs = 0;     // alpha-beta cutoffs
    std::int64_t fallbacks = 0;   // decisions with no legal action (idle/guard taken)
    std::int64_t forced = 0;      // forced reactions in the real run
    std::int64_t shallower = 0;   // decisions made at a lower depth than asked (leaf budget)
    double seconds = 0;           // wall-clock planning time
    double prunedShare() const { return choices > 0 ? static_cast<double>(pruned) / static_cast<double>(choices) : 0.0; }
};

// A one-joint body's root placement at a time (SPEC 4.5: the rat is a
// character with one joint, moved along the user's trajectory, not by
// captured actions; the luggage chain's bag is carried in the porters' hands).
struct RootKey {
    double time = 0;
    RootXf at;
    float height = -1;  // m above the floor; < 0: the body's own (a rat runs on the floor)
    float pitch = 0;    // rad: the body's +Z axis raised above the floor this much (a ball along a forearm)
    friend bool operator==(const RootKey&, const RootKey&) = default;
};

struct SceneCharacter {
    std::string name;
    // "" for a person playing the project's actions; "rat", "bag" or "ball"
    // for a one-joint body whose root follows `keys` (its track stays empty).
    std::string body;
    std::vector<RootKey> keys;  // time-ordered
    // A carried body (the football carrier's ball): the character holding it
    // and which hand (0 left, 1 right); -1: nobody in particular.
    int holder = -1, hand = 1;
    // A held ball (scene version 3): over [heldFrom, heldTo] its keys are
    // its holder's (heldBallKeys), made by the composer and again by the
    // scene reader, so the file stores only the interval, not those keys.
    // heldTo < heldFrom: not held (every key as stored, as in older files).
    double heldFrom = 0, heldTo = -1;
    bool held() const { return holder >= 0 && heldTo >= heldFrom; }
    int side = 0, group = 0;
    std::string preset;
    int depth = 0;
    std::vector<ActionInstance> track;
    std::vector<Checkpoint> path;  // for metrics (path-following error)
    bool loopPath = false;
    int opponent = -1;             // explicit opponent, -1: nearest enemy of its group
    std::int64_t fallbacks = 0;
};

struct Scene {
    std::string project;     // project file, relative to the scene file when saved
    double duration = 0;
    std::uint64_t seed = 0;
    std::vector<SceneCharacter> characters;
    std::vector<HitEvent> hits;
    std::vector<CatchEvent> catches;
    PlannerStats stats;
    std::string spec;        // the scene spec it was made from (JSON text), for the record
    Arena arena;             // the stage it was planned on (SimOptions::arena), for viewers
    std::vector<FloorMark> marks;  // lines on the floor for viewers (composed scenes)
    FloorBitmap floor;             // the painted area a domino scene was composed on (empty: none)

    // The instance of character c playing at time t (the last one for t past the end); -1 when the track is empty.
    int instanceAt(int c, double t) const;
    // A person is in the scene from its first action's start on
    // (composed scenes bring newcomers in later). Creatures never count as
    // present bodies: they have no action, so planners and metrics skip them.
    bool present(int c, double t) const {
        const auto& track = characters[static_cast<std::size_t>(c)].track;
        return !track.empty() && t >= track.front().start - 1e-9;
    }
    bool isCreature(int c) const { return !characters[static_cast<std::size_t>(c)].body.empty(); }
};

// The one-joint skeleton of a body kind ("rat", "bag", "ball"): a root joint with an
// end site along +Z (a rat's nose), so the body mesh is one capsule; nullptr
// for a kind this build does not know.
const Skeleton* creatureSkeleton(std::string_view body);
inline constexpr float kRatLength = 0.24f;  // m, root to nose
inline constexpr float kRatHeight = 0.05f;  // m, root above the floor
inline constexpr float kBagLength = 0.45f;  // m, end to end of the luggage chain's bag (a holdall)
// The American football carrier's ball: 0.28 m tip to tip, 0.17 m across (a
// regulation ball), tucked at the carrying hand along its forearm, its
// middle kBallTuck behind the hand (the front tip in the palm, the back end
// against the forearm).
inline constexpr float kBallLength = 0.28f;
inline constexpr float kBallRadius = 0.085f;
inline constexpr float kBallTuck = 0.06f;
// The key of a ball tucked at `hand` (world) along the forearm from `elbow`:
// its root is the back tip, its +Z axis points from the elbow to the hand.
RootKey ballKey(double time, const glm::vec3& hand, const glm::vec3& elbow);
// Where the holding hand is on a ball placed by (at, height, pitch): the
// point of its axis kBallTuck beyond its middle.
glm::vec3 ballGrip(const RootXf& at, float height, float pitch);
// The world rotation of a one-joint body: heading about +Y, then pitch.
glm::quat creatureRotation(double heading, float pitch);
// A creature's placement at time t (held at its first and last keys), and
// the height of its root then.
RootXf creatureAt(const SceneCharacter& c, double t);
float creatureHeightAt(const SceneCharacter& c, double t);
float creaturePitchAt(const SceneCharacter& c, double t);
// Where its holder's hand holds a ball at time t: ballGrip of its keys
// interpolated at t (the posture solver's target and the metrics' ball).
glm::vec3 ballGripAt(const SceneCharacter& ball, double t);
// The keys of the ball `ball` held over [heldFrom, heldTo]: ballKey of its
// holder's hand and elbow (ScenePoser, the kinematic pose) every
// 1/kSampleRate s from heldFrom, the last at heldTo. Empty where the ball is
// not held, its holder is a creature or has no track, or its skeleton has no
// such arm.
std::vector<RootKey> heldBallKeys(const Scene& scene, const ActionLibrary& lib, int ball);
// The number of keys heldBallKeys makes for a hold of [from, to].
std::int64_t heldKeyCount(double from, double to);
// Gives every held ball its keys over the hold (heldBallKeys, the balls in
// parallel), keeping its keys before and after the hold.
void placeHeldBalls(Scene& scene, const ActionLibrary& lib);

std::string sceneToJson(const Scene& scene, const ActionLibrary& lib);
// Resolves actions against the library; errors name the file, JSON path and problem.
Result<Scene> sceneFromJson(std::string_view text, std::string_view fileName, const ActionLibrary& lib);
// Reads only the project path (to know what to load before parsing the rest).
Result<std::string> sceneProjectPath(std::string_view text, std::string_view fileName);
Status saveScene(const Scene& scene, const ActionLibrary& lib, const std::filesystem::path& file);

// Plays a scene back: the full local pose of a character at any time, with
// the motion's root placed in the scene and a short blend at every action
// boundary (offsets from the previous action's pose decaying to zero).
class ScenePoser {
public:
    ScenePoser(const Scene& scene, const ActionLibrary& lib, double blendSeconds = 0.15);
    const Skeleton& skeleton(int character) const;
    // Local pose (the skeleton's root joint in scene coordinates).
    void pose(int character, double t, Pose& out) const;
    // World joint positions of a character at time t.
    void worldPositions(int character, double t, std::vector<glm::vec3>& out) const;
    // Foot contact of the source clip at time t: [left, right] (creatures: none).
    std::array<bool, 2> contacts(int character, double t) const;

private:
    void rawPose(int character, int instance, double t, Pose& out) const;
    // The instance's pose at a clip time (s into its clip, held at its ends).
    void rawPoseAt(int character, int instance, double clipTime, Pose& out) const;
    const Scene& scene_;
    const ActionLibrary& lib_;
    double blend_;
};

}  // namespace fray::sim
