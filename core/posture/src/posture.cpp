#include "fray/posture/posture.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <numbers>
#include <limits>
#include <numeric>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <ode/ode.h>
#include <ode/threading_impl.h>
#include <tbb/parallel_for.h>
#include <dlfcn.h>

#include "fray/core/kinematics.h"

namespace fray::posture {

std::optional<Mode> parseMode(std::string_view name) {
    if (name == "kinematic") return Mode::Kinematic;
    if (name == "physics") return Mode::Physics;
    return std::nullopt;
}

const char* modeName(Mode mode) { return mode == Mode::Physics ? "physics" : "kinematic"; }

void Report::note(std::string line) {
    if (notes.size() < kMaxNotes) notes.push_back(std::move(line));
}

namespace {

using sim::Obb;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kMaxCorrectingSpeed = 2.0;  // m/s: contacts push overlapping bodies apart no faster
constexpr double kPinReach = 3.0;            // a pin is let go when the hip's target is this many legs away (a jump cut)
constexpr double kContactYield = 0.25;       // control gain left to a body touching another character
constexpr double kBodyYield = 0.6;           // and to the rest of that character's bodies
                                             // (a touching body's whole limb, or its trunk, yields as the body does)
constexpr double kPinComfort = 0.97;         // share of the leg's length the hip's target is kept within from a pin
constexpr double kPinTolerance = 0.02;       // m: a pin stays put while its foot's target is this close
constexpr double kPinSlide = 0.002;          // m per frame: a pin follows a sliding target no faster
constexpr double kPinSlideFast = 0.003;      // m per frame: the same while the hip's target is out of the leg's reach
constexpr double kHitDepth = 0.01;           // m: a blow is aimed this far inside the target's box
constexpr double kPinMaxHeight = 0.3;        // m: a supported ankle higher than this is not pinned
constexpr double kPinShove = 0.004;          // m per frame: a pin yields to another character pressing on its leg
constexpr double kPinLegErp = 0.2;           // contacts on a pinned foot or shin: soft (a spring of
constexpr double kPinLegCfm = 1e-3;          // ERP / (h CFM), 48 kN/m at 240 steps a second)
constexpr double kPinStep = 0.005;           // m per frame: the most a pin moves, slide and shove together
constexpr double kContactMargin = 0.03;      // m: collision boxes are grown by this for finding contacts ahead (speculative)
constexpr double kGapSlack = 0.005;          // m: a speculative contact lets bodies close the real gap less this
constexpr double kTouchGap = 0.005;          // m: closer than this a body counts as touching (its control yields)
constexpr double kArmSlack = 1.05;           // a hand pin farther than this many arm lengths from the collar is let go
constexpr int kSettleSteps = 60;             // at most this many contact-only steps separate characters that start inside each other
constexpr double kSettleDepth = 0.005;       // m: until no two characters' boxes are deeper than this inside each other
constexpr double kHoldReach = 0.03;          // m: a porter holds a bag while its captured hands' midpoint is this close to the bag's centre (not while it passes between two porters)

// ODE's QuickStep reorders constraints with dRandInt, which draws from one
// process-wide generator (dRand). Two islands stepping at once would take
// numbers from each other's sequence, so the result would depend on thread
// timing. dRand is defined below with the same generator (the same
// sequence for the same seed) kept per thread while an island steps: each
// step seeds its own thread's generator, and islands step in parallel with
// no lock. Outside a step it calls ODE's own dRand. Where the definition
// does not take the place of ODE's (an ODE built to bind its own calls), the
// steps run one at a time under a lock, seeding ODE's generator: the same
// numbers, the same results, only slower (checked once at start).
struct StepRandom {
    bool active = false;
    std::uint32_t seed = 0;
    std::uint64_t draws = 0;
};
thread_local StepRandom stepRandom;
bool perThreadRandom = false;

std::uint32_t nextRandom(std::uint32_t seed) { return seed * 1664525u + 1013904223u; }  // ODE's dRand

// While alive, this thread's dRand draws from `seed` onwards.
class StepRandomScope {
public:
    explicit StepRandomScope(std::uint32_t seed) { stepRandom.active = true, stepRandom.seed = seed; }
    ~StepRandomScope() { stepRandom.active = false; }
    StepRandomScope(const StepRandomScope&) = delete;
    StepRandomScope& operator=(const StepRandomScope&) = delete;
};

void initOde() {
    static std::once_flag once;
    std::call_once(once, [] {
        dInitODE2(0);
        // Does QuickStep's dRandInt reach the dRand below? Draw once and see,
        // and that it is the same sequence as ODE's.
        const unsigned long saved = dRandGetSeed();
        dRandSetSeed(12345);
        const unsigned long ode = dRandInt(1000);
        dRandSetSeed(saved);
        unsigned long mine = 0;
        {
            StepRandomScope scope(12345);
            stepRandom.draws = 0;
            mine = dRandInt(1000);
        }
        perThreadRandom = stepRandom.draws == 1 && mine == ode;
    });
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const glm::quat& q) { return std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w); }

glm::dvec3 vecOf(const dReal* v) { return {v[0], v[1], v[2]}; }
glm::dquat quatOf(const dReal* q) {
    glm::dquat r;
    r.w = q[0], r.x = q[1], r.y = q[2], r.z = q[3];
    return r;
}
void setQuat(dBodyID b, const glm::dquat& q) {
    const dQuaternion o = {q.w, q.x, q.y, q.z};
    dBodySetQuaternion(b, o);
}

// Rotation vector (axis * angle) of a rotation, the short way round.
glm::dvec3 rotationVector(glm::dquat q) {
    if (q.w < 0) q = -q;
    const glm::dvec3 v(q.x, q.y, q.z);
    const double s = glm::length(v);
    if (s < 1e-12) return 2.0 * v;
    return v * (2.0 * std::atan2(s, q.w) / s);
}

double smooth(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * (3.0 - 2.0 * x);
}

// The joint whose body carries a segment's box.
int segmentBody(int segment, const StandardJoints& j) {
    switch (segment) {
        case sim::kPelvis: return j.pelvis;
        case sim::kTorso: return j.spine >= 0 ? j.spine : j.pelvis;
        case sim::kHead: return j.neck >= 0 ? j.neck : j.head;
        case sim::kLeftUpperArm: return j.leftShoulder;
        case sim::kLeftForearm: return j.leftElbow;
        case sim::kRightUpperArm: return j.rightShoulder;
        case sim::kRightForearm: return j.rightElbow;
        case sim::kLeftThigh: return j.leftHip;
        case sim::kLeftShin: return j.leftKnee;
        case sim::kLeftFoot: return j.leftFoot;
        case sim::kRightThigh: return j.rightHip;
        case sim::kRightShin: return j.rightKnee;
        case sim::kRightFoot: return j.rightFoot;
        default: return j.pelvis;
    }
}

// The far joint of a segment's box (as sim::segmentBoxes spans it): the box
// runs from segmentBody's joint to this one.
int segmentFar(int segment, const StandardJoints& j) {
    switch (segment) {
        case sim::kPelvis: return j.spine >= 0 && j.spine != j.pelvis ? j.spine : j.chest;
        case sim::kTorso: return j.neck >= 0 ? j.neck : j.head;
        case sim::kHead: return j.head;
        case sim::kLeftUpperArm: return j.leftElbow;
        case sim::kLeftForearm: return j.leftHand;
        case sim::kRightUpperArm: return j.rightElbow;
        case sim::kRightForearm: return j.rightHand;
        case sim::kLeftThigh: return j.leftKnee;
        case sim::kLeftShin: return j.leftFoot;
        case sim::kLeftFoot: return j.leftToe;
        case sim::kRightThigh: return j.rightKnee;
        case sim::kRightShin: return j.rightFoot;
        case sim::kRightFoot: return j.rightToe;
        default: return -1;
    }
}

// One collision box of a character: the part of a segment's box that one
// body carries. A segment box spanning several bodies (the torso: spine to
// neck over three spine bodies) is cut across its axis at the joints between
// them, each piece carried by the body it covers, so a contact pushes the
// body that really moves that part of the box.
struct Piece {
    int segment = 0;
    int body = 0;       // joint whose body carries it
    int next = -1;      // the joint where it ends (-1: the box's far end)
    bool first = true;  // starts at the box's near end
    dGeomID geom = nullptr;
    float radius = 0;   // bounding sphere, for the broad phase
};

// A target adjustment: joints of one character moved by weight * offset,
// eased in over [peak - lead, peak] and out over [peak, peak + tail].
struct Pull {
    int character = 0;
    double peak = 0, lead = 0, tail = 0;
    glm::vec3 offset{0.0f};
    std::vector<std::pair<int, float>> joints;
    // The body it reaches for: the offset follows that joint's deviation from
    // its captured place (-1: a fixed offset).
    int other = -1, otherJoint = -1;
    int otherFar = -1;  // with otherJoint, the target segment's two ends: the offset follows its middle
    double weight(double t) const {
        if (t < peak - lead || t > peak + tail) return 0.0;
        return t <= peak ? smooth((t - (peak - lead)) / lead) : smooth(1.0 - (t - peak) / tail);
    }
};

// A blow: the victim's body pushed by the striker's momentum once.
struct Blow {
    double time = 0;
    int attacker = 0, defender = 0;
    int tipJoint = 0, targetJoint = 0;
    double mass = 0;   // kg behind the blow (the striking limb)
    double scale = 1;  // blocked blows push less
    std::int64_t step = 0;  // the physics step it is pushed in: the first after the hit's frame is shown
};

// What control() pulls a body towards over one frame's substeps, computed
// once a frame from the targets (the substeps only interpolate).
struct Aim {
    glm::dvec3 c0{0.0}, c1{0.0};     // centre of mass at the last frame's targets and this one's
    glm::dvec3 v01{0.0}, v12{0.0};   // captured velocity before and after this frame
    glm::dvec3 acc{0.0}, spin{0.0};  // captured acceleration and angular velocity
    glm::dquat q0{1, 0, 0, 0}, q1{1, 0, 0, 0};
};

struct Character {
    int index = 0;
    const Skeleton* skeleton = nullptr;
    StandardJoints roles;
    int jointCount = 0;
    bool controlled = true;
    bool created = false;
    std::vector<glm::dvec3> centre;  // body centre (mass) in its joint's frame
    std::vector<double> mass, inertia;
    std::vector<double> reach;       // m: ankle to hip along the leg (pin compatibility)
    std::vector<dBodyID> bodies;     // per joint (null where it rides)
    std::vector<std::uint8_t> rides; // per joint: an end joint that is no body of its own (see rider())
    std::vector<Piece> pieces;  // collision boxes, by segment then along it
    std::array<dJointID, 2> pin{nullptr, nullptr};
    std::array<glm::dvec3, 2> pinAt{};
    double maxFootSpan = 2.0;
    std::array<dJointID, 2> handPin{nullptr, nullptr};  // left, right hand pinned to a bag
    std::array<glm::dvec3, 2> grip{};                   // where, in the bag's frame
    std::array<bool, 2> gripped{false, false};          // grip taken in the current hold
    int heldBag = -1;                                   // the scene character of the bag held
    int heldBall = -1;                                  // the scene character of the ball it carries (its holder is this one)
    dJointID ballPin = nullptr;                         // its ball hand pinned to the ball (Options::handPins)
    std::array<double, 2> armLength{0.6, 0.6};          // m: shoulder to hand
    bool reportedReach = false;
    std::array<double, 2> legLength{1.0, 1.0};  // m: ankle to hip joint
    std::vector<glm::vec3> pinShift;  // per joint: targets moved onto the pins (pinned feet, their knees half)
    std::vector<std::uint8_t> pinHeld; // per joint: held by a pin (no velocity target)
    std::vector<std::uint8_t> pinLeg;  // per joint: the foot or shin body of a pinned leg (its contacts are soft)
    std::vector<std::uint8_t> touched; // per joint: its body touches another character this step
    std::vector<std::uint8_t> group;   // per joint: 0 the trunk (pelvis, spine, neck, head), 1-4 a leg or an arm (hip or shoulder down)
    std::array<std::uint8_t, 5> groupTouched{};  // per group: one of its bodies touches another character this step
    bool touching = false;             // any of them does
    bool linked = false;               // a contact joins one of its bodies to another character's this step (Solver::Hybrid)
    bool calm = false;                 // no contact at this pair of substeps' first: both taken as one step (Options::calmPairs)
    std::vector<glm::dvec3> shove;     // per joint: contact push from other characters over the last frame (sum of normal x depth)
    std::vector<double> shoveDepth;    // per joint: the deepest of those contacts (m)
    std::vector<float> torqueScale;  // per joint: twist control eased off where a pull moves the limb
    // Targets at the last frame and this one.
    std::vector<glm::vec3> p0, p1, p2;  // targets at the last frame, this one and the next
    std::vector<glm::quat> r0, r1, r2;
    std::vector<glm::vec3> lastPos;
    std::vector<glm::quat> lastRot;
    bool haveFinite = false;
    bool reportedNonFinite = false;
    // Output.
    std::vector<glm::vec3> outPos;
    std::vector<glm::quat> outRot;
    std::vector<glm::vec3> scratch;
    std::vector<glm::vec3> deviation;  // output minus target at the last frame (where it really is)
    std::vector<Aim> aims;             // per body: what control() pulls towards this frame (set once a frame)
};

// Is joint j on the spine (from the chest down to, not including, the pelvis)?
bool isSpine(const Character& c, int j) {
    for (int k = c.roles.chest; k >= 0 && k != c.roles.pelvis; k = c.skeleton->parents[static_cast<std::size_t>(k)]) {
        if (k == j) return true;
    }
    return false;
}

std::mutex& stepMutex() {
    static std::mutex m;
    return m;
}

// One ODE step of `world` by h, its random stream seeded first: per thread
// where ODE allows it, else under one lock (see StepRandom). QuickStep
// draws from it; the direct solver (an Options::solver choice) is seeded
// the same way, so its results cannot depend on threads either.
void seededStep(dWorldID world, dReal h, std::uint32_t seed, Solver solver) {
    const auto stepOnce = [&] { solver == Solver::Direct ? dWorldStep(world, h) : dWorldQuickStep(world, h); };
    if (perThreadRandom) {
        StepRandomScope scope(seed);
        stepOnce();
    } else {
        const std::lock_guard<std::mutex> lock(stepMutex());
        dRandSetSeed(seed);
        stepOnce();
    }
}

struct Island {
    int index = 0;
    dWorldID world = nullptr;
    dJointGroupID contacts = nullptr;
    dGeomID floor = nullptr;
    dThreadingImplementationID threading = nullptr;  // its own: ODE's default one is shared by all worlds
    std::vector<int> members;
    std::vector<int> blows;    // Impl::blows whose victim is a member, in order
    int contactsThisStep = 0;  // contacts between characters in the current step
    double deepest = 0;        // m: the deepest of them (of the real boxes)
    double time = 0;           // s: the scene time at the start of the current step
    std::vector<std::uint8_t> kind;  // per member: how solve() steps it (scratch)
    Report report;
};

}  // namespace

