#include "builder.h"

#include <cmath>
#include <stdexcept>

#include "rig.h"

namespace fray::demo::detail {

using glm::dvec3;

StyleParams StyleParams::of(Style s) {
    StyleParams p;
    p.style = s;
    if (s == Style::Energetic) {
        p.recovery = 0.02;
        p.bounce = 0.014;
    } else if (s == Style::Tired) {
        p.tempo = 1.32;
        p.strike = 1.05;
        p.amplitude = 0.82;
        p.guardDrop = 0.09;
        p.recovery = 0.16;
        p.bounce = 0.004;
    }
    return p;
}

const std::vector<ActionInfo>& actionTable() {
    static const std::vector<ActionInfo> table = {
        // boxing / kickboxing
        {"jab", true, {"punch"}, {"LeftHand"}, "straight", "head", nullptr},
        {"cross", true, {"punch"}, {"RightHand"}, "straight", "head", nullptr},
        {"hook_left", true, {"punch"}, {"LeftHand"}, "from_left", "head", nullptr},
        {"hook_right", true, {"punch"}, {"RightHand"}, "from_right", "head", nullptr},
        {"uppercut_left", true, {"punch"}, {"LeftHand"}, "upward", "head", nullptr},
        {"uppercut_right", true, {"punch"}, {"RightHand"}, "upward", "head", nullptr},
        {"front_kick", true, {"kick"}, {"RightFoot"}, "straight", "torso", nullptr},
        {"roundhouse_left", true, {"kick"}, {"LeftFoot"}, "from_left", "torso", nullptr},
        {"roundhouse_right", true, {"kick"}, {"RightFoot"}, "from_right", "torso", nullptr},
        {"knee_strike", true, {"kick"}, {"RightLeg"}, "upward", "torso", nullptr},
        // defences
        {"block_high", true, {"block"}, {"LeftHand", "RightHand"}, nullptr, nullptr, "head"},
        {"block_low", true, {"block"}, {"LeftForeArm", "RightForeArm"}, nullptr, nullptr, "torso"},
        {"parry", true, {"block"}, {"RightHand"}, nullptr, nullptr, "head"},
        {"slip_left", true, {"avoid", "dodge"}, {"Head", "Spine2"}, nullptr, nullptr, "head"},
        {"slip_right", true, {"avoid", "dodge"}, {"Head", "Spine2"}, nullptr, nullptr, "head"},
        {"duck", true, {"avoid", "dodge"}, {"Head", "Hips"}, nullptr, nullptr, "head"},
        {"sway_back", true, {"avoid"}, {"Head", "Spine2"}, nullptr, nullptr, "head"},
        // footwork
        {"step_forward", true, {"step"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"step_back", true, {"step"}, {"RightFoot", "LeftFoot"}, nullptr, nullptr, nullptr},
        {"step_left", true, {"step"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"step_right", true, {"step"}, {"RightFoot", "LeftFoot"}, nullptr, nullptr, nullptr},
        {"pivot_left", true, {"step", "turn"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"pivot_right", true, {"step", "turn"}, {"RightFoot", "LeftFoot"}, nullptr, nullptr, nullptr},
        {"guard_idle", true, {"idle"}, {}, nullptr, nullptr, nullptr},
        {"to_guard", true, {"transition"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"to_stand", true, {"transition"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        // hit reactions
        {"head_snap", true, {"pushed"}, {"Head"}, "front", "head", nullptr},
        {"body_stagger", true, {"pushed"}, {"Spine1"}, "front", "torso", nullptr},
        {"knocked_back", true, {"pushed", "step"}, {"Hips"}, "front", "head", nullptr},
        {"knocked_down", true, {"pushed", "falling"}, {"Hips"}, "front", "head", nullptr},
        // falls
        {"fall_forward", false, {"falling"}, {"Hips"}, nullptr, nullptr, nullptr},
        {"fall_backward", false, {"falling"}, {"Hips"}, nullptr, nullptr, nullptr},
        {"fall_sideways", false, {"falling"}, {"Hips"}, nullptr, nullptr, nullptr},
        {"fall_pushed", false, {"pushed", "falling"}, {"Hips"}, "front", "torso", nullptr},
        {"get_up", false, {"transition"}, {"Hips"}, nullptr, nullptr, nullptr},
        // locomotion
        {"walk", false, {"walk"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"jog", false, {"run"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"run", false, {"run"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"turn_walk", false, {"walk", "turn"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"turn_run", false, {"run", "turn"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"backpedal", false, {"walk"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"idle_stand", false, {"idle"}, {}, nullptr, nullptr, nullptr},
        // carrying
        {"pick_up_box", false, {"carry"}, {"LeftHand", "RightHand"}, nullptr, nullptr, nullptr},
        {"walk_carry", false, {"carry", "walk"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"hand_over", false, {"hand", "carry"}, {"LeftHand", "RightHand"}, nullptr, nullptr, nullptr},
        {"receive", false, {"receive"}, {"LeftHand", "RightHand"}, nullptr, nullptr, nullptr},
        {"turn_carry", false, {"carry", "turn"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"put_down", false, {"carry"}, {"LeftHand", "RightHand"}, nullptr, nullptr, nullptr},
        // football (the football library set only)
        {"juke_left", false, {"avoid"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, "torso"},
        {"juke_right", false, {"avoid"}, {"RightFoot", "LeftFoot"}, nullptr, nullptr, "torso"},
        {"tackle", false, {"tackle"}, {"LeftHand", "RightHand"}, "straight", "torso", nullptr},
        // one end of a long box (the carry set only)
        {"carry_end_lift", false, {"carry", "transition"}, {"LeftHand", "RightHand"}, nullptr, nullptr, nullptr},
        {"carry_end_forward", false, {"carry", "step"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"carry_end_back", false, {"carry", "step"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"carry_end_left", false, {"carry", "step"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"carry_end_right", false, {"carry", "step"}, {"RightFoot", "LeftFoot"}, nullptr, nullptr, nullptr},
        {"carry_end_turn_left", false, {"carry", "turn"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"carry_end_turn_right", false, {"carry", "turn"}, {"RightFoot", "LeftFoot"}, nullptr, nullptr, nullptr},
        {"carry_end_hold", false, {"carry", "idle"}, {}, nullptr, nullptr, nullptr},
        {"carry_end_forward_left", false, {"carry", "step"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"carry_end_forward_right", false, {"carry", "step"}, {"RightFoot", "LeftFoot"}, nullptr, nullptr, nullptr},
        {"carry_end_back_left", false, {"carry", "step"}, {"LeftFoot", "RightFoot"}, nullptr, nullptr, nullptr},
        {"carry_end_back_right", false, {"carry", "step"}, {"RightFoot", "LeftFoot"}, nullptr, nullptr, nullptr},
    };
    return table;
}

const ActionInfo& actionInfo(std::string_view name) {
    for (const ActionInfo& a : actionTable())
        if (name == a.name) return a;
    throw std::logic_error("demo actor: unknown action kind '" + std::string(name) + "'");
}

Builder::Builder(Style style, std::uint64_t seed) : rng(seed), sp(StyleParams::of(style)) {}

double Builder::snap(double t) { return std::round(t * kDemoFps) / kDemoFps; }

void Builder::pose(double t0, double t1, const Pose& p) {
    for (int c = 0; c < kChannelCount; ++c)
        if (p.has[static_cast<std::size_t>(c)]) ease(static_cast<Ch>(c), t0, t1, p.v[static_cast<std::size_t>(c)]);
    for (int side = 0; side < 2; ++side)
        if (p.hasHand[static_cast<std::size_t>(side)]) hand(side, t0, t1, p.hand[static_cast<std::size_t>(side)]);
}

void Builder::hand(int side, double t0, double t1, const dvec3& offsetH) {
    const glm::dquat r = chestRotationH(val(PelvisYaw, t1), val(PelvisPitch, t1), val(PelvisRoll, t1),
                                        val(SpinePitch, t1), val(SpineYaw, t1), val(SpineRoll, t1));
    const dvec3 c = glm::inverse(r) * offsetH;
    for (int a = 0; a < 3; ++a) ease(handCh(side, a), t0, t1, c[a]);
}

void Builder::handWorld(int side, double t0, double t1, const dvec3& world) {
    for (int a = 0; a < 3; ++a) hold(handCh(side, a), t0);
    SolvedFrame sf;
    solveFrame(tl, t1, sf);
    // Chest orientation from the spine (the solver's world rotation of Spine2).
    const glm::dquat H = rotY(heading(t1));
    const glm::dquat r = H * chestRotationH(val(PelvisYaw, t1), val(PelvisPitch, t1), val(PelvisRoll, t1),
                                            val(SpinePitch, t1), val(SpineYaw, t1), val(SpineRoll, t1));
    const dvec3 c = glm::inverse(r) * (world - sf.world[kSpine2]);
    for (int a = 0; a < 3; ++a) key(handCh(side, a), t1, c[a]);
}

void Builder::moveBase(double t0, double t1, const dvec3& to, double headingTo) {
    ease(BaseX, t0, t1, to.x);
    ease(BaseZ, t0, t1, to.z);
    ease(Heading, t0, t1, headingTo);
}

FootPlant Builder::plantAt(const dvec3& b, double h, double x, double z, double yawRel) {
    FootPlant p;
    p.ankle = b + rotY(h) * dvec3(x, 0, z) + dvec3(0, RigDims::ankleHeight, 0);
    p.ankle.y = RigDims::ankleHeight;
    p.yaw = h + yawRel;
    return p;
}

std::array<FootPlant, 2> Builder::stanceFeet(Mode m, const dvec3& b, double h) const {
    if (m == Mode::Guard) return {plantAt(b, h, 0.11, 0.21, -0.35), plantAt(b, h, -0.13, -0.21, -0.70)};
    return {plantAt(b, h, 0.10, 0.0, 0.10), plantAt(b, h, -0.10, 0.0, -0.10)};
}

void Builder::step(int side, double t0, double t1, const FootPlant& to, double lift, double toeOff, double heelStrike) {
    tl.feet[static_cast<std::size_t>(side)].swing(t0, t1, to, lift, toeOff, heelStrike);
}

dvec3 Builder::footRelHips(int side, double t) {
    SolvedFrame sf;
    solveFrame(tl, t, sf);
    const int foot = side == 0 ? kLFoot : kRFoot;
    return glm::inverse(rotY(heading(t))) * (sf.world[foot] - sf.root);
}

void Builder::liftFree(int side, double t0, double t1) {
    const FootPlant p = tl.feet[static_cast<std::size_t>(side)].last();
    const dvec3 rel = footRelHips(side, t0);
    for (int a = 0; a < 3; ++a) key(footCh(side, a), t0, rel[a]);
    key(footYawCh(side), t0, 0.0);
    key(footPitchCh(side), t0, 0.0);
    const dvec3 knee = glm::inverse(rotY(heading(t0))) * (rotY(p.yaw) * dvec3(0, 0, 1));
    for (int a = 0; a < 3; ++a) key(kneeCh(side, a), t0, knee[a]);
    ease(freeCh(side), t0, t1, 1.0);
}

void Builder::plantFree(int side, double t0, double t1, const FootPlant& to) {
    // The free target starts exactly where the ankle is, so the blend cannot jump.
    const dvec3 rel0 = footRelHips(side, t0);
    for (int a = 0; a < 3; ++a) key(footCh(side, a), t0, rel0[a]);
    step(side, t0, t0, to, 0.0);
    ease(freeCh(side), t0, t1, 0.0);
    ease(floorCh(side), t0, t1, 0.0);
    // Bring the free target onto the plant so the blend does not wander.
    SolvedFrame sf;
    solveFrame(tl, t1, sf);
    const double h = heading(t1);
    const dvec3 rel = glm::inverse(rotY(h)) * (to.ankle - sf.root);
    for (int a = 0; a < 3; ++a) ease(footCh(side, a), t0, t1, rel[a]);
    ease(footYawCh(side), t0, t1, 0.0);
    ease(footPitchCh(side), t0, t1, 0.0);
    const dvec3 knee = glm::inverse(rotY(h)) * (rotY(to.yaw) * dvec3(0, 0, 1));
    for (int a = 0; a < 3; ++a) ease(kneeCh(side, a), t0, t1, knee[a]);
}

void Builder::pivotFoot(int side, double t0, double t1, double yawTo) {
    const FootPlant p = tl.feet[static_cast<std::size_t>(side)].last();
    FootPlant q = p;
    q.yaw = yawTo;
    q.ankle += rotY(p.yaw) * dvec3(0, 0, RigDims::toeZ) - rotY(yawTo) * dvec3(0, 0, RigDims::toeZ);
    q.ankle.y = RigDims::ankleHeight;
    step(side, t0, t1, q, 0.012);
}

Pose Builder::modePose(Mode m) const {
    Pose p;
    // Posture only: the feet (free weights, targets) belong to the actions.
    p.set(ShiftX, 0).set(ShiftZ, 0).set(PelvisRoll, 0).set(SpineRoll, 0).set(HeadYaw, 0).set(HeadRoll, 0);
    switch (m) {
        case Mode::Guard: {
            const double tired = sp.style == Style::Tired ? 1.0 : 0.0;
            const double drop = sp.guardDrop;
            p.set(ShiftZ, -0.02).set(Height, 0.935 + 0.012 * tired);
            p.set(PelvisYaw, -0.55 + 0.08 * tired).set(PelvisPitch, 0.06 + 0.03 * tired);
            p.set(SpinePitch, 0.12 + 0.10 * tired).set(SpineYaw, 0.30);
            p.set(HeadPitch, 0.08 + 0.06 * tired).set(Gaze, 1.0);
            p.setHand(0, {0.07, 0.24 - drop, 0.30}).setHand(1, {-0.09, 0.22 - drop, 0.21});
            p.setPole(0, {0.35, -1.0, -0.25}).setPole(1, {-0.35, -1.0, -0.25});
            break;
        }
        case Mode::Carry:
            p.set(Height, 0.985).set(PelvisYaw, 0).set(PelvisPitch, 0).set(SpinePitch, -0.04).set(SpineYaw, 0);
            p.set(HeadPitch, 0.12).set(Gaze, 0.8);
            p.setHand(0, {0.20, -0.20, 0.33}).setHand(1, {-0.20, -0.20, 0.33});
            p.setPole(0, {0.5, -1.0, -0.3}).setPole(1, {-0.5, -1.0, -0.3});
            break;
        default:
            p.set(Height, 0.995).set(PelvisYaw, 0).set(PelvisPitch, 0.0).set(SpinePitch, 0.03).set(SpineYaw, 0);
            p.set(HeadPitch, 0.0).set(Gaze, 0.8);
            p.setHand(0, {0.21, -0.42, 0.03}).setHand(1, {-0.21, -0.42, 0.03});
            p.setPole(0, {0.3, 0.0, -1.0}).setPole(1, {-0.3, 0.0, -1.0});
            break;
    }
    return p;
}

double Builder::finish(std::string_view name, double endTime) {
    const ActionInfo& info = actionInfo(name);
    const int end = std::max(frame + 1, static_cast<int>(std::lround(endTime * kDemoFps)));
    TruthAction a;
    a.name = std::string(name);
    a.firstFrame = frame;
    a.lastFrame = end - 1;
    a.style = std::string(info.fighting ? toString(sp.style) : toString(Style::Neutral));
    for (const char* s : info.annotations) a.annotations.emplace_back(s);
    for (const char* s : info.joints) a.joints.emplace_back(s);
    if (info.attackDirection) a.attackDirection = info.attackDirection;
    if (info.targetPart) a.targetPart = info.targetPart;
    if (info.defendedPart) a.defendedPart = info.defendedPart;
    actions.push_back(std::move(a));
    frame = end;
    return end / kDemoFps;
}

}  // namespace fray::demo::detail
