#pragma once
// The interaction rules every planner plays by (tree expansion, patch
// generation, composition): when an attack lands on a defender and whether it
// is blocked, the impulse of a blow, and the forced reaction (clip and start
// frame) that best matches a victim's posture and the push (SPEC 2.1, 4.2).
// InteractionEngine holds all of their state; the body-overlap tests sit
// beside it. Internal to fray_sim.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "fray/sim/action_library.h"
#include "fray/sim/scene.h"

namespace fray::sim::detail {

// One action being played: which clip, when it started in scene time, how far
// into the clip it started, and where its first frame is placed.
struct Playing {
    int action = 0;
    double start = 0, offset = 0;
    RootXf root;
    double clipTime(double t) const { return offset + (t - start); }
    RootXf placement(const ActionLibrary& lib, double t) const { return root * lib.rootAt(action, clipTime(t)); }
    Obb box(const ActionLibrary& lib, double t, int segment) const {
        return lib.boxesAt(action, lib.sampleAt(action, clipTime(t)))[segment].placed(root);
    }

};

// A body in a clip at clip time tau, the clip's first frame placed at root.
struct BodyPose {
    int action = 0;
    double tau = 0;
    RootXf root;
};

// Do the core segments (SPEC 2.4: pelvis, torso, head, thighs) of two bodies
// overlap, boxes shrunk by `shrink` (grazing contact is not penetration)?
// Bodies whose pelvises are more than pelvisReach apart never do.
bool coreBodiesOverlap(const ActionLibrary& lib, const BodyPose& a, const BodyPose& b, float shrink, float pelvisReach = 1.2f);

// The same test in two halves, for callers that test one body against many:
// a body's pelvis on the floor and its core boxes placed and shrunk, the
// boxes only when asked (they cost ten times the pelvis).
class CoreBody {
public:
    CoreBody(const ActionLibrary& lib, const BodyPose& pose, float shrink)
        : CoreBody(lib, pose, FloorRotation(pose.root.heading), shrink) {}
    // With the rotation of pose.root already computed.
    CoreBody(const ActionLibrary& lib, const BodyPose& pose, const FloorRotation& rotate, float shrink)
        : CoreBody(lib, pose, rotate, lib.rootAt(pose.action, pose.tau).pos, shrink) {}
    // And with the pelvis in the clip's frame, lib.rootAt(pose.action, pose.tau).pos, already known.
    CoreBody(const ActionLibrary& lib, const BodyPose& pose, const FloorRotation& rotate, glm::vec2 clipPelvis,
             float shrink);
    glm::vec2 pelvis() const { return pelvis_; }
    const BodyPose& pose() const { return pose_; }
    const FloorRotation& rotation() const { return rotate_; }
    const std::array<Obb, kCoreSegments.size()>& boxes() const;
    // Their bounding-sphere radii (valid after boxes()).
    const std::array<float, kCoreSegments.size()>& radii() const { return radii_; }

private:
    const ActionLibrary* lib_;
    BodyPose pose_;
    FloorRotation rotate_;
    float shrink_;
    glm::vec2 pelvis_;
    // Empty until asked for (an empty optional costs no initialisation).
    mutable std::optional<std::array<Obb, kCoreSegments.size()>> boxes_;
    mutable std::array<float, kCoreSegments.size()> radii_;
};
bool coreBodiesOverlap(const CoreBody& a, const CoreBody& b, float pelvisReach);

// A floor disc round a body's core boxes, shrunk, at every sample of every
// clip (in the clip's frame), worked out once for a library: two bodies whose
// discs are apart fail every bounding-sphere test of coreBodiesOverlap, so
// the boxes of a pair that is near by the pelvis but apart by the discs need
// not be placed (a first test with the same answer; crowds stand within the
// pelvis reach of their neighbours).
class CoreDiscs {
public:
    struct Disc {
        glm::vec2 centre{0.0f};
        float radius = 0;
    };
    CoreDiscs(const ActionLibrary& lib, float shrink);
    // The disc of a body placed (its root's rotation given).
    Disc placed(const BodyPose& pose, const FloorRotation& rotate) const {
        const Disc& d = discs_[static_cast<std::size_t>(first_[static_cast<std::size_t>(pose.action)] + lib_->sampleAt(pose.action, pose.tau))];
        return {pose.root.pos + rotate(d.centre), d.radius};
    }
    Disc placed(const CoreBody& b) const { return placed(b.pose(), b.rotation()); }
    // Certainly apart: a margin covers the rounding of placing discs and boxes.
    static bool apart(const Disc& a, const Disc& b) {
        const glm::vec2 d = a.centre - b.centre;
        const float scale = std::fabs(a.centre.x) + std::fabs(a.centre.y) + std::fabs(b.centre.x) + std::fabs(b.centre.y);
        const float r = a.radius + b.radius + 2e-3f + 1e-5f * scale;
        return glm::dot(d, d) > r * r;
    }
    float shrink() const { return shrink_; }

private:
    const ActionLibrary* lib_;
    float shrink_;
    std::vector<int> first_;  // per action: its first sample's disc
    std::vector<Disc> discs_;
};
// The bounding spheres of the core boxes (shrunk) at every sample of every
// clip, in the clip's frame (coreBodiesOverlap's first test), and per clip a
// sphere per core segment round that segment's at every sample (its swept
// spheres): a body none of whose spheres meets a swept sphere of a clip
// placed somewhere fails every bounding-sphere test of coreBodiesOverlap
// against a body playing that clip there, at any of its samples.
class CoreSpheres {
public:
    static constexpr std::size_t kCount = kCoreSegments.size();
    // Spheres placed, with the largest |x| + |z| of their centres.
    struct Placed {
        std::array<glm::vec3, kCount> centre;
        std::array<float, kCount> radius;
        float scale = 0;
    };
    CoreSpheres(const ActionLibrary& lib, float shrink);
    // A body's spheres at a sample of its clip (the centres placed as
    // Obb::placed places the boxes', the radii of the shrunk boxes: the same
    // floats as CoreBody::boxes' centres and radii).
    Placed placed(int action, int sample, const RootXf& root, const FloorRotation& rotate) const {
        return place(samples_[static_cast<std::size_t>(first_[static_cast<std::size_t>(action)] + sample)], root, rotate);
    }
    // A clip's swept spheres placed at `root`.
    Placed swept(int action, const RootXf& root) const {
        return place(swept_[static_cast<std::size_t>(action)], root, FloorRotation(root.heading));
    }
    // Certainly no sphere of `body` meets one of `swept`: a margin of 2 mm
    // and 2e-5 of the coordinates covers the rounding of placing either.
    static bool apart(const Placed& body, const Placed& swept) {
        const float margin = 2e-3f + 2e-5f * (body.scale + swept.scale);
        for (std::size_t j = 0; j < kCount; ++j) {
            for (std::size_t i = 0; i < kCount; ++i) {
                const glm::vec3 d = body.centre[i] - swept.centre[j];
                const float r = body.radius[i] + swept.radius[j] + margin;
                if (glm::dot(d, d) <= r * r) return false;
            }
        }
        return true;
    }

private:
    struct Local {
        std::array<glm::vec3, kCount> centre;
        std::array<float, kCount> radius;
    };
    static Placed place(const Local& l, const RootXf& root, const FloorRotation& rotate) {
        Placed out;
        for (std::size_t i = 0; i < kCount; ++i) {
            out.centre[i] = rotate(l.centre[i]) + glm::vec3(root.pos.x, 0.0f, root.pos.y);
            out.radius[i] = l.radius[i];
            out.scale = std::max(out.scale, std::fabs(out.centre[i].x) + std::fabs(out.centre[i].z));
        }
        return out;
    }
    std::vector<int> first_;     // per action: its first sample's
    std::vector<Local> samples_;
    std::vector<Local> swept_;   // per action
};

inline BodyPose bodyAt(const Playing& p, double t) { return {p.action, p.clipTime(t), p.root}; }

// Earliest hit in [t0, t1] of one attacker on one defender; time < 0 if none.
struct HitCandidate {
    double time = -1;
    int target = 0;
    int effector = 0;
    double speed = 0;
    bool blocked = false;
    // Is this a hit, earlier than `best` (the first found wins a tie)?
    bool before(const HitCandidate& best) const { return time >= 0 && (best.time < 0 || time < best.time); }
};

// Effective mass (kg) behind a blow with this segment: impulse = speed x mass.
double effectiveMass(int effector);

// The push direction of a blow in the victim's heading frame, from the two placements at contact.
glm::vec2 pushDirection(const RootXf& victim, const RootXf& attacker);

// A forced reaction: the reactive clip, the clip time it starts at, where its
// first frame goes so that it continues the victim's pose, and when it ends.
struct ForcedReaction {
    int action = -1;  // -1: the pool has no clip
    double offset = 0;
    RootXf root;
    double end = 0;
    // The instance in a scene track (forced).
    ActionInstance instance(double start) const { return {action, start, offset, end, root, true, false}; }
};

// A scene's hits in time order (attacker order within one moment).
void sortHits(std::vector<HitEvent>& hits);

// Ends a track's last action at t and appends a forced reaction starting then.
void cutIntoReaction(std::vector<ActionInstance>& track, double t, const ForcedReaction& reaction);

// The reaction choices made over one library, for as long as it lives: the
// reaction pools met so far, by value (equal pools share an id), and per
// thread the choices keyed by pool id, victim clip and sample, push sector
// and strength. A choice is a function of the library and its key alone, so
// a remembered one is exact. Owned by the ActionLibrary (its copies share
// it); used through InteractionEngine.
class ReactionMemo {
public:
    struct Key {
        int pool = 0, action = 0, sample = 0, sector = 0;
        bool strong = false;
        bool operator==(const Key&) const = default;
    };
    struct Hash {
        std::size_t operator()(const Key& k) const;
    };
    using Table = std::unordered_map<Key, std::pair<int, int>, Hash>;