struct Simulator::Impl {
    const sim::Scene& scene;
    const sim::ActionLibrary& lib;
    Options opt;
    sim::ScenePoser poser;
    std::vector<Character> chars;
    std::vector<Island> islands;
    std::vector<Pull> pulls;
    std::vector<std::vector<int>> pullsOf;  // per character
    std::vector<Blow> blows;
    std::vector<int> bags;  // scene characters that are bags (hands pin to them)
    Report report;
    mutable Report mergedReport;
    std::vector<std::uint8_t> pinRefused;  // per Options::pins entry: already reported
    int frame = -1, frames = 0;
    double h = 0;

    Impl(const sim::Scene& s, const sim::ActionLibrary& l, const Options& o) : scene(s), lib(l), opt(o), poser(s, l) {
        initOde();
        frames = static_cast<int>(std::floor(scene.duration * opt.fps)) + 1;
        h = 1.0 / (opt.fps * opt.substeps);
        pinRefused.assign(opt.pins.size(), 0);
        for (std::size_t i = 0; i < scene.characters.size(); ++i) {
            if (scene.characters[i].body == "bag" && !scene.characters[i].keys.empty()) bags.push_back(static_cast<int>(i));
        }
        setupCharacters();
        // A ball's holder (the football carrier) holds it all along.
        for (std::size_t i = 0; i < scene.characters.size(); ++i) {
            const auto& b = scene.characters[i];
            if (b.body != "ball" || b.keys.empty() || b.holder < 0 || static_cast<std::size_t>(b.holder) >= chars.size()) continue;
            if (!scene.isCreature(b.holder)) chars[static_cast<std::size_t>(b.holder)].heldBall = static_cast<int>(i);
        }
        setupPulls();
        setupIslands();
    }

    ~Impl() {
        for (auto& c : chars) {
            for (const auto& piece : c.pieces) {
                if (piece.geom) dGeomDestroy(piece.geom);
            }
        }
        for (auto& is : islands) {
            if (is.floor) dGeomDestroy(is.floor);
            if (is.contacts) dJointGroupDestroy(is.contacts);
            if (is.world) dWorldDestroy(is.world);
            if (is.threading) dThreadingFreeImplementation(is.threading);
        }
    }

    std::string nameOf(int c) const { return "'" + scene.characters[static_cast<std::size_t>(c)].name + "'"; }

    void setupCharacters() {
        chars.resize(scene.characters.size());
        for (std::size_t i = 0; i < chars.size(); ++i) {
            auto& c = chars[i];
            c.index = static_cast<int>(i);
            if (scene.isCreature(c.index) || scene.characters[i].track.empty()) continue;
            c.skeleton = &poser.skeleton(c.index);
            const auto& first = lib.actions()[static_cast<std::size_t>(scene.characters[i].track.front().action)];
            c.roles = lib.motion(first.motion).joints;
            c.controlled = !(i < opt.ragdoll.size() && opt.ragdoll[i] != 0);
            const auto& sk = *c.skeleton;
            c.jointCount = sk.jointCount();
            const auto n = static_cast<std::size_t>(c.jointCount);
            c.centre.assign(n, glm::dvec3(0.0));
            c.mass.assign(n, 0.5);
            c.inertia.assign(n, 0.0);
            for (int j = 0; j < c.jointCount; ++j) {
                const auto kids = sk.children(j);
                glm::dvec3 sum(0.0);
                double length = 0;
                for (int k : kids) sum += glm::dvec3(sk.offsets[static_cast<std::size_t>(k)]);
                if (!kids.empty()) {
                    sum /= static_cast<double>(kids.size());
                } else if (sk.endSites[static_cast<std::size_t>(j)]) {
                    sum = glm::dvec3(*sk.endSites[static_cast<std::size_t>(j)]);
                }
                length = glm::length(sum);
                c.centre[static_cast<std::size_t>(j)] = 0.5 * sum;
                // A lean adult of about 70 kg: the big segments by role, the
                // rest about 12 kg per metre of segment, never under 0.3 kg.
                c.mass[static_cast<std::size_t>(j)] = std::max(0.3, 12.0 * length);
                const auto& r0 = c.roles;
                if (j == r0.pelvis) c.mass[static_cast<std::size_t>(j)] = 10;
                else if (j == r0.head) c.mass[static_cast<std::size_t>(j)] = 5;
                else if (j == r0.leftHip || j == r0.rightHip) c.mass[static_cast<std::size_t>(j)] = 8;
                else if (j == r0.leftKnee || j == r0.rightKnee) c.mass[static_cast<std::size_t>(j)] = 3.5;
                else if (j == r0.leftShoulder || j == r0.rightShoulder) c.mass[static_cast<std::size_t>(j)] = 2;
                else if (j == r0.leftElbow || j == r0.rightElbow) c.mass[static_cast<std::size_t>(j)] = 1.5;
                else if (j == r0.leftFoot || j == r0.rightFoot) c.mass[static_cast<std::size_t>(j)] = 1;
                else if (j == r0.leftHand || j == r0.rightHand) c.mass[static_cast<std::size_t>(j)] = 0.5;
                else if (isSpine(c, j)) c.mass[static_cast<std::size_t>(j)] = 8;
                const double r = std::max(0.05, 0.5 * length);
                c.inertia[static_cast<std::size_t>(j)] = 0.4 * c.mass[static_cast<std::size_t>(j)] * r * r;
            }
            auto chain = [&](int from, int to) {
                double len = 0;
                for (int j = from; j >= 0 && j != to; j = sk.parents[static_cast<std::size_t>(j)]) {
                    len += static_cast<double>(glm::length(sk.offsets[static_cast<std::size_t>(j)]));
                }
                return len;
            };
            const double leg = std::max(chain(c.roles.leftFoot, c.roles.pelvis), chain(c.roles.rightFoot, c.roles.pelvis));
            c.maxFootSpan = 2.0 * leg;
            c.legLength = {chain(c.roles.leftFoot, c.roles.leftHip), chain(c.roles.rightFoot, c.roles.rightHip)};
            if (c.roles.hasHands() && c.roles.leftShoulder >= 0 && c.roles.rightShoulder >= 0) {
                // From the shoulder joint's parent (the collar) to the hand: what the hand can reach.
                c.armLength = {chain(c.roles.leftHand, sk.parents[static_cast<std::size_t>(c.roles.leftShoulder)]),
                               chain(c.roles.rightHand, sk.parents[static_cast<std::size_t>(c.roles.rightShoulder)])};
            }
            c.torqueScale.assign(n, 1.0f);
            c.rides.assign(n, 0);
            for (int j = 0; j < c.jointCount; ++j) c.rides[static_cast<std::size_t>(j)] = rider(c, j) ? 1 : 0;
            c.pinShift.assign(n, glm::vec3(0.0f));
            c.pinHeld.assign(n, 0);
            c.pinLeg.assign(n, 0);
            c.touched.assign(n, 0);
            c.group.assign(n, 0);
            for (int j = 0; j < c.jointCount; ++j) {
                const int roots[4] = {c.roles.leftHip, c.roles.rightHip, c.roles.leftShoulder, c.roles.rightShoulder};
                for (int k = j; k >= 0 && c.group[static_cast<std::size_t>(j)] == 0; k = sk.parents[static_cast<std::size_t>(k)]) {
                    for (int g = 0; g < 4; ++g) {
                        if (roots[g] >= 0 && k == roots[g]) c.group[static_cast<std::size_t>(j)] = static_cast<std::uint8_t>(g + 1);
                    }
                }
            }
            c.shove.assign(n, glm::dvec3(0.0));
            c.shoveDepth.assign(n, 0.0);
            c.p0.assign(n, glm::vec3(0.0f));
            c.p1 = c.p2 = c.p0;
            c.r0.assign(n, glm::quat(1, 0, 0, 0));
            c.r1 = c.r2 = c.r0;
            c.outPos = c.p0;
            c.outRot = c.r0;
        }
    }

    // Kinematic targets of character c at time t (world positions, rotations).
    void kinematic(int c, double t, std::vector<glm::vec3>& pos, std::vector<glm::quat>& rot) const {
        Pose pose;
        poser.pose(c, t, pose);
        const auto& ch = chars[static_cast<std::size_t>(c)];
        pos.resize(static_cast<std::size_t>(ch.jointCount));
        rot.resize(static_cast<std::size_t>(ch.jointCount));
        if (pose.translations.size() != pos.size()) {
            std::fill(pos.begin(), pos.end(), glm::vec3(std::numeric_limits<float>::quiet_NaN()));
            return;
        }
        forwardKinematics(*ch.skeleton, pose.translations, pose.rotations, pos, rot);
    }

    // The joints that move with a limb segment (its near joint and everything
    // below it fully, the joint above it half).
    std::vector<std::pair<int, float>> limbJoints(const Character& c, int nearJoint, float aboveWeight) const {
        std::vector<std::pair<int, float>> out;
        const auto& sk = *c.skeleton;
        for (int j = 0; j < c.jointCount; ++j) {
            for (int k = j; k >= 0; k = sk.parents[static_cast<std::size_t>(k)]) {
                if (k == nearJoint) {
                    out.emplace_back(j, 1.0f);
                    break;
                }
            }
        }
        const int above = sk.parents[static_cast<std::size_t>(nearJoint)];
        if (above >= 0) out.emplace_back(above, aboveWeight);
        return out;
    }

