#pragma once
// Run-time posture synthesis (SPEC 5, thesis appendix A): the displayed poses
// of a planned scene made by a physics particle system on ODE. Each joint of a
// character is a particle carried by a rigid segment (box geometry), segments
// are linked by ball joints, gravity pulls and an infinite floor plane holds
// the rag dolls. PD forces and torques (capped) pull every particle to the
// captured pose (soft constraints, adjusted so blows meet the victim's body
// and catching hands reach the runaway); supported feet are pinned where they
// land (hard constraints); segments of different characters collide.
//
// Deterministic: a fixed step, characters that may touch simulated together
// in one world in index order (an island), islands run in parallel (TBB) and
// write only their own characters: the same scene gives the same bytes on
// any number of threads.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "fray/core/motion.h"
#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/sim/action_library.h"
#include "fray/sim/metrics.h"
#include "fray/sim/scene.h"
#include "fray/sim/segment_boxes.h"

namespace fray::posture {

// How the displayed poses are made: today's playback, or the solver.
enum class Mode { Kinematic, Physics };
std::optional<Mode> parseMode(std::string_view name);  // "kinematic" | "physics"
const char* modeName(Mode mode);

// A foot pin asked for by the user over a time span: kept only where the
// scene's contacts say the foot is supported (else refused and reported).
struct FootPin {
    int character = 0;
    int foot = 0;  // 0 left, 1 right
    double from = 0, to = 0;
};

// How ODE solves each step's constraints (ball joints, pins, contacts).
enum class Solver {
    Direct,     // dWorldStep: an exact solve (LDLT factorisation / LCP) per group of linked bodies; a
                // character of 20 bodies in a tree is small enough that this costs less than
                // QuickStep's 40 sweeps (1.8x the frames per CPU-second), and the joints and pins hold
                // exactly; but with the contact rules of the third pass the chase's bodies go 3.0 cm
                // into each other and the rat crowd's 2.03 cm (docs/POSTURE.md "Speed")
    Iterative,  // dWorldQuickStep: projected Gauss-Seidel, `iterations` sweeps (every scene meets
                // issue 25's thresholds with it)
    Hybrid,     // each step, the characters that have a contact with another character are solved
                // by QuickStep (as Iterative) and the others, alone with their joints and pins, by
                // the direct solver (as Direct): the default, every scene meets issue 25's thresholds
                // and 200 characters get 1.8x QuickStep's frames per CPU-second (docs/POSTURE.md "Speed")
};

struct Options {
    double fps = 60;             // frames produced per second of scene
    int substeps = 4;            // physics steps per frame (fixed step = 1 / (fps * substeps))
    Solver solver = Solver::Hybrid;
    int iterations = 40;         // Solver::Iterative: QuickStep iterations in steps with contacts between characters (strong PD
                                 // forces push bodies through contacts with fewer)
    int freeIterations = 40;     // and in steps without (25 lets pinned feet slip 1.2 cm in the luggage chain)
    bool calmPairs = true;       // Solver::Direct, Hybrid: a character with no contact with another character
                                 // (its grown boxes apart from everyone's) at the first substep of a pair takes
                                 // both substeps as one direct step (docs/POSTURE.md "Calm pairs")
    double frequency = 8;        // Hz: PD natural frequency of the particles (Ke = m w^2); the
                                 // captured velocity and acceleration are fed forward
    double dampingRatio = 1;     // Kd = 2 zeta m w
    double maxAcceleration = 1000;  // m/s^2: force cap per particle (|F| <= m a)
    double angularFrequency = 8;    // Hz: the twist-keeping torques
    double maxAngularAcceleration = 4000;  // rad/s^2: torque cap (|T| <= I a)
    double hitLead = 0.25, hitTail = 0.2;  // s: ease in before a hit, out after it
    double hitForce = 0.3;       // share of the striker's momentum pushed into the victim
    double catchLead = 0.4;      // s: hands reach out before a catch
    double catchReach = 0.7;     // m: farthest a catching hand is pulled
    bool parry = true;           // a defender's free forearm moves towards an unblocked incoming blow
    double parryShare = 0.35;    // share of the way from the hand to the striking segment
    double parryReach = 0.25;    // m: the farthest a parrying hand is pulled
    bool collisions = true;      // segments of different characters collide
    bool footPins = true;        // pin supported feet
    bool handPins = false;       // pin a porter's hands to the bag it holds (the luggage chain); off by default:
                                 // with it the porters' arms meet at hand-overs 8.9 cm deep (docs/POSTURE.md)
    bool hitTargets = true;      // pull blows onto the victim's surface
    std::vector<std::uint8_t> ragdoll;  // per character, 1: no control (falls as a rag doll); missing = controlled
    std::vector<FootPin> pins;   // extra pins from the user
    bool parallel = true;        // islands on TBB threads
    double islandReach = 2.5;    // m: characters whose pelvises come this close share a world
};

// What the solver clamped, refused or reset, for the user.
struct Report {
    int nonFiniteTargets = 0;   // joint targets that were NaN/inf (held at the last finite value)
    int refusedPins = 0;        // pins not set: foot not supported, too high, or incompatible
    int releasedPins = 0;       // pins let go because the pose moved the foot away
    std::int64_t cappedForces = 0;  // particle forces or torques at their cap (steps x particles)
    int resets = 0;             // characters put back on their targets after a non-finite state
    int initialOverlaps = 0;    // pairs of characters starting inside each other
    std::int64_t directSteps = 0;     // character-steps solved by the direct solver (Solver::Direct, Hybrid; a calm
                                      // pair's one step counts for its two substeps)
    std::int64_t iterativeSteps = 0;  // and by QuickStep (Solver::Iterative, Hybrid: characters touching another)
    std::int64_t calmSteps = 0;       // of the direct ones, pairs of substeps taken as one step (Options::calmPairs)
    std::vector<std::string> notes;  // one line each, the first kMaxNotes
    static constexpr std::size_t kMaxNotes = 50;
    void note(std::string line);
};

// The physics poses of a scene, frame by frame.
struct Frames {
    sim::JointTracks world;                      // world joint positions (also what metrics read)
    std::vector<std::vector<glm::quat>> rotations;  // per character: frames x joints world rotations
    // Per character: a held ball's root position and rotation per frame,
    // tucked at its holder's physics hand along the physics forearm (as the
    // composer keys it on the captured pose: sim::ballKey); empty for every
    // other character.
    std::vector<std::vector<glm::vec3>> ballPositions;
    std::vector<std::vector<glm::quat>> ballRotations;
    Report report;
    int islands = 0;
};

// Steps a scene one frame at a time (benchmarks, viewers); see simulate().
class Simulator {
public:
    Simulator(const sim::Scene& scene, const sim::ActionLibrary& lib, const Options& options);
    ~Simulator();
    Simulator(const Simulator&) = delete;
    Simulator& operator=(const Simulator&) = delete;
    // Advances to the next frame (the first call produces frame 0).
    void step();
    int frame() const;  // the last frame produced, -1 before the first step
    int frameCount() const;
    // The character's world joint positions and rotations at the last frame
    // (the captured pose while it is not in the scene yet; empty for creatures).
    std::span<const glm::vec3> positions(int character) const;
    std::span<const glm::quat> rotations(int character) const;
    const Report& report() const;
    int islands() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Checks the scene and options (errors name the field) and runs the whole
// scene. Same input, same bytes. Progress is reported every few frames
// (stage "posture"); a false return stops it with fray::cancelled().
Result<Frames> simulate(const sim::Scene& scene, const sim::ActionLibrary& lib, const Options& options = {},
                        const ProgressFn& progress = {});

// The displayed joint positions in either mode at options.fps.
Result<sim::JointTracks> tracks(Mode mode, const sim::Scene& scene, const sim::ActionLibrary& lib, const Options& options = {});

// The displayed poses of a scene at any time, in either mode: what
// renderers, exporters and viewers draw. Kinematic: the scene poser's.
// Physics: the whole scene simulated once at options.fps when made, then
// joint positions interpolated linearly and rotations spherically between
// the two frames around t (times outside the scene are clamped to it).
// Creatures (a rat, a bag) are always the scene poser's, except a held ball
// in physics mode: it follows its holder's physics hand (Frames::ballPositions). Keeps references
// to the scene and the library, which must outlive it. Thread-safe to read.
class ScenePoses {
public:
    // Errors: bad options (naming the field), or cancelled through progress.
    static Result<ScenePoses> make(Mode mode, const sim::Scene& scene, const sim::ActionLibrary& lib,
                                   const Options& options = {}, const ProgressFn& progress = {});
    ScenePoses(ScenePoses&&) noexcept;
    ScenePoses& operator=(ScenePoses&&) noexcept;
    ~ScenePoses();

    Mode mode() const;
    const Skeleton& skeleton(int character) const;
    // World joint positions and rotations of a character at t (s).
    void world(int character, double t, std::vector<glm::vec3>& positions, std::vector<glm::quat>& rotations) const;
    // The local pose (root in scene coordinates) of a character at t.
    void pose(int character, double t, Pose& out) const;
    // What the solver clamped or refused (empty in kinematic mode).
    const Report& report() const;

private:
    struct Impl;
    explicit ScenePoses(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// The local pose (root joint in scene coordinates) of a skeleton from its
// world joint positions and rotations, for exporters and renderers.
void localPose(const Skeleton& skeleton, std::span<const glm::vec3> world, std::span<const glm::quat> worldRotations,
               Pose& out);

}  // namespace fray::posture
