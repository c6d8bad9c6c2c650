#pragma once
// Authoring of a take: actions append keys to the timeline, footsteps to the
// foot schedules and their ground-truth record to `actions`. Every action
// starts where the previous one ended (same channel values, slopes matched or
// zero), so a take is one continuous motion.
#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "fray/demo/demo_actor.h"
#include "fray/demo/ground_truth.h"
#include "rng.h"
#include "solver.h"
#include "timeline.h"

namespace fray::demo::detail {

struct StyleParams {
    Style style = Style::Neutral;
    double tempo = 1.0;      // duration multiplier of the fighting set
    double strike = 1.0;     // multiplier of the fast phase of attacks (kept near 1: speed is physics)
    double amplitude = 1.0;  // size of twists, leans and weight shifts
    double guardDrop = 0.0;  // hands this much lower than the energetic guard (m)
    double recovery = 0.0;   // settle time appended to actions (s)
    double bounce = 0.0;     // guard bounce (m)
    static StyleParams of(Style s);
};

// What the body is doing between actions; actions check and update it.
enum class Mode : std::uint8_t { Stand, Guard, Carry, Supine, Prone };

// Target values for a set of channels. Hands are given in the heading frame,
// relative to the chest joint, and converted to the chest frame at key time.
struct Pose {
    std::array<double, kChannelCount> v{};
    std::array<bool, kChannelCount> has{};
    std::array<glm::dvec3, 2> hand{};
    std::array<bool, 2> hasHand{};
    Pose& set(Ch c, double x) {
        v[static_cast<std::size_t>(c)] = x;
        has[static_cast<std::size_t>(c)] = true;
        return *this;
    }
    Pose& add(Ch c, double x) { return set(c, get(c) + x); }  // on a channel already set
    double get(Ch c) const { return v[static_cast<std::size_t>(c)]; }
    Pose& setHand(int side, const glm::dvec3& h) {
        hand[static_cast<std::size_t>(side)] = h;
        hasHand[static_cast<std::size_t>(side)] = true;
        return *this;
    }
    // Hand target directly in the chest frame (moves with the torso).
    Pose& setHandChest(int side, const glm::dvec3& c) {
        for (int a = 0; a < 3; ++a) set(handCh(side, a), c[a]);
        hasHand[static_cast<std::size_t>(side)] = false;
        return *this;
    }
    Pose& setPole(int side, const glm::dvec3& p) {
        for (int a = 0; a < 3; ++a) set(poleCh(side, a), p[a]);
        return *this;
    }
    Pose& setFoot(int side, const glm::dvec3& p) {
        for (int a = 0; a < 3; ++a) set(footCh(side, a), p[a]);
        return *this;
    }
    Pose& setKnee(int side, const glm::dvec3& p) {
        for (int a = 0; a < 3; ++a) set(kneeCh(side, a), p[a]);
        return *this;
    }
};

// Static description of an action kind (annotations and joints for the truth).
struct ActionInfo {
    const char* name;
    bool fighting;  // styled (energetic / tired)
    std::vector<const char*> annotations;
    std::vector<const char*> joints;
    const char* attackDirection;  // nullptr when not an attack or reaction
    const char* targetPart;
    const char* defendedPart;
};
const std::vector<ActionInfo>& actionTable();
const ActionInfo& actionInfo(std::string_view name);

// Locomotion state carried from one step action to the next.
struct GaitState {
    bool active = false;
    int nextSwing = 0;           // side whose foot swings in the next step
    double speed = 0;            // along the heading at the last boundary (m/s, < 0 backwards)
    double yawRate = 0;          // rad/s at the last boundary
    std::array<double, 2> liftTime{};  // when each foot's current stance ends
    std::array<double, 2> stanceCentre{};  // middle of each foot's current stance
};

class Builder {
public:
    Builder(Style style, std::uint64_t seed);

    Timeline tl;
    Rng rng;
    StyleParams sp;
    Mode mode = Mode::Stand;
    GaitState gait;
    int frame = 0;  // first frame of the next action
    std::vector<TruthAction> actions;

    static double snap(double t);  // to the frame grid
    double now() const { return frame / kDemoFps; }
    // Duration multiplier for the next fighting action: tempo with a little jitter.
    double k(double spread = 0.04) { return sp.tempo * rng.jitter(spread); }

    double val(Ch c, double t) const { return tl[c].value(t); }
    void key(Ch c, double t, double v, double slope = 0, Interp in = Interp::Quintic) { tl[c].key(t, v, slope, in); }
    void ease(Ch c, double t0, double t1, double v) { tl[c].ease(t0, t1, v); }
    void hold(Ch c, double t) { tl[c].hold(t); }
    // Eases every channel the pose sets (hands last: they need the chest orientation at t1).
    void pose(double t0, double t1, const Pose& p);
    // Eases a hand to an offset from the chest joint given in the heading frame at t1.
    void hand(int side, double t0, double t1, const glm::dvec3& offsetH);
    // Eases a hand to a world point (uses the solved body at t1).
    void handWorld(int side, double t0, double t1, const glm::dvec3& world);

    glm::dvec3 base(double t) const { return {val(BaseX, t), 0.0, val(BaseZ, t)}; }
    double heading(double t) const { return val(Heading, t); }
    // Moves the base / heading (eased, flat ends).
    void moveBase(double t0, double t1, const glm::dvec3& to, double headingTo);
    // A flat-foot plant at (x, z) in the heading frame of `base`, foot yaw relative to the heading.
    static FootPlant plantAt(const glm::dvec3& base, double heading, double x, double z, double yawRel);
    std::array<FootPlant, 2> stanceFeet(Mode m, const glm::dvec3& base, double heading) const;
    void step(int side, double t0, double t1, const FootPlant& to, double lift, double toeOff = 0, double heelStrike = 0);
    // Plants a free foot: the schedule jumps (unseen) to `to`, then the free weight eases to 0 over [t0, t1].
    void plantFree(int side, double t0, double t1, const FootPlant& to);
    // Frees a planted foot over [t0, t1]; the free target starts at the plant (relative to the Hips at t0).
    void liftFree(int side, double t0, double t1);
    // Ankle of a planted foot relative to the Hips in the heading frame, at time t.
    glm::dvec3 footRelHips(int side, double t);
    // Pivot on the ball of the foot to a new yaw (a quick, barely lifted swing).
    void pivotFoot(int side, double t0, double t1, double yawTo);

    Pose modePose(Mode m) const;
    Pose guardPose() const { return modePose(Mode::Guard); }

    // Records the action [frame, end) and advances. endTime is snapped to the grid.
    double finish(std::string_view name, double endTime);
    double endOf(double t) const { return std::ceil(t * kDemoFps - 1e-6) / kDemoFps; }
};

}  // namespace fray::demo::detail