    void setupPulls() {
        pullsOf.resize(chars.size());
        std::vector<glm::vec3> pa, pb;
        std::vector<glm::quat> ra, rb;
        auto person = [&](int c) {
            return c >= 0 && c < static_cast<int>(chars.size()) && chars[static_cast<std::size_t>(c)].skeleton != nullptr;
        };
        for (const auto& hit : scene.hits) {
            if (!person(hit.attacker) || !person(hit.defender) || hit.effector < 0 || hit.effector >= sim::kSegmentCount ||
                hit.target < 0 || hit.target >= sim::kSegmentCount) {
                continue;
            }
            const auto& att = chars[static_cast<std::size_t>(hit.attacker)];
            const auto& def = chars[static_cast<std::size_t>(hit.defender)];
            Blow blow{hit.time, hit.attacker, hit.defender, segmentBody(hit.effector, att.roles),
                      segmentBody(hit.target, def.roles), 0.0, hit.blocked ? 0.5 : 1.0};
            const auto limb = limbJoints(att, segmentBody(hit.effector, att.roles), 0.5f);
            for (const auto& [j, w] : limb) blow.mass += static_cast<double>(w) * att.mass[static_cast<std::size_t>(j)];
            // Counted in whole steps: a hit time a rounding error either side
            // of a frame's time pushes in the same step (it decided before
            // whether the victim flew off before or after the frame of the
            // hit was shown: a blow measured on the surface or 2 cm off it).
            blow.step = static_cast<std::int64_t>(std::llround(hit.time * opt.fps)) * opt.substeps;
            blows.push_back(blow);
            if (!opt.hitTargets) continue;
            kinematic(hit.attacker, hit.time, pa, ra);
            kinematic(hit.defender, hit.time, pb, rb);
            if (!std::all_of(pa.begin(), pa.end(), [](const glm::vec3& v) { return finite(v); }) ||
                !std::all_of(pb.begin(), pb.end(), [](const glm::vec3& v) { return finite(v); })) {
                continue;
            }
            const auto A = sim::segmentBoxes(pa, att.roles)[static_cast<std::size_t>(hit.effector)];
            const auto B = sim::segmentBoxes(pb, def.roles)[static_cast<std::size_t>(hit.target)];
            glm::vec3 normal;
            const double d = sim::boxSignedDistance(A, B, &normal);
            // Aim a little into the surface: the collision holds the striker on it.
            const glm::vec3 offset = normal * static_cast<float>(d + kHitDepth);
            if (glm::length(offset) > 0.6f) {
                report.note("hit at " + std::to_string(hit.time) + " s: " + nameOf(hit.attacker) + "'s " +
                            sim::segmentName(hit.effector) + " is " + std::to_string(d) +
                            " m from the target; not pulled");
                continue;
            }
            Pull p;
            p.character = hit.attacker;
            p.peak = hit.time;
            p.lead = opt.hitLead;
            p.tail = opt.hitTail;
            p.offset = offset;
            p.joints = limb;
            p.other = hit.defender;
            // The middle of the victim's target segment, where the blow meets
            // it: a thigh swinging away about its hip moves there, not at the hip.
            p.otherJoint = segmentBody(hit.target, def.roles);
            p.otherFar = segmentFar(hit.target, def.roles);
            pullsOf[static_cast<std::size_t>(hit.attacker)].push_back(static_cast<int>(pulls.size()));
            pulls.push_back(std::move(p));
        }
        // Parry: before an unblocked blow, the defender's forearm nearer to
        // the striking segment moves part way towards it, when the defender
        // is not attacking itself (its arms are free).
        for (const auto& hit : scene.hits) {
            if (!opt.parry || hit.blocked || !person(hit.attacker) || !person(hit.defender) || hit.effector < 0 ||
                hit.effector >= sim::kSegmentCount) {
                continue;
            }
            const int inst = scene.instanceAt(hit.defender, hit.time);
            const auto& track = scene.characters[static_cast<std::size_t>(hit.defender)].track;
            if (inst < 0 || static_cast<std::size_t>(inst) >= track.size()) continue;
            if (lib.action(track[static_cast<std::size_t>(inst)].action).is(sim::kAttack)) continue;
            const auto& att = chars[static_cast<std::size_t>(hit.attacker)];
            const auto& def = chars[static_cast<std::size_t>(hit.defender)];
            kinematic(hit.attacker, hit.time, pa, ra);
            kinematic(hit.defender, hit.time, pb, rb);
            const auto strike = sim::segmentBoxes(pa, att.roles)[static_cast<std::size_t>(hit.effector)].centre;
            int hand = -1, elbow = -1;
            float best = std::numeric_limits<float>::max();
            for (const auto& [hj, ej] : {std::pair{def.roles.leftHand, def.roles.leftElbow},
                                         std::pair{def.roles.rightHand, def.roles.rightElbow}}) {
                if (hj < 0 || ej < 0 || !finite(pb[static_cast<std::size_t>(hj)])) continue;
                const float d = glm::length(strike - pb[static_cast<std::size_t>(hj)]);
                if (d < best) best = d, hand = hj, elbow = ej;
            }
            if (hand < 0 || !finite(strike)) continue;
            glm::vec3 offset = (strike - pb[static_cast<std::size_t>(hand)]) * static_cast<float>(opt.parryShare);
            const float len = glm::length(offset);
            if (len > static_cast<float>(opt.parryReach)) offset *= static_cast<float>(opt.parryReach) / len;
            Pull p;
            p.character = hit.defender;
            p.peak = hit.time;
            p.lead = opt.hitLead;
            p.tail = opt.hitTail;
            p.offset = offset;
            p.joints = limbJoints(def, elbow, 0.5f);
            for (auto& [j, w] : p.joints) {
                if (j == elbow) w = 0.6f;  // the hand leads, the elbow follows part way
            }
            pullsOf[static_cast<std::size_t>(hit.defender)].push_back(static_cast<int>(pulls.size()));
            pulls.push_back(std::move(p));
        }
        for (const auto& k : scene.catches) {
            if (!person(k.chaser) || !person(k.runaway)) continue;
            const auto& ch = chars[static_cast<std::size_t>(k.chaser)];
            kinematic(k.chaser, k.time, pa, ra);
            kinematic(k.runaway, k.time, pb, rb);
            const auto torso = sim::segmentBoxes(pb, chars[static_cast<std::size_t>(k.runaway)].roles)[sim::kTorso];
            for (const auto& [hand, elbow] : {std::pair{ch.roles.leftHand, ch.roles.leftElbow},
                                             std::pair{ch.roles.rightHand, ch.roles.rightElbow}}) {
                if (hand < 0 || elbow < 0 || !finite(pa[static_cast<std::size_t>(hand)])) continue;
                // The nearest point of the runaway's torso box to the hand.
                const glm::vec3 q = pa[static_cast<std::size_t>(hand)];
                const glm::vec3 rel = q - torso.centre;
                glm::vec3 on = torso.centre;
                for (int a = 0; a < 3; ++a) on += torso.axes[a] * std::clamp(glm::dot(rel, torso.axes[a]), -torso.half[a], torso.half[a]);
                const glm::vec3 offset = on - q;
                if (!finite(offset) || static_cast<double>(glm::length(offset)) > opt.catchReach) continue;
                Pull p;
                p.character = k.chaser;
                p.peak = k.time;
                p.lead = opt.catchLead;
                p.tail = 0.3;
                p.offset = offset;
                p.joints = limbJoints(ch, elbow, 0.5f);
                p.other = k.runaway;
                p.otherJoint = chars[static_cast<std::size_t>(k.runaway)].roles.spine;
                for (auto& [j, w] : p.joints) {
                    if (j == elbow) w = 0.6f;  // the hand reaches, the elbow follows part way
                }
                pullsOf[static_cast<std::size_t>(k.chaser)].push_back(static_cast<int>(pulls.size()));
                pulls.push_back(std::move(p));
            }
        }
        for (const auto& pin : opt.pins) {
            if (!person(pin.character) || pin.foot < 0 || pin.foot > 1) {
                ++report.refusedPins;
                report.note("foot pin on character " + std::to_string(pin.character) + ", foot " + std::to_string(pin.foot) +
                            ": no such person or foot; refused");
            }
        }
    }

    // Islands: characters whose pelvises come within islandReach of each
    // other at some time (sampled at 10 Hz) share a world.
    void setupIslands() {
        const int n = static_cast<int>(chars.size());
        std::vector<int> parent(static_cast<std::size_t>(n));
        std::iota(parent.begin(), parent.end(), 0);
        auto find = [&](int x) {
            while (parent[static_cast<std::size_t>(x)] != x) {
                parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
                x = parent[static_cast<std::size_t>(x)];
            }
            return x;
        };
        const double cell = opt.islandReach;
        const int samples = static_cast<int>(std::floor(scene.duration * 10.0)) + 1;
        std::unordered_map<std::int64_t, std::vector<int>> grid;
        std::vector<glm::vec2> at(static_cast<std::size_t>(n));
        auto key = [](std::int64_t x, std::int64_t z) { return (x << 32) ^ (z & 0xffffffff); };
        for (int s = 0; s < samples; ++s) {
            const double t = s / 10.0;
            grid.clear();
            for (int c = 0; c < n; ++c) {
                if (!chars[static_cast<std::size_t>(c)].skeleton) continue;
                const auto& track = scene.characters[static_cast<std::size_t>(c)].track;
                const auto& inst = track[static_cast<std::size_t>(std::max(0, scene.instanceAt(c, t)))];
                const glm::vec2 p = inst.placementAt(lib, inst.clipTimeAt(t)).pos;
                at[static_cast<std::size_t>(c)] = p;
                if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
                const auto gx = static_cast<std::int64_t>(std::floor(static_cast<double>(p.x) / cell));
                const auto gz = static_cast<std::int64_t>(std::floor(static_cast<double>(p.y) / cell));
                for (std::int64_t dx = -1; dx <= 1; ++dx) {
                    for (std::int64_t dz = -1; dz <= 1; ++dz) {
                        const auto it = grid.find(key(gx + dx, gz + dz));
                        if (it == grid.end()) continue;
                        for (int o : it->second) {
                            if (static_cast<double>(glm::length(at[static_cast<std::size_t>(o)] - p)) <= cell) parent[static_cast<std::size_t>(find(c))] = find(o);
                        }
                    }
                }
                grid[key(gx, gz)].push_back(c);
            }
        }
        std::map<int, int> islandOf;  // root -> island, in order of each island's first member
        for (int c = 0; c < n; ++c) {
            if (!chars[static_cast<std::size_t>(c)].skeleton) continue;
            const int root = find(c);
            auto [it, fresh] = islandOf.try_emplace(root, static_cast<int>(islands.size()));
            if (fresh) islands.emplace_back();
            islands[static_cast<std::size_t>(it->second)].members.push_back(c);
        }
        for (auto& is : islands) {
            is.index = static_cast<int>(&is - islands.data());
            is.world = dWorldCreate();
            // Each world steps with its own (self-threaded) job list, so
            // islands can step at the same time on different threads.
            is.threading = dThreadingAllocateSelfThreadedImplementation();
            dWorldSetStepThreadingImplementation(is.world, dThreadingImplementationGetFunctions(is.threading), is.threading);
            dWorldSetGravity(is.world, 0, -9.81, 0);
            dWorldSetERP(is.world, 0.3);
            dWorldSetCFM(is.world, 1e-7);
            dWorldSetQuickStepNumIterations(is.world, opt.iterations);
            dWorldSetContactMaxCorrectingVel(is.world, kMaxCorrectingSpeed);
            dWorldSetContactSurfaceLayer(is.world, 0.002);
            is.contacts = dJointGroupCreate(0);
            is.floor = dCreatePlane(nullptr, 0, 1, 0, 0);
        }
        // Each island looks only at the blows on its own members (not at every
        // blow of the scene every step).
        std::vector<int> islandOfChar(chars.size(), -1);
        for (const auto& is : islands) {
            for (int m : is.members) islandOfChar[static_cast<std::size_t>(m)] = is.index;
        }
        for (std::size_t b = 0; b < blows.size(); ++b) {
            const int i = islandOfChar[static_cast<std::size_t>(blows[b].defender)];
            if (i >= 0) islands[static_cast<std::size_t>(i)].blows.push_back(static_cast<int>(b));
        }
    }

    // Targets of character c at time t, adjusted, with non-finite values held.
    void targets(Island& is, Character& c, double t, std::vector<glm::vec3>& pos, std::vector<glm::quat>& rot) {
        kinematic(c.index, t, pos, rot);
        bool bad = false;
        for (std::size_t j = 0; j < pos.size(); ++j) {
            if (finite(pos[j]) && finite(rot[j])) continue;
            bad = true;
            pos[j] = c.haveFinite ? c.lastPos[j] : glm::vec3(0.0f);
            rot[j] = c.haveFinite ? c.lastRot[j] : glm::quat(1, 0, 0, 0);
        }
        if (bad) {
            ++is.report.nonFiniteTargets;
            if (!c.reportedNonFinite) {
                c.reportedNonFinite = true;
                is.report.note("character " + nameOf(c.index) + ": non-finite pose at " + std::to_string(t) +
                               " s; held at its last finite pose");
            }
        } else {
            c.lastPos = pos, c.lastRot = rot, c.haveFinite = true;
        }
        std::fill(c.torqueScale.begin(), c.torqueScale.end(), 1.0f);
        for (int p : pullsOf[static_cast<std::size_t>(c.index)]) {
            const Pull& pull = pulls[static_cast<std::size_t>(p)];
            const double w = pull.weight(t);
            if (w <= 0) continue;
            glm::vec3 offset = pull.offset;
            if (pull.other >= 0 && pull.otherJoint >= 0) {
                const auto& o = chars[static_cast<std::size_t>(pull.other)];
                if (o.created && !o.deviation.empty()) {
                    const glm::vec3 near = o.deviation[static_cast<std::size_t>(pull.otherJoint)];
                    offset += pull.otherFar >= 0 ? 0.5f * (near + o.deviation[static_cast<std::size_t>(pull.otherFar)]) : near;
                }
            }
            for (const auto& [j, jw] : pull.joints) {
                pos[static_cast<std::size_t>(j)] += offset * static_cast<float>(w * static_cast<double>(jw));
                // The limb's twist follows the pull rather than the capture.
                auto& ts = c.torqueScale[static_cast<std::size_t>(j)];
                ts = std::min(ts, static_cast<float>(1.0 - w * static_cast<double>(jw)));
            }
        }
    }