    // The id of a pool (ascending clips), added when new, and its clips
    // (which stay where they are for the memo's life).
    std::pair<int, const std::vector<int>*> pool(const std::vector<int>& clips);
    // This thread's choices.
    Table& table() { return tables_.local(); }

private:
    std::mutex mutex_;
    std::deque<std::vector<int>> pools_;
    tbb::enumerable_thread_specific<Table> tables_;
};

// The interaction rules over one library, with their state explicit: per
// action the initial travel of reactive clips, the reaction pools this engine
// uses (each character's or pattern entry's) and the library's ReactionMemo
// of choices. Pools are added before planning starts; the rest is safe to use
// from many threads at once.
class InteractionEngine {
public:
    explicit InteractionEngine(const ActionLibrary& lib);
    InteractionEngine(const InteractionEngine&) = delete;
    InteractionEngine& operator=(const InteractionEngine&) = delete;

    const ActionLibrary& library() const { return *lib_; }

    // Adds a pool of reactive clips (ascending action indices) and returns its
    // id; pools with the same clips share one id (and their choices).
    int addPool(const std::vector<int>& pool);
    const std::vector<int>& pool(int id) const { return *pools_[static_cast<std::size_t>(id)]; }

    // The earliest blow in [t0, t1] of att's action on def: none unless att
    // plays an attack with an effector that has not landed yet (`spent`) and
    // def is not in a forced reaction. A block on the segment hit stops it.
    HitCandidate strike(const Playing& att, bool spent, const Playing& def, bool defReacting, double t0, double t1) const;

    // The momentum of a landed blow (speed x the effector's effective mass).
    static double impulse(double speed, int effector) { return speed * effectiveMass(effector); }
    static double impulse(const HitCandidate& hit) { return impulse(hit.speed, hit.effector); }

    // The forced reaction of `victim` to a push at t from someone placed at
    // `pusher`: the clip of pool `poolId` and start sample that best match the
    // victim's posture and the push direction, a fall when strong; action -1
    // when the pool has none.
    ForcedReaction react(const Playing& victim, const RootXf& pusher, double t, bool strong, int poolId) const;

private:
    std::pair<int, int> chooseReaction(const Playing& victim, double t, glm::vec2 pushLocal, bool strong, int poolId) const;

    const ActionLibrary* lib_;
    std::vector<glm::vec2> reactionDir_;  // per action: initial floor travel of reactive clips (unit), else zero
    std::shared_ptr<ReactionMemo> memo_;  // the library's
    std::vector<const std::vector<int>*> pools_;  // by pool id: the clips of the pools added here (else null)
};

}  // namespace fray::sim::detail