    // An end joint (no children) that carries no collision box, no pin and
    // no big mass (a finger or toe end, not the head, a hand or a foot) is
    // no body of its own: it rides on its parent's body, turned by its
    // captured rotation relative to the parent. Each such body cost three
    // constraint rows and its light mass slowed the solver's convergence.
    bool rider(const Character& c, int j) const {
        const auto& sk = *c.skeleton;
        if (sk.parents[static_cast<std::size_t>(j)] < 0 || !sk.children(j).empty()) return false;
        const auto& r = c.roles;
        if (j == r.head || j == r.neck || j == r.leftHand || j == r.rightHand || j == r.leftFoot || j == r.rightFoot) return false;
        for (int s = 0; s < sim::kSegmentCount; ++s) {
            if (segmentBody(s, r) == j) return false;
        }
        return true;
    }

    glm::dvec3 jointPos(const Character& c, int j) const {
        if (c.rides[static_cast<std::size_t>(j)]) {
            const int p = c.skeleton->parents[static_cast<std::size_t>(j)];
            const dBodyID b = c.bodies[static_cast<std::size_t>(p)];
            return vecOf(dBodyGetPosition(b)) +
                   quatOf(dBodyGetQuaternion(b)) * (glm::dvec3(c.skeleton->offsets[static_cast<std::size_t>(j)]) -
                                                    c.centre[static_cast<std::size_t>(p)]);
        }
        const dBodyID b = c.bodies[static_cast<std::size_t>(j)];
        return vecOf(dBodyGetPosition(b)) - quatOf(dBodyGetQuaternion(b)) * c.centre[static_cast<std::size_t>(j)];
    }

    // A joint's world rotation: its body's, or for a rider its parent's
    // turned by the captured relative rotation.
    glm::dquat jointRot(const Character& c, int j) const {
        const auto u = static_cast<std::size_t>(j);
        if (!c.rides[u]) return quatOf(dBodyGetQuaternion(c.bodies[u]));
        const auto p = static_cast<std::size_t>(c.skeleton->parents[u]);
        return quatOf(dBodyGetQuaternion(c.bodies[p])) * (glm::conjugate(glm::dquat(c.r1[p])) * glm::dquat(c.r1[u]));
    }

    void create(Island& is, Character& c) {
        const auto n = static_cast<std::size_t>(c.jointCount);
        c.bodies.resize(n);
        for (std::size_t j = 0; j < n; ++j) {
            if (c.rides[j]) {
                c.bodies[j] = nullptr;
                continue;
            }
            dBodyID b = dBodyCreate(is.world);
            dMass m;
            dMassSetZero(&m);
            m.mass = c.mass[j];
            m.I[0] = m.I[5] = m.I[10] = c.inertia[j];
            dBodySetMass(b, &m);
            const glm::dquat q(c.r1[j]);
            const glm::dvec3 centre = glm::dvec3(c.p1[j]) + q * c.centre[j];
            dBodySetPosition(b, centre.x, centre.y, centre.z);
            setQuat(b, q);
            const glm::dvec3 v = (glm::dvec3(c.p1[j]) - glm::dvec3(c.p0[j])) * opt.fps;
            dBodySetLinearVel(b, v.x, v.y, v.z);
            c.bodies[j] = b;
        }
        const auto& sk = *c.skeleton;
        for (std::size_t j = 1; j < n; ++j) {
            const int p = sk.parents[j];
            if (p < 0 || c.rides[j]) continue;
            dJointID joint = dJointCreateBall(is.world, nullptr);
            dJointAttach(joint, c.bodies[static_cast<std::size_t>(p)], c.bodies[j]);
            dJointSetBallAnchor(joint, c.p1[j].x, c.p1[j].y, c.p1[j].z);
        }
        const auto boxes = sim::segmentBoxes(c.p1, c.roles);
        for (int s = 0; s < sim::kSegmentCount; ++s) {
            const Obb& box = boxes[static_cast<std::size_t>(s)];
            // The bodies the box spans: its near joint's and, where the far
            // joint is not that body's child, the ones in between.
            const int near = segmentBody(s, c.roles);
            const int far = segmentFar(s, c.roles);
            std::vector<int> chain;
            for (int k = far >= 0 ? sk.parents[static_cast<std::size_t>(far)] : -1; k >= 0; k = sk.parents[static_cast<std::size_t>(k)]) {
                chain.push_back(k);
                if (k == near) break;
            }
            if (chain.empty() || chain.back() != near) chain.assign(1, near);  // not a chain: one piece
            std::reverse(chain.begin(), chain.end());
            for (std::size_t k = 0; k < chain.size(); ++k) {
                Piece piece;
                piece.segment = s;
                piece.body = chain[k];
                piece.next = k + 1 < chain.size() ? chain[k + 1] : -1;
                piece.first = k == 0;
                piece.geom = dCreateBox(nullptr, 2.0 * static_cast<double>(box.half.x), 2.0 * static_cast<double>(box.half.y),
                                        2.0 * static_cast<double>(box.half.z));
                dGeomSetBody(piece.geom, c.bodies[static_cast<std::size_t>(piece.body)]);
                c.pieces.push_back(piece);
            }
        }
        syncGeoms(c);
        c.created = true;
        // Bodies that start inside one another are pushed apart gently.
        for (int o : is.members) {
            const auto& other = chars[static_cast<std::size_t>(o)];
            if (o == c.index || !other.created) continue;
            const auto mine = boxes;
            const auto theirs = sim::segmentBoxes(other.outPos, other.roles);
            double depth = 0;
            for (const auto& a : mine) {
                for (const auto& b : theirs) depth = std::max(depth, sim::boxPenetration(a, b));
            }
            if (depth > 0.01) {
                ++is.report.initialOverlaps;
                char line[256];
                std::snprintf(line, sizeof line, "characters %s and %s start %.1f cm inside each other: pushed apart at <= %.1f m/s",
                              nameOf(other.index).c_str(), nameOf(c.index).c_str(), 100.0 * depth, kMaxCorrectingSpeed);
                is.report.note(line);
            }
        }
    }

    void readOut(Character& c) {
        c.deviation.resize(static_cast<std::size_t>(c.jointCount));
        for (std::size_t j = 0; j < static_cast<std::size_t>(c.jointCount); ++j) {
            c.outPos[j] = glm::vec3(jointPos(c, static_cast<int>(j)));
            c.outRot[j] = glm::quat(jointRot(c, static_cast<int>(j)));
            c.deviation[j] = c.outPos[j] - c.p1[j];
        }
    }

    void reset(Island& is, Character& c, double t) {
        for (auto& pin : c.pin) {
            if (pin) dJointDestroy(pin), pin = nullptr;
        }
        for (auto& pin : c.handPin) {
            if (pin) dJointDestroy(pin), pin = nullptr;
        }
        if (c.ballPin) dJointDestroy(c.ballPin), c.ballPin = nullptr;
        c.heldBag = -1;
        for (std::size_t j = 0; j < static_cast<std::size_t>(c.jointCount); ++j) {
            if (c.rides[j]) continue;
            const glm::dquat q(c.r1[j]);
            const glm::dvec3 centre = glm::dvec3(c.p1[j]) + q * c.centre[j];
            dBodySetPosition(c.bodies[j], centre.x, centre.y, centre.z);
            setQuat(c.bodies[j], q);
            dBodySetLinearVel(c.bodies[j], 0, 0, 0);
            dBodySetAngularVel(c.bodies[j], 0, 0, 0);
        }
        ++is.report.resets;
        is.report.note("character " + nameOf(c.index) + ": non-finite physics state at " + std::to_string(t) +
                       " s; put back on its targets");
    }

    void updatePins(Island& is, Character& c, double t) {
        const auto contact = poser.contacts(c.index, t);
        const int feet[2] = {c.roles.leftFoot, c.roles.rightFoot};
        for (std::size_t r = 0; r < opt.pins.size(); ++r) {
            const auto& req = opt.pins[r];
            if (req.character != c.index || req.foot < 0 || req.foot > 1 || t < req.from || t > req.to) continue;
            if (!contact[static_cast<std::size_t>(req.foot)] && !pinRefused[r]) {
                pinRefused[r] = 1;  // one character's request: only its island writes it
                ++is.report.refusedPins;
                is.report.note("character " + nameOf(c.index) + ": " + (req.foot == 0 ? "left" : "right") + " foot pin at " +
                               std::to_string(t) + " s refused: the contacts say that foot is not supported");
            }
        }
        for (int f = 0; f < 2; ++f) {
            auto& pin = c.pin[static_cast<std::size_t>(f)];
            const int foot = feet[f];
            if (foot < 0) continue;
            const glm::dvec3 target(c.p1[static_cast<std::size_t>(foot)]);
            if (!c.controlled || !opt.footPins || !contact[static_cast<std::size_t>(f)]) {
                if (pin) dJointDestroy(pin), pin = nullptr;
                continue;
            }
            if (pin) {
                // Where the capture slides a supported foot (blends, placements)
                // the pin follows it, no faster than kPinSlide per frame.
                // Faster (still under 1 cm) where the hip's target is out of the leg's reach.
                auto& at = c.pinAt[static_cast<std::size_t>(f)];
                const int hip = f == 0 ? c.roles.leftHip : c.roles.rightHip;
                const glm::dvec3 hipTarget(c.p1[static_cast<std::size_t>(hip)]);
                const double leg = c.legLength[static_cast<std::size_t>(f)];
                const glm::dvec3 d = target - at;
                const double off = glm::length(d);
                const glm::dvec3 before = at;
                if (off > kPinTolerance) {
                    const double cap = glm::length(hipTarget - at) > leg ? kPinSlideFast : kPinSlide;
                    at += d * (std::min(off - kPinTolerance, cap) / off);
                    dJointSetBallAnchor2(pin, at.x, at.y, at.z);
                }
                // Another character pressing on this leg (a neighbour's leg
                // in the way of a planted foot): the pin and the contact
                // cannot both hold, so the pin gives way, along the floor,
                // no faster than kPinShove per frame (a shuffled foot),
                // until they part.
                glm::dvec3 push(0.0);
                double deepest = 0;
                const int knee = f == 0 ? c.roles.leftKnee : c.roles.rightKnee;
                for (const auto& [j, w] : limbJoints(c, knee >= 0 ? knee : foot, 1.0f)) {
                    if (j == (f == 0 ? c.roles.leftHip : c.roles.rightHip)) continue;
                    push += c.shove[static_cast<std::size_t>(j)];
                    deepest = std::max(deepest, c.shoveDepth[static_cast<std::size_t>(j)]);
                }
                push.y = 0;
                if (const double len = glm::length(push); len > 1e-9 && deepest > 0.002) {
                    // Slide and shove together move a pin at most kPinStep a
                    // frame: the foot follows its pin with some slip (a
                    // knocked-down victim's sliding fall pressed by the faller:
                    // 0.25 cm), and the sum stays under the 1 cm skate.
                    const double room = std::max(0.0, kPinStep - glm::length(at - before));
                    at += push * (std::min({deepest, kPinShove, room}) / len);
                    dJointSetBallAnchor2(pin, at.x, at.y, at.z);
                }
                // Let go where the pose and the pin are far beyond compatible.
                if (glm::length(hipTarget - at) > leg * kPinReach) {
                    dJointDestroy(pin), pin = nullptr;
                    ++is.report.releasedPins;
                }
                continue;
            }
            // Pinned where it is (a lagging foot then slides to its target
            // like a pin does), unless it is clearly off the floor.
            const glm::dvec3 now = jointPos(c, foot);
            if (target.y > kPinMaxHeight || now.y > kPinMaxHeight) {
                ++is.report.refusedPins;
                continue;
            }
            const auto& other = c.pin[static_cast<std::size_t>(1 - f)];
            if (other && glm::length(now - c.pinAt[static_cast<std::size_t>(1 - f)]) > c.maxFootSpan) {
                ++is.report.refusedPins;
                is.report.note("character " + nameOf(c.index) + ": feet pins " + std::to_string(glm::length(now - c.pinAt[static_cast<std::size_t>(1 - f)])) +
                               " m apart are beyond the legs' reach; the second is not set");
                continue;
            }
            pin = dJointCreateBall(is.world, nullptr);
            dJointAttach(pin, c.bodies[static_cast<std::size_t>(foot)], nullptr);
            dJointSetBallAnchor(pin, now.x, now.y, now.z);
            dJointSetBallParam(pin, dParamERP, 0.95);
            dJointSetBallParam(pin, dParamCFM, 1e-9);
            // The foot lands: it stops there (else the pin catches it a step late).
            dBodySetLinearVel(c.bodies[static_cast<std::size_t>(foot)], 0, 0, 0);
            c.pinAt[static_cast<std::size_t>(f)] = now;
        }
        // The pinned feet's targets are the pins: the control does not pull against them.
        std::fill(c.pinShift.begin(), c.pinShift.end(), glm::vec3(0.0f));
        std::fill(c.pinHeld.begin(), c.pinHeld.end(), std::uint8_t{0});
        std::fill(c.pinLeg.begin(), c.pinLeg.end(), std::uint8_t{0});
        for (int f = 0; f < 2; ++f) {
            if (!c.pin[static_cast<std::size_t>(f)]) continue;
            const int foot = feet[f];
            const int knee = f == 0 ? c.roles.leftKnee : c.roles.rightKnee;
            for (const auto& [j, w] : limbJoints(c, knee >= 0 ? knee : foot, 1.0f)) {
                if (j != (f == 0 ? c.roles.leftHip : c.roles.rightHip)) c.pinLeg[static_cast<std::size_t>(j)] = 1;
            }
            const glm::vec3 shift = glm::vec3(c.pinAt[static_cast<std::size_t>(f)]) - c.p1[static_cast<std::size_t>(foot)];
            for (const auto& [j, w] : limbJoints(c, foot, 0.5f)) {
                c.pinShift[static_cast<std::size_t>(j)] = shift * w;
                c.pinHeld[static_cast<std::size_t>(j)] = w >= 1.0f ? 1 : 0;
            }
        }
        // Where the captured body leaves a pinned foot behind (a blend moving
        // the root), the rest of the body's targets are kept within the leg's
        // reach, so control and pin do not fight.
        glm::dvec3 bodyShift(0.0);
        for (int f = 0; f < 2; ++f) {
            if (!c.pin[static_cast<std::size_t>(f)]) continue;
            const int hip = f == 0 ? c.roles.leftHip : c.roles.rightHip;
            const glm::dvec3 v = glm::dvec3(c.p1[static_cast<std::size_t>(hip)]) + bodyShift - c.pinAt[static_cast<std::size_t>(f)];
            const double len = glm::length(v);
            const double excess = len - kPinComfort * c.legLength[static_cast<std::size_t>(f)];
            if (excess > 0) bodyShift -= v * (excess / len);
        }
        if (glm::length(bodyShift) > 0) {
            for (std::size_t j = 0; j < c.pinShift.size(); ++j) {
                if (!c.pinHeld[j]) c.pinShift[j] += glm::vec3(bodyShift);
            }
        }
        // The pushes are gathered afresh over the coming frame's steps.
        std::fill(c.shove.begin(), c.shove.end(), glm::dvec3(0.0));
        std::fill(c.shoveDepth.begin(), c.shoveDepth.end(), 0.0);
    }

    // A bag's frame at t: origin at its root (an end) at its height, axes
    // side, up and along the bag.
    struct BagFrame {
        glm::dvec3 origin, side, up{0, 1, 0}, along;
        glm::dvec3 toWorld(const glm::dvec3& l) const { return origin + side * l.x + up * l.y + along * l.z; }
        glm::dvec3 toLocal(const glm::dvec3& w) const {
            const glm::dvec3 d = w - origin;
            return {glm::dot(d, side), glm::dot(d, up), glm::dot(d, along)};
        }
    };
    BagFrame bagFrame(int bag, double t) const {
        const auto& sc = scene.characters[static_cast<std::size_t>(bag)];
        const sim::RootXf at = sim::creatureAt(sc, t);
        const glm::vec2 f = sim::headingVector(at.heading);
        BagFrame b;
        b.origin = {at.pos.x, sim::creatureHeightAt(sc, t), at.pos.y};
        b.along = glm::dvec3(f.x, 0.0, f.y);
        b.side = glm::cross(b.up, b.along);
        return b;
    }

    // Hard constraints of a porter's hands on the bag it holds (the luggage
    // chain: the bag is a kinematic creature following the holders' captured
    // hands). A porter holds a bag while its captured hands' midpoint is
    // within kHoldReach of the bag's centre; then each hand is pinned to the
    // bag where it is when the hold starts, and follows the bag every step.
    // A pin the arm cannot reach (farther than the arm's length from its
    // shoulder, as with the feet pinned) is not set, so hands and feet never
    // pin the body incompatibly.
    void updateHandPins(Island& is, Character& c, double t) {
        if (bags.empty() || !c.controlled || !c.roles.hasHands()) return;
        const int hands[2] = {c.roles.leftHand, c.roles.rightHand};
        const glm::dvec3 mid = 0.5 * (glm::dvec3(c.p1[static_cast<std::size_t>(hands[0])]) + glm::dvec3(c.p1[static_cast<std::size_t>(hands[1])]));
        int held = -1;
        for (int b : bags) {
            const BagFrame f = bagFrame(b, t);
            if (glm::length(f.toWorld({0.0, 0.0, 0.5 * static_cast<double>(sim::kBagLength)}) - mid) < kHoldReach) held = b;
        }
        if (held != c.heldBag) {
            for (auto& pin : c.handPin) {
                if (pin) dJointDestroy(pin), pin = nullptr;
            }
            c.gripped = {false, false};
            c.heldBag = held;
        }
        if (held < 0) return;
        // The bodies are where the last frame left them; the targets are this frame's.
        const BagFrame f = bagFrame(held, std::max(0.0, t - 1.0 / opt.fps));
        const BagFrame next = bagFrame(held, t);
        for (int k = 0; k < 2; ++k) {
            auto& pin = c.handPin[static_cast<std::size_t>(k)];
            const int shoulder = k == 0 ? c.roles.leftShoulder : c.roles.rightShoulder;
            const int collar = c.skeleton->parents[static_cast<std::size_t>(shoulder)];
            const glm::dvec3 from = jointPos(c, collar >= 0 ? collar : shoulder);
            // Where the hand took hold in this hold, else where it is now.
            const glm::dvec3 at = c.gripped[static_cast<std::size_t>(k)] ? f.toWorld(c.grip[static_cast<std::size_t>(k)]) : jointPos(c, hands[k]);
            if (glm::length(at - from) > kArmSlack * c.armLength[static_cast<std::size_t>(k)]) {
                if (pin) dJointDestroy(pin), pin = nullptr, ++is.report.releasedPins;
                else ++is.report.refusedPins;
                if (!c.reportedReach) {
                    c.reportedReach = true;
                    is.report.note("character " + nameOf(c.index) + ": a hand pin on the bag at " + std::to_string(t) +
                                   " s is beyond the arm's reach; not held");
                }
                continue;
            }
            if (!pin) {
                pin = dJointCreateBall(is.world, nullptr);
                dJointAttach(pin, c.bodies[static_cast<std::size_t>(hands[k])], nullptr);
                dJointSetBallAnchor(pin, at.x, at.y, at.z);
                dJointSetBallParam(pin, dParamERP, 0.95);
                dJointSetBallParam(pin, dParamCFM, 1e-9);
                if (!c.gripped[static_cast<std::size_t>(k)]) c.grip[static_cast<std::size_t>(k)] = f.toLocal(at);
                c.gripped[static_cast<std::size_t>(k)] = true;
            }
            // The hand's target is its grip, so control does not pull against the pin.
            c.pinShift[static_cast<std::size_t>(hands[k])] =
                glm::vec3(next.toWorld(c.grip[static_cast<std::size_t>(k)])) - c.p1[static_cast<std::size_t>(hands[k])];
        }
    }

    // Where a ball carrier's hand holds its ball at t (the ball as keyed).
    glm::dvec3 ballGripAt(int ball, double t) const { return glm::dvec3(sim::ballGripAt(scene.characters[static_cast<std::size_t>(ball)], t)); }

    // A football carrier's arm holds the ball (issue 25): a soft constraint,
    // the carrying hand's target moved onto the ball's grip (the ball is keyed
    // from the captured hand, so this is the captured hand up to the keys'
    // interpolation, and stays there while the body is pushed about); with
    // Options::handPins also a hard pin of the hand on the grip, moved with
    // the ball every step (moveHandPins), let go like the bag's pins where
    // the arm cannot reach it.
    void updateBallHold(Island& is, Character& c, double t) {
        if (c.heldBall < 0 || !c.controlled || !c.roles.hasHands()) return;
        const int k = scene.characters[static_cast<std::size_t>(c.heldBall)].hand == 0 ? 0 : 1;
        const int hand = k == 0 ? c.roles.leftHand : c.roles.rightHand;
        const glm::dvec3 grip = ballGripAt(c.heldBall, t);
        if (!finite(glm::vec3(grip))) return;
        c.pinShift[static_cast<std::size_t>(hand)] = glm::vec3(grip) - c.p1[static_cast<std::size_t>(hand)];
        if (!opt.handPins) return;
        const int shoulder = k == 0 ? c.roles.leftShoulder : c.roles.rightShoulder;
        if (shoulder < 0) return;
        const int collar = c.skeleton->parents[static_cast<std::size_t>(shoulder)];
        const glm::dvec3 from = jointPos(c, collar >= 0 ? collar : shoulder);
        if (glm::length(grip - from) > kArmSlack * c.armLength[static_cast<std::size_t>(k)]) {
            if (c.ballPin) dJointDestroy(c.ballPin), c.ballPin = nullptr, ++is.report.releasedPins;
            else ++is.report.refusedPins;
            if (!c.reportedReach) {
                c.reportedReach = true;
                is.report.note("character " + nameOf(c.index) + ": a hand pin on the ball at " + std::to_string(t) +
                               " s is beyond the arm's reach; not held");
            }
            return;
        }
        if (!c.ballPin) {
            // Pinned where the hand is; the pin moves onto the grip with the ball's next step.
            const glm::dvec3 at = jointPos(c, hand);
            c.ballPin = dJointCreateBall(is.world, nullptr);
            dJointAttach(c.ballPin, c.bodies[static_cast<std::size_t>(hand)], nullptr);
            dJointSetBallAnchor(c.ballPin, at.x, at.y, at.z);
            dJointSetBallParam(c.ballPin, dParamERP, 0.95);
            dJointSetBallParam(c.ballPin, dParamCFM, 1e-9);
        }
    }

    // Moves the hand pins with their bag (or ball) to where it is at the end of a step.
    void moveHandPins(Character& c, double t) {
        if (c.ballPin) {
            const glm::dvec3 at = ballGripAt(c.heldBall, t);
            dJointSetBallAnchor2(c.ballPin, at.x, at.y, at.z);
        }
        if (c.heldBag < 0) return;
        const BagFrame f = bagFrame(c.heldBag, t);
        for (int k = 0; k < 2; ++k) {
            const dJointID pin = c.handPin[static_cast<std::size_t>(k)];
            if (!pin) continue;
            const glm::dvec3 at = f.toWorld(c.grip[static_cast<std::size_t>(k)]);
            dJointSetBallAnchor2(pin, at.x, at.y, at.z);
        }
    }

    // The frame's aims of every body (the parts of control() that do not
    // change between substeps).
    void aim(Character& c) const {
        c.aims.resize(static_cast<std::size_t>(c.jointCount));
        for (std::size_t j = 0; j < static_cast<std::size_t>(c.jointCount); ++j) {
            Aim& a = c.aims[j];
            a.q0 = glm::dquat(c.r0[j]), a.q1 = glm::dquat(c.r1[j]);
            a.c0 = glm::dvec3(c.p0[j]) + a.q0 * c.centre[j];
            a.c1 = glm::dvec3(c.p1[j]) + a.q1 * c.centre[j];
            const glm::dvec3 c2 = glm::dvec3(c.p2[j]) + glm::dquat(c.r2[j]) * c.centre[j];
            // The captured motion's velocity and acceleration, fed forward so
            // the PD terms only correct the error (no lag on fast blows).
            a.v01 = (a.c1 - a.c0) * opt.fps, a.v12 = (c2 - a.c1) * opt.fps;
            a.acc = (a.v12 - a.v01) * opt.fps;
            a.spin = rotationVector(a.q1 * glm::conjugate(a.q0)) * opt.fps;
        }
    }

    void control(Island& is, Character& c, double alpha) {
        const double w = kTwoPi * opt.frequency, kd = 2.0 * opt.dampingRatio * w;
        const double wr = kTwoPi * opt.angularFrequency, kdr = 2.0 * opt.dampingRatio * wr;
        for (std::size_t j = 0; j < static_cast<std::size_t>(c.jointCount); ++j) {
            const dBodyID b = c.bodies[j];
            if (!b) continue;  // rides on its parent
            const Aim& a = c.aims[j];
            const glm::dvec3 &c0 = a.c0, &c1 = a.c1, &v01 = a.v01, &v12 = a.v12;
            const glm::dquat &q0 = a.q0, &q1 = a.q1;
            glm::dvec3 target = c0 + (c1 - c0) * alpha;
            glm::dvec3 targetVel = v01 + (v12 - v01) * (alpha - 0.5);
            glm::dvec3 targetAcc = a.acc;
            if (c.pinHeld[j]) {
                target = c1 + glm::dvec3(c.pinShift[j]);
                targetVel = targetAcc = glm::dvec3(0.0);
            } else {
                target += glm::dvec3(c.pinShift[j]);
            }
            // A body touching another character yields, and so does the rest
            // of its limb (or trunk): the control of the thigh and shin behind
            // a touching foot would otherwise drive the foot through the
            // contact (the chase's swinging foot into a neighbour's shin).
            // A limb pulled onto a body (a blow, a catch, a parry) is meant to
            // meet it: only its touching bodies yield.
            const bool yields = c.touched[j] || (c.groupTouched[c.group[j]] && c.torqueScale[j] >= 1.0f);
            const double m = c.mass[j] * (yields ? kContactYield : (c.touching ? kBodyYield : 1.0));
            glm::dvec3 f = m * (w * w * (target - vecOf(dBodyGetPosition(b))) + kd * (targetVel - vecOf(dBodyGetLinearVel(b))) +
                                targetAcc);
            const double fmax = c.mass[j] * opt.maxAcceleration;
            if (const double len = glm::length(f); len > fmax) f *= fmax / len, ++is.report.cappedForces;
            dBodyAddForce(b, f.x, f.y, f.z);

            const glm::dquat qt = glm::slerp(q0, q1, alpha);
            const glm::dvec3 err = rotationVector(qt * glm::conjugate(quatOf(dBodyGetQuaternion(b))));
            const glm::dvec3& targetSpin = a.spin;
            const double I = c.inertia[j] * static_cast<double>(c.torqueScale[j]);
            glm::dvec3 torque = I * (wr * wr * err + kdr * (targetSpin - vecOf(dBodyGetAngularVel(b))));
            const double tmax = c.inertia[j] * opt.maxAngularAcceleration;
            if (const double len = glm::length(torque); len > tmax) torque *= tmax / len, ++is.report.cappedForces;
            dBodyAddTorque(b, torque.x, torque.y, torque.z);
        }
    }

    // Collision boxes where the metrics see them: the segment boxes of the
    // current joint positions, carried by their bodies.
    void syncGeoms(Character& c) {
        std::vector<glm::vec3>& at = c.scratch;
        at.resize(static_cast<std::size_t>(c.jointCount));
        for (int j = 0; j < c.jointCount; ++j) at[static_cast<std::size_t>(j)] = glm::vec3(jointPos(c, j));
        const auto boxes = sim::segmentBoxes(at, c.roles);
        for (auto& piece : c.pieces) {
            const Obb& box = boxes[static_cast<std::size_t>(piece.segment)];
            const glm::vec3 axis = box.axes[0];
            // Along the axis, from the box's centre: the piece runs from its
            // body's joint to the next body's joint (the box's ends for the
            // first and last pieces).
            float u0 = -box.half.x, u1 = box.half.x;
            if (!piece.first) u0 = std::clamp(glm::dot(at[static_cast<std::size_t>(piece.body)] - box.centre, axis), -box.half.x, box.half.x);
            if (piece.next >= 0) u1 = std::clamp(glm::dot(at[static_cast<std::size_t>(piece.next)] - box.centre, axis), -box.half.x, box.half.x);
            if (u1 < u0 + 0.01f) u1 = std::min(u0 + 0.01f, box.half.x), u0 = u1 - 0.01f;
            const float halfLength = 0.5f * (u1 - u0);
            const glm::vec3 centre = box.centre + axis * (0.5f * (u0 + u1));
            // Grown by the contact margin: contacts are found before the boxes
            // meet (see collide()).
            const auto grow = static_cast<float>(kContactMargin);
            dGeomBoxSetLengths(piece.geom, 2.0 * static_cast<double>(halfLength + grow), 2.0 * static_cast<double>(box.half.y + grow),
                               2.0 * static_cast<double>(box.half.z + grow));
            piece.radius = glm::length(glm::vec3(halfLength, box.half.y, box.half.z) + grow);
            dGeomSetOffsetWorldPosition(piece.geom, centre.x, centre.y, centre.z);
            dMatrix3 R;
            for (int r = 0; r < 3; ++r) {
                for (int k = 0; k < 3; ++k) R[r * 4 + k] = static_cast<double>(box.axes[k][r]);
                R[r * 4 + 3] = 0;
            }
            dGeomSetOffsetWorldRotation(piece.geom, R);
        }
    }

    // Signed distance of two collision pieces' real boxes (the geoms less the margin).
    static double realDistance(dGeomID a, dGeomID b) {
        auto box = [](dGeomID g) {
            Obb o;
            const dReal* c = dGeomGetPosition(g);
            const dReal* R = dGeomGetRotation(g);
            dVector3 len;
            dGeomBoxGetLengths(g, len);
            o.centre = glm::vec3(glm::dvec3(c[0], c[1], c[2]));
            for (int k = 0; k < 3; ++k) {
                o.axes[k] = glm::vec3(glm::dvec3(R[k], R[4 + k], R[8 + k]));
                o.half[k] = static_cast<float>(std::max(0.0, 0.5 * len[k] - kContactMargin));
            }
            return o;
        };
        return sim::boxSignedDistance(box(a), box(b));
    }

    // skipCalm: the second substep of a pair, where the calm characters are
    // a step ahead (they took both substeps at once) and are not collided.
    void collide(Island& is, bool skipCalm = false) {
        is.contactsThisStep = 0;
        is.deepest = 0;
        for (int m : is.members) {
            auto& c = chars[static_cast<std::size_t>(m)];
            if (!c.created || (skipCalm && c.calm)) continue;
            syncGeoms(c);
            std::fill(c.touched.begin(), c.touched.end(), std::uint8_t{0});
            c.groupTouched.fill(0);
            c.touching = false;
            c.linked = false;
        }
        dContactGeom found[4];
        // Bodies of touching segments yield: their control is softened so the
        // contact, not the captured pose, decides where they meet.
        // Speculative contacts: the boxes are grown by kContactMargin, so a
        // contact is found while the real boxes are still up to a margin
        // apart on each side. Such a contact has no friction and lets the
        // bodies close the gap in this step and no further (the normal
        // velocity may approach at gap / h), so fast limbs (a diving
        // tackler's foot at 6 m/s moves 2.5 cm a step) stop at the surface
        // instead of sinking into it before a contact exists.
        auto add = [&](dGeomID a, dGeomID b, Character* ca, int ba, Character* cb, int bb) {
            const int k = dCollide(a, b, 4, found, sizeof(dContactGeom));
            if (k > 0 && ca && cb) ca->linked = cb->linked = true;
            const double grown = cb ? 2.0 * kContactMargin : kContactMargin;  // the floor is not grown
            // Apart, the real boxes' gap bounds the contacts' depth: a box
            // grown by the margin along its axes reaches farther at its edges
            // and corners (edge to edge 2 x 3 cm x sqrt 2), so two edges 2 cm
            // apart counted as touching and stopped there (domino blows 1-2 cm
            // off the surface, their control yielding before they met). The
            // gap is counted kGapSlack short: bodies stop just before they
            // meet rather than exactly at it (forearms sank 2.2 cm into a
            // torso at the luggage chain's hand-overs without the slack).
            const double real = k > 0 && cb ? realDistance(a, b) : -1.0;
            const double apart = real > 0 ? std::max(0.0, real - kGapSlack) : -1.0;
            bool touch = false;
            for (int i = 0; i < k; ++i) {
                dContact contact{};
                contact.surface.mode = dContactSoftCFM | dContactSoftERP | dContactApprox1;
                contact.surface.mu = 0.6;
                contact.surface.soft_erp = 0.5;
                contact.surface.soft_cfm = 1e-7;
                contact.geom = found[i];
                // Against a pinned foot or shin the contact is soft: the pin
                // and a body pressing on the leg cannot both hold (a faller
                // lying across a knocked-down victim's planted shin), and with
                // two stiff constraints the solver broke the pin (the foot
                // slid 1-1.5 cm in a frame). The pressing body sinks in a
                // little while the pin gives way at kPinShove a frame.
                if ((ca && ca->pinLeg[static_cast<std::size_t>(ba)]) || (cb && cb->pinLeg[static_cast<std::size_t>(bb)])) {
                    contact.surface.soft_erp = kPinLegErp;
                    contact.surface.soft_cfm = kPinLegCfm;
                }
                const double depth = apart >= 0 ? std::min(found[i].depth - grown, -apart) : found[i].depth - grown;  // of the real boxes; negative: a gap
                if (depth < 0) {
                    contact.surface.mu = 0;
                    contact.surface.mode |= dContactMotionN;
                    contact.surface.motionN = depth / h;
                    contact.geom.depth = 0;
                } else {
                    contact.geom.depth = depth;
                }
                touch = touch || depth > -kTouchGap;
                dJointID joint = dJointCreateContact(is.world, is.contacts, &contact);
                if (ca) ++is.contactsThisStep;
                if (ca && cb) is.deepest = std::max(is.deepest, depth);
                dJointAttach(joint, dGeomGetBody(a), dGeomGetBody(b));
                if (!ca || !cb || depth <= 0) continue;
                // How the contact pushes each side (away from the other's box), for the pins.
                glm::dvec3 n = vecOf(found[i].normal);
                if (glm::dot(n, vecOf(dGeomGetPosition(a)) - vecOf(dGeomGetPosition(b))) < 0) n = -n;
                const auto ja = static_cast<std::size_t>(ba), jb = static_cast<std::size_t>(bb);
                ca->shove[ja] += n * depth, ca->shoveDepth[ja] = std::max(ca->shoveDepth[ja], depth);
                cb->shove[jb] -= n * depth, cb->shoveDepth[jb] = std::max(cb->shoveDepth[jb], depth);
            }
            if (touch && ca) ca->touched[static_cast<std::size_t>(ba)] = 1, ca->groupTouched[ca->group[static_cast<std::size_t>(ba)]] = 1, ca->touching = true;
            if (touch && cb) cb->touched[static_cast<std::size_t>(bb)] = 1, cb->groupTouched[cb->group[static_cast<std::size_t>(bb)]] = 1, cb->touching = true;
        };
        for (std::size_t x = 0; x < is.members.size(); ++x) {
            auto& a = chars[static_cast<std::size_t>(is.members[x])];
            if (!a.created || (skipCalm && a.calm)) continue;
            if (!a.controlled) {
                for (const auto& piece : a.pieces) add(piece.geom, is.floor, nullptr, 0, nullptr, 0);
            }
            if (!opt.collisions) continue;
            const glm::dvec3 pa = vecOf(dBodyGetPosition(a.bodies[static_cast<std::size_t>(a.roles.pelvis)]));
            for (std::size_t y = x + 1; y < is.members.size(); ++y) {
                auto& b = chars[static_cast<std::size_t>(is.members[y])];
                if (!b.created || (skipCalm && b.calm)) continue;
                const glm::dvec3 pb = vecOf(dBodyGetPosition(b.bodies[static_cast<std::size_t>(b.roles.pelvis)]));
                if (glm::length(pa - pb) > 2.5) continue;
                for (const auto& qa : a.pieces) {
                    const glm::dvec3 ca = vecOf(dGeomGetPosition(qa.geom));
                    for (const auto& qb : b.pieces) {
                        const glm::dvec3 cb = vecOf(dGeomGetPosition(qb.geom));
                        if (glm::length(ca - cb) > static_cast<double>(qa.radius + qb.radius)) continue;
                        add(qa.geom, qb.geom, &a, qa.body, &b, qb.body);
                    }
                }
            }
        }
    }

    void pushBlows(Island& is, std::int64_t step) {
        for (int b : is.blows) {
            const Blow& blow = blows[static_cast<std::size_t>(b)];
            if (blow.step != step) continue;
            auto& a = chars[static_cast<std::size_t>(blow.attacker)];
            auto& d = chars[static_cast<std::size_t>(blow.defender)];
            if (!a.created || !d.created) continue;
            const glm::dvec3 v = vecOf(dBodyGetLinearVel(a.bodies[static_cast<std::size_t>(blow.tipJoint)]));
            const glm::dvec3 impulse = opt.hitForce * blow.scale * blow.mass * v;
            if (!std::isfinite(impulse.x + impulse.y + impulse.z)) continue;
            const glm::dvec3 f = impulse / h;  // over one step
            dBodyAddForce(d.bodies[static_cast<std::size_t>(blow.targetJoint)], f.x, f.y, f.z);
        }
    }

    // One physics step of the island's world by h with opt.solver. Hybrid:
    // the characters joined to another by a contact this step are solved by
    // QuickStep, the rest by the direct solver, each set while the other's
    // bodies are disabled (ODE steps only enabled bodies; no joint links the
    // two sets: ball joints and pins stay within a character or go to the
    // world, contacts between characters are all in the first set).
    // Calm characters (Options::calmPairs) take the first substep of a pair
    // as one direct step of 2h, alone (pairStart), and sit the second one
    // out, disabled (they have no contact: nothing links them to the others).
    void solve(Island& is, std::uint32_t seed, bool pairStart = false) {
        // Per member: 0 QuickStep by h, 1 direct by h, 2 direct by 2h, 3 not stepped.
        int count[4] = {0, 0, 0, 0};
        is.kind.resize(is.members.size());
        for (std::size_t i = 0; i < is.members.size(); ++i) {
            const auto& c = chars[static_cast<std::size_t>(is.members[i])];
            int k = 1;
            if (!c.created) k = 1;  // no bodies
            else if (c.calm) k = pairStart ? 2 : 3;
            else if (opt.solver == Solver::Iterative || (opt.solver == Solver::Hybrid && c.linked)) k = 0;
            is.kind[i] = static_cast<std::uint8_t>(k);
            if (c.created) ++count[k];
        }
        is.report.iterativeSteps += count[0];
        is.report.directSteps += count[1] + 2 * count[2];
        is.report.calmSteps += count[2];
        const int sets = (count[0] > 0) + (count[1] > 0) + (count[2] > 0);
        if (sets <= 1 && count[3] == 0) {
            if (count[2] > 0) seededStep(is.world, 2 * h, seed, Solver::Direct);
            else seededStep(is.world, h, seed, count[0] > 0 ? Solver::Iterative : Solver::Direct);
            return;
        }
        auto only = [&](int k) {  // enable the bodies of set k, disable the others'
            for (std::size_t i = 0; i < is.members.size(); ++i) {
                const auto& c = chars[static_cast<std::size_t>(is.members[i])];
                if (!c.created) continue;
                const bool on = is.kind[i] == k;
                for (dBodyID b : c.bodies) {
                    if (b && (dBodyIsEnabled(b) != 0) != on) on ? dBodyEnable(b) : dBodyDisable(b);
                }
            }
        };
        if (count[1] > 0) only(1), seededStep(is.world, h, seed, Solver::Direct);
        if (count[0] > 0) only(0), seededStep(is.world, h, seed, Solver::Iterative);
        if (count[2] > 0) only(2), seededStep(is.world, 2 * h, seed, Solver::Direct);
        for (std::size_t i = 0; i < is.members.size(); ++i) {
            const auto& c = chars[static_cast<std::size_t>(is.members[i])];
            if (!c.created) continue;
            for (dBodyID b : c.bodies) {
                if (b && !dBodyIsEnabled(b)) dBodyEnable(b);
            }
        }
    }

    // Calm pairs only where a step of 2h keeps the PD control stable (as
    // checkOptions() asks of h).
    bool calmPairs() const {
        const double h2 = 2.0 / (opt.fps * opt.substeps);
        return opt.calmPairs && opt.solver != Solver::Iterative && opt.frequency * kTwoPi * h2 < 1.0 &&
               opt.angularFrequency * kTwoPi * h2 < 1.0;
    }

    void markCalm(Island& is, std::int64_t stepIndex) {
        for (int m : is.members) {
            auto& c = chars[static_cast<std::size_t>(m)];
            c.calm = c.created && c.controlled && !c.linked && !c.handPin[0] && !c.handPin[1] && !c.ballPin;
        }
        for (int b : is.blows) {
            const Blow& blow = blows[static_cast<std::size_t>(b)];
            if (blow.step == stepIndex || blow.step == stepIndex + 1) chars[static_cast<std::size_t>(blow.defender)].calm = false;
        }
    }

    void clearCalm(Island& is) {
        for (int m : is.members) chars[static_cast<std::size_t>(m)].calm = false;
    }

    bool finiteState(const Character& c) const {
        for (dBodyID b : c.bodies) {
            if (!b) continue;
            const dReal* p = dBodyGetPosition(b);
            const dReal* q = dBodyGetQuaternion(b);
            const dReal* v = dBodyGetLinearVel(b);
            const dReal* w = dBodyGetAngularVel(b);
            for (int k = 0; k < 3; ++k) {
                if (!std::isfinite(p[k]) || !std::isfinite(v[k]) || !std::isfinite(w[k])) return false;
            }
            if (!std::isfinite(q[0] + q[1] + q[2] + q[3])) return false;
        }
        return true;
    }

    void stepIsland(Island& is, int f) {
        dAllocateODEDataForThread(dAllocateMaskAll);
        const double t = f / opt.fps;
        for (int m : is.members) {
            auto& c = chars[static_cast<std::size_t>(m)];
            if (f == 0) {
                targets(is, c, t, c.p1, c.r1);
                c.p0 = c.p1, c.r0 = c.r1;
            } else {
                c.p0.swap(c.p1), c.r0.swap(c.r1);
                c.p1.swap(c.p2), c.r1.swap(c.r2);
            }
            targets(is, c, (f + 1) / opt.fps, c.p2, c.r2);
        }
        bool any = false;
        for (int m : is.members) {
            auto& c = chars[static_cast<std::size_t>(m)];
            if (!c.created) continue;
            any = true;
            updatePins(is, c, t);
            if (opt.handPins) updateHandPins(is, c, t);
            updateBallHold(is, c, t);
        }
        if (any && f > 0) {
            for (int m : is.members) {
                auto& c = chars[static_cast<std::size_t>(m)];
                if (c.created && c.controlled) aim(c);
            }
            for (int s = 0; s < opt.substeps; ++s) {
                const double alpha = static_cast<double>(s + 1) / opt.substeps;
                is.time = (f - 1) / opt.fps + s * h;
                const std::int64_t stepIndex = static_cast<std::int64_t>(f - 1) * opt.substeps + s;
                // Calm pairs: at the first substep of a pair, the characters
                // without any contact with another character (not even a
                // speculative one: their grown boxes are apart), without a
                // blow on them in either substep and without hand pins take
                // both substeps as one direct step of 2h; at the second they
                // are neither collided, controlled nor stepped.
                const bool pairStart = calmPairs() && s % 2 == 0 && s + 1 < opt.substeps;
                const bool pairEnd = calmPairs() && s % 2 == 1;
                collide(is, pairEnd);
                if (pairStart) markCalm(is, stepIndex);
                for (int m : is.members) {
                    auto& c = chars[static_cast<std::size_t>(m)];
                    if (c.calm && pairEnd) continue;
                    // A calm character's step of 2h aims, as every step, at
                    // the targets h ahead (not 2h): the PD control then keeps
                    // the bodies h ahead of the captured motion, as with two
                    // steps of h (aiming 2h ahead they ran twice as far ahead,
                    // the chase's mean deviation 0.89 -> 1.39 cm).
                    if (c.created && c.controlled) control(is, c, alpha);
                    if (c.created) moveHandPins(c, is.time + h);
                }
                pushBlows(is, stepIndex);
                // Each step draws QuickStep's constraint order from its own
                // seed, so the result does not depend on threads or on what
                // ran before (see StepRandom).
                const unsigned long seed = static_cast<unsigned long>(is.index) * 1000003ul +
                                           static_cast<unsigned long>(f) * 64ul + static_cast<unsigned long>(s);
                dWorldSetQuickStepNumIterations(is.world, is.contactsThisStep > 0 ? opt.iterations : opt.freeIterations);
                solve(is, static_cast<std::uint32_t>(seed), pairStart);
                dJointGroupEmpty(is.contacts);
                if (pairEnd) clearCalm(is);
            }
            clearCalm(is);
        }
        const int overlaps = is.report.initialOverlaps;
        for (int m : is.members) {
            auto& c = chars[static_cast<std::size_t>(m)];
            if (c.created) {
                if (!finiteState(c)) reset(is, c, t);
                readOut(c);
            } else if (scene.present(c.index, t)) {
                create(is, c);
                readOut(c);
            } else {
                c.outPos = c.p1, c.outRot = c.r1;
            }
        }
        if (is.report.initialOverlaps > overlaps) settle(is, f);
    }

    // Characters that appear inside one another (a composed crowd placed
    // overlapping) are separated before their first frame is shown: contacts
    // alone (no gravity, no control) push the bodies apart, at most
    // kSettleSteps steps, until no contact is deeper than kSettleDepth; then
    // every body gets its velocity back.
    void settle(Island& is, int f) {
        std::vector<std::array<dReal, 6>> velocity;
        for (int m : is.members) {
            for (dBodyID b : chars[static_cast<std::size_t>(m)].bodies) {
                if (!b) continue;  // rides on its parent
                const dReal* v = dBodyGetLinearVel(b);
                const dReal* w = dBodyGetAngularVel(b);
                velocity.push_back({v[0], v[1], v[2], w[0], w[1], w[2]});
                dBodySetLinearVel(b, 0, 0, 0);
                dBodySetAngularVel(b, 0, 0, 0);
            }
        }
        dWorldSetGravity(is.world, 0, 0, 0);
        int steps = 0;
        for (; steps < kSettleSteps; ++steps) {
            collide(is);
            if (is.deepest <= kSettleDepth) {
                dJointGroupEmpty(is.contacts);
                break;
            }
            const auto seed = static_cast<std::uint32_t>(static_cast<unsigned long>(is.index) * 1000003ul + static_cast<unsigned long>(f) * 64ul + 63ul - static_cast<unsigned long>(steps));
            solve(is, seed);
            dJointGroupEmpty(is.contacts);
        }
        dWorldSetGravity(is.world, 0, -9.81, 0);
        std::size_t k = 0;
        for (int m : is.members) {
            auto& c = chars[static_cast<std::size_t>(m)];
            for (dBodyID b : c.bodies) {
                if (!b) continue;  // rides on its parent
                const auto& v = velocity[k++];
                dBodySetLinearVel(b, v[0], v[1], v[2]);
                dBodySetAngularVel(b, v[3], v[4], v[5]);
            }
            std::fill(c.shove.begin(), c.shove.end(), glm::dvec3(0.0));
            std::fill(c.shoveDepth.begin(), c.shoveDepth.end(), 0.0);
            if (c.created) readOut(c);
        }
        char line[160];
        std::snprintf(line, sizeof line, "frame %d: starting overlaps separated in %d contact-only steps (deepest left %.1f cm)", f, steps,
                      100.0 * is.deepest);
        is.report.note(line);
    }

    void step() {
        ++frame;
        if (opt.parallel && islands.size() > 1) {
            tbb::parallel_for(std::size_t{0}, islands.size(), [&](std::size_t i) { stepIsland(islands[i], frame); });
        } else {
            for (auto& is : islands) stepIsland(is, frame);
        }
    }

    Report merged() const {
        Report r = report;
        for (const auto& is : islands) {
            r.nonFiniteTargets += is.report.nonFiniteTargets;
            r.refusedPins += is.report.refusedPins;
            r.releasedPins += is.report.releasedPins;
            r.cappedForces += is.report.cappedForces;
            r.resets += is.report.resets;
            r.initialOverlaps += is.report.initialOverlaps;
            r.directSteps += is.report.directSteps;
            r.iterativeSteps += is.report.iterativeSteps;
            r.calmSteps += is.report.calmSteps;
            for (const auto& n : is.report.notes) r.note(n);
        }
        return r;
    }
};

Simulator::Simulator(const sim::Scene& scene, const sim::ActionLibrary& lib, const Options& options)
    : impl_(std::make_unique<Impl>(scene, lib, options)) {}
Simulator::~Simulator() = default;
void Simulator::step() {
    if (impl_->frame + 1 < impl_->frames) impl_->step();
}
int Simulator::frame() const { return impl_->frame; }
int Simulator::frameCount() const { return impl_->frames; }
std::span<const glm::vec3> Simulator::positions(int character) const {
    const auto& c = impl_->chars[static_cast<std::size_t>(character)];
    if (!c.skeleton) return {};
    return c.outPos;
}
std::span<const glm::quat> Simulator::rotations(int character) const {
    const auto& c = impl_->chars[static_cast<std::size_t>(character)];
    if (!c.skeleton) return {};
    return c.outRot;
}
const Report& Simulator::report() const {
    impl_->mergedReport = impl_->merged();
    return impl_->mergedReport;
}
int Simulator::islands() const { return static_cast<int>(impl_->islands.size()); }

namespace {

Status checkOptions(const sim::Scene& scene, const Options& o) {
    auto bad = [](const std::string& field, const std::string& why) { return makeError("posture options: " + field + " " + why); };
    if (!(o.fps >= 1 && o.fps <= 1000)) return bad("fps", "must be in [1, 1000]");
    if (o.substeps < 1 || o.substeps > 64) return bad("substeps", "must be in [1, 64]");
    if (o.solver != Solver::Direct && o.solver != Solver::Iterative && o.solver != Solver::Hybrid) {
        return bad("solver", "must be Direct, Iterative or Hybrid");
    }
    if (o.iterations < 1 || o.iterations > 500) return bad("iterations", "must be in [1, 500]");
    if (o.freeIterations < 1 || o.freeIterations > 500) return bad("freeIterations", "must be in [1, 500]");
    if (!(o.frequency > 0 && o.frequency * kTwoPi / (o.fps * o.substeps) < 1.0)) {
        return bad("frequency", "must be positive and below fps * substeps / (2 pi) (an unstable step otherwise)");
    }
    if (!(o.angularFrequency > 0 && o.angularFrequency * kTwoPi / (o.fps * o.substeps) < 1.0)) {
        return bad("angularFrequency", "must be positive and below fps * substeps / (2 pi)");
    }
    if (!(o.dampingRatio >= 0 && o.dampingRatio <= 4)) return bad("dampingRatio", "must be in [0, 4]");
    if (!(o.maxAcceleration > 0) || !(o.maxAngularAcceleration > 0)) return bad("maxAcceleration", "caps must be positive");
    if (!(o.hitLead > 0) || !(o.hitTail > 0) || !(o.catchLead > 0)) return bad("hitLead", "ease times must be positive");
    if (!(o.islandReach > 0)) return bad("islandReach", "must be positive");
    if (o.ragdoll.size() > scene.characters.size()) return bad("ragdoll", "names more characters than the scene has");
    if (!(scene.duration >= 0) || !std::isfinite(scene.duration)) return makeError("posture: the scene's duration is not a finite time");
    if (scene.duration * o.fps > 10'000'000) return makeError("posture: the scene is too long for this frame rate");
    return {};
}

// The balls held in the scene, frame by frame at the holder's physics hand
// and forearm, so a ball never floats away from the arm that holds it. A
// ball whose holder is not simulated stays as keyed.
void heldBalls(const sim::Scene& scene, const sim::ActionLibrary& lib, Frames& out) {
    const auto n = scene.characters.size();
    out.ballPositions.assign(n, {});
    out.ballRotations.assign(n, {});
    for (std::size_t b = 0; b < n; ++b) {
        const auto& ball = scene.characters[b];
        const int h = ball.holder;
        if (ball.body != "ball" || ball.keys.empty() || h < 0 || static_cast<std::size_t>(h) >= n || !out.world.has(h)) continue;
        const auto& track = scene.characters[static_cast<std::size_t>(h)].track;
        if (track.empty()) continue;
        const auto& joints = lib.motion(lib.actions()[static_cast<std::size_t>(track.front().action)].motion).joints;
        const int hand = ball.hand == 0 ? joints.leftHand : joints.rightHand;
        const int elbow = ball.hand == 0 ? joints.leftElbow : joints.rightElbow;
        if (hand < 0 || elbow < 0) continue;
        const auto frames = static_cast<std::size_t>(out.world.frames);
        auto& pos = out.ballPositions[b];
        auto& rot = out.ballRotations[b];
        pos.reserve(frames), rot.reserve(frames);
        for (int f = 0; f < out.world.frames; ++f) {
            const auto at = out.world.at(h, f);
            const sim::RootKey k = sim::ballKey(f / out.world.fps, at[static_cast<std::size_t>(hand)], at[static_cast<std::size_t>(elbow)]);
            pos.emplace_back(k.at.pos.x, k.height, k.at.pos.y);
            rot.push_back(sim::creatureRotation(k.at.heading, k.pitch));
        }
    }
}

}  // namespace

Result<Frames> simulate(const sim::Scene& scene, const sim::ActionLibrary& lib, const Options& options,
                        const ProgressFn& progress) {
    if (auto st = checkOptions(scene, options); !st) return st.error();
    Simulator s(scene, lib, options);
    Frames out;
    const auto n = scene.characters.size();
    out.world.fps = options.fps;
    out.world.frames = s.frameCount();
    out.world.joints.resize(n);
    out.world.jointCount.assign(n, 0);
    out.rotations.resize(n);
    for (std::size_t c = 0; c < n; ++c) {
        const auto jc = s.positions(static_cast<int>(c)).size();
        out.world.jointCount[c] = static_cast<int>(jc);
        out.world.joints[c].reserve(jc * static_cast<std::size_t>(s.frameCount()));
        out.rotations[c].reserve(jc * static_cast<std::size_t>(s.frameCount()));
    }
    for (int f = 0; f < s.frameCount(); ++f) {
        if (f % 16 == 0 && !reportProgress(progress, static_cast<double>(f) / s.frameCount(), "posture")) {
            return cancelled("posture");
        }
        s.step();
        for (std::size_t c = 0; c < n; ++c) {
            const auto p = s.positions(static_cast<int>(c));
            const auto r = s.rotations(static_cast<int>(c));
            out.world.joints[c].insert(out.world.joints[c].end(), p.begin(), p.end());
            out.rotations[c].insert(out.rotations[c].end(), r.begin(), r.end());
        }
    }
    out.report = s.report();
    out.islands = s.islands();
    heldBalls(scene, lib, out);
    return out;
}

Result<sim::JointTracks> tracks(Mode mode, const sim::Scene& scene, const sim::ActionLibrary& lib, const Options& options) {
    if (mode == Mode::Kinematic) return sim::kinematicTracks(scene, lib, options.fps);
    auto frames = simulate(scene, lib, options);
    if (!frames) return frames.error();
    return std::move(frames->world);
}

struct ScenePoses::Impl {
    Mode mode = Mode::Kinematic;
    const sim::Scene& scene;
    sim::ScenePoser poser;
    Frames frames;  // physics mode only

    Impl(Mode m, const sim::Scene& s, const sim::ActionLibrary& lib) : mode(m), scene(s), poser(s, lib) {}

    // A held ball that follows its holder's physics hand (Frames::ballPositions).
    bool ballFollows(int c) const {
        return mode == Mode::Physics && c >= 0 && static_cast<std::size_t>(c) < frames.ballPositions.size() &&
               !frames.ballPositions[static_cast<std::size_t>(c)].empty();
    }
    bool simulated(int c) const {
        return mode == Mode::Physics && c >= 0 && static_cast<std::size_t>(c) < frames.world.joints.size() &&
               frames.world.jointCount[static_cast<std::size_t>(c)] > 0 && frames.world.frames > 0;
    }
};

ScenePoses::ScenePoses(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ScenePoses::ScenePoses(ScenePoses&&) noexcept = default;
ScenePoses& ScenePoses::operator=(ScenePoses&&) noexcept = default;
ScenePoses::~ScenePoses() = default;

Result<ScenePoses> ScenePoses::make(Mode mode, const sim::Scene& scene, const sim::ActionLibrary& lib,
                                    const Options& options, const ProgressFn& progress) {
    auto impl = std::make_unique<Impl>(mode, scene, lib);
    if (mode == Mode::Physics) {
        auto frames = simulate(scene, lib, options, progress);
        if (!frames) return frames.error();
        impl->frames = std::move(*frames);
    }
    return ScenePoses(std::move(impl));
}

Mode ScenePoses::mode() const { return impl_->mode; }
const Skeleton& ScenePoses::skeleton(int character) const { return impl_->poser.skeleton(character); }
const Report& ScenePoses::report() const { return impl_->frames.report; }

void ScenePoses::world(int character, double t, std::vector<glm::vec3>& positions, std::vector<glm::quat>& rotations) const {
    const Impl& m = *impl_;
    if (m.ballFollows(character)) {
        const auto& p = m.frames.ballPositions[static_cast<std::size_t>(character)];
        const auto& r = m.frames.ballRotations[static_cast<std::size_t>(character)];
        const int last = static_cast<int>(p.size()) - 1;
        double x = std::isfinite(t) ? t * m.frames.world.fps : 0.0;
        x = std::clamp(x, 0.0, static_cast<double>(last));
        const int f0 = std::min(static_cast<int>(std::floor(x)), last);
        const int f1 = std::min(f0 + 1, last);
        const auto a = static_cast<float>(x - f0);
        const auto i0 = static_cast<std::size_t>(f0), i1 = static_cast<std::size_t>(f1);
        positions.assign(1, p[i0] + (p[i1] - p[i0]) * a);
        rotations.assign(1, a == 0.0f ? r[i0] : glm::normalize(glm::slerp(r[i0], r[i1], a)));
        return;
    }
    if (!m.simulated(character)) {
        Pose pose;
        m.poser.pose(character, t, pose);
        positions.resize(pose.translations.size());
        rotations.resize(pose.translations.size());
        forwardKinematics(m.poser.skeleton(character), pose.translations, pose.rotations, positions, rotations);
        return;
    }
    const auto c = static_cast<std::size_t>(character);
    const auto n = static_cast<std::size_t>(m.frames.world.jointCount[c]);
    const int last = m.frames.world.frames - 1;
    double x = std::isfinite(t) ? t * m.frames.world.fps : 0.0;
    x = std::clamp(x, 0.0, static_cast<double>(last));
    const int f0 = std::min(static_cast<int>(std::floor(x)), last);
    const int f1 = std::min(f0 + 1, last);
    const auto a = static_cast<float>(x - f0);
    const glm::vec3* p0 = &m.frames.world.joints[c][static_cast<std::size_t>(f0) * n];
    const glm::vec3* p1 = &m.frames.world.joints[c][static_cast<std::size_t>(f1) * n];
    const glm::quat* r0 = &m.frames.rotations[c][static_cast<std::size_t>(f0) * n];
    const glm::quat* r1 = &m.frames.rotations[c][static_cast<std::size_t>(f1) * n];
    positions.resize(n);
    rotations.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
        positions[j] = p0[j] + (p1[j] - p0[j]) * a;
        rotations[j] = a == 0.0f ? r0[j] : glm::normalize(glm::slerp(r0[j], r1[j], a));
    }
}

void ScenePoses::pose(int character, double t, Pose& out) const {
    if (!impl_->simulated(character) && !impl_->ballFollows(character)) {
        impl_->poser.pose(character, t, out);
        return;
    }
    std::vector<glm::vec3> positions;
    std::vector<glm::quat> rotations;
    world(character, t, positions, rotations);
    localPose(impl_->poser.skeleton(character), positions, rotations, out);
}

void localPose(const Skeleton& skeleton, std::span<const glm::vec3> world, std::span<const glm::quat> worldRotations,
               Pose& out) {
    const auto n = static_cast<std::size_t>(skeleton.jointCount());
    out.translations.assign(n, glm::vec3(0.0f));
    out.rotations.assign(n, glm::quat(1, 0, 0, 0));
    if (world.size() < n || worldRotations.size() < n) return;
    for (std::size_t j = 0; j < n; ++j) {
        const int p = skeleton.parents[j];
        if (p < 0) {
            out.translations[j] = world[j];
            out.rotations[j] = worldRotations[j];
        } else {
            out.translations[j] = skeleton.offsets[j];
            out.rotations[j] = glm::normalize(glm::inverse(worldRotations[static_cast<std::size_t>(p)]) * worldRotations[j]);
        }
    }
}

}  // namespace fray::posture

// ODE's generator, per thread while an island steps (see StepRandom above).
extern "C" unsigned long dRand(void) {
    using fray::posture::stepRandom;
    if (stepRandom.active) {
        stepRandom.seed = fray::posture::nextRandom(stepRandom.seed);
        ++stepRandom.draws;
        return stepRandom.seed;
    }
    using Fn = unsigned long (*)(void);
    static const Fn ode = reinterpret_cast<Fn>(dlsym(RTLD_NEXT, "dRand"));
    if (ode) return ode();
    // No ODE dRand found after this one: the same generator, process-wide.
    static std::atomic<std::uint32_t> seed{0};
    std::uint32_t now = seed.load(), next = 0;
    do {
        next = fray::posture::nextRandom(now);
    } while (!seed.compare_exchange_weak(now, next));
    return next;
}
