// Carrying a box (about 40 x 35 cm): pick up from the floor, put down, hand
// over to someone in front, receive from someone. The box itself is not part
// of the skeleton; the hands hold its sides.
#include "actions.h"
#include "rig.h"

namespace fray::demo::detail {

using glm::dvec3;

namespace {

// Squat over a box on the floor in front; hands on its sides at grasp height.
Pose squatPose() {
    Pose p;
    p.set(Height, 0.46).set(PelvisPitch, 0.55).set(SpinePitch, 0.70).set(ShiftZ, -0.10).set(ShiftX, 0);
    p.set(HeadPitch, -0.35).set(Gaze, 0.2).set(PelvisYaw, 0).set(SpineYaw, 0);
    p.setPole(0, {0.8, -0.5, -0.3}).setPole(1, {-0.8, -0.5, -0.3});
    return p;
}

dvec3 graspPoint(const Builder& b, double t, int side, double out) {
    return b.base(t) + rotY(b.heading(t)) * dvec3(sideSign(side) * out, 0.26, 0.42);
}

}  // namespace

void pickUpBox(Builder& b) {
    const double t0 = b.now(), k = b.rng.jitter(0.06);
    const double tDown = t0 + 0.85 * k, tGrip = tDown + 0.25 * k, tUp = tGrip + 0.85 * k;
    b.pose(t0, tDown, squatPose());
    for (int side = 0; side < 2; ++side) {
        b.handWorld(side, t0 + 0.25 * k, tDown - 0.1 * k, graspPoint(b, tDown, side, 0.26));
        b.handWorld(side, tDown - 0.1 * k, tGrip, graspPoint(b, tGrip, side, 0.20));
    }
    b.pose(tGrip, tUp, b.modePose(Mode::Carry));
    b.mode = Mode::Carry;
    b.finish("pick_up_box", b.endOf(tUp + 0.05));
}

void putDown(Builder& b) {
    const double t0 = b.now(), k = b.rng.jitter(0.06);
    const double tDown = t0 + 0.90 * k, tOpen = tDown + 0.25 * k, tUp = tOpen + 0.85 * k;
    b.pose(t0, tDown, squatPose());
    for (int side = 0; side < 2; ++side) {
        b.handWorld(side, t0 + 0.1 * k, tDown, graspPoint(b, tDown, side, 0.20));
        b.handWorld(side, tDown, tOpen, graspPoint(b, tOpen, side, 0.28));
    }
    b.pose(tOpen, tUp, b.modePose(Mode::Stand));
    b.mode = Mode::Stand;
    b.finish("put_down", b.endOf(tUp + 0.05));
}

void handOver(Builder& b) {
    const double t0 = b.now(), k = b.rng.jitter(0.06);
    const double tOut = t0 + 0.50 * k, tHold = tOut + 0.30 * k, tOpen = tHold + 0.15 * k, tBack = tOpen + 0.50 * k;
    Pose out = b.modePose(Mode::Carry);
    out.setHand(0, {0.20, -0.10, 0.52}).setHand(1, {-0.20, -0.10, 0.52}).set(SpinePitch, 0.12).set(ShiftZ, 0.04);
    out.setPole(0, {0.5, -1.0, 0.0}).setPole(1, {-0.5, -1.0, 0.0});
    Pose open = out;
    open.setHand(0, {0.28, -0.12, 0.48}).setHand(1, {-0.28, -0.12, 0.48});
    b.pose(t0, tOut, out);
    b.pose(tHold, tOpen, open);
    b.pose(tOpen, tBack, b.modePose(Mode::Stand));
    b.mode = Mode::Stand;
    b.finish("hand_over", b.endOf(tBack + 0.05));
}

void receiveBox(Builder& b) {
    const double t0 = b.now(), k = b.rng.jitter(0.06);
    const double tOut = t0 + 0.50 * k, tGrip = tOut + 0.20 * k, tHold = tGrip + 0.15 * k, tIn = tHold + 0.50 * k;
    Pose reach = b.modePose(Mode::Stand);
    reach.setHand(0, {0.27, -0.08, 0.50}).setHand(1, {-0.27, -0.08, 0.50}).set(SpinePitch, 0.12).set(ShiftZ, 0.04);
    reach.setPole(0, {0.5, -1.0, 0.0}).setPole(1, {-0.5, -1.0, 0.0});
    Pose grip = reach;
    grip.setHand(0, {0.20, -0.10, 0.50}).setHand(1, {-0.20, -0.10, 0.50});
    b.pose(t0, tOut, reach);
    b.pose(tOut, tGrip, grip);
    b.pose(tHold, tIn, b.modePose(Mode::Carry));
    b.mode = Mode::Carry;
    b.finish("receive", b.endOf(tIn + 0.05));
}

}  // namespace fray::demo::detail

// ---- one end of a long box (the carry set) ------------------------------------
// Both hands hold one end of a long box whose other end a second capture's
// actor holds, face to face. Every carry-end action lasts kCarryEndStep s
// and keeps the grip fixed in front of the chest, so two captures pair
// action by action: both carriers decide at the same times, and the grips
// move with the bases by the same eased profile.

namespace fray::demo::detail {

namespace {

Pose carryEndPose() {
    Pose p;
    p.set(ShiftX, 0).set(ShiftZ, 0).set(PelvisRoll, 0).set(SpineRoll, 0).set(HeadYaw, 0).set(HeadRoll, 0);
    p.set(Height, 0.98).set(PelvisYaw, 0).set(PelvisPitch, 0.02).set(SpinePitch, 0.04).set(SpineYaw, 0);
    p.set(HeadPitch, 0.06).set(Gaze, 0.0);
    p.setHand(0, {0.12, -0.16, 0.40}).setHand(1, {-0.12, -0.16, 0.40});
    p.setPole(0, {0.6, -1.0, -0.2}).setPole(1, {-0.6, -1.0, -0.2});
    return p;
}

constexpr double kFootWidth = 0.12;  // m either side of the base

}  // namespace

void carryEndLift(Builder& b) {
    const double t0 = b.now(), t1 = t0 + kCarryEndStep;
    b.pose(t0, t1 - 0.1, carryEndPose());
    b.mode = Mode::Carry;
    b.finish("carry_end_lift", t1);
}

void carryEndStep(Builder& b, CarryEndMove move) {
    const double t0 = b.now(), t1 = t0 + kCarryEndStep;
    const double h0 = b.heading(t0);
    const dvec3 p0 = b.base(t0);
    const double stride = kCarryEndStride * b.rng.jitter(0.06);
    dvec3 local(0.0);  // x left, z forward
    double turn = 0;
    const char* name = "carry_end_hold";
    int lead = b.rng.below(2);
    switch (move) {
        case CarryEndMove::Forward: local.z = stride, name = "carry_end_forward"; break;
        case CarryEndMove::Back: local.z = -stride, name = "carry_end_back"; break;
        case CarryEndMove::Left: local.x = stride, name = "carry_end_left", lead = 0; break;
        case CarryEndMove::Right: local.x = -stride, name = "carry_end_right", lead = 1; break;
        case CarryEndMove::TurnLeft:
        case CarryEndMove::TurnRight: {
            // Round the box's middle, kCarryEndPivot ahead: the grip stays on the circle the box end makes.
            turn = (move == CarryEndMove::TurnLeft ? 1.0 : -1.0) * kCarryEndTurn * b.rng.jitter(0.06);
            local = dvec3(-kCarryEndPivot * std::sin(turn), 0.0, kCarryEndPivot - kCarryEndPivot * std::cos(turn));
            name = move == CarryEndMove::TurnLeft ? "carry_end_turn_left" : "carry_end_turn_right";
            lead = move == CarryEndMove::TurnLeft ? 1 : 0;
            break;
        }
        case CarryEndMove::ForwardLeft:
        case CarryEndMove::ForwardRight:
        case CarryEndMove::BackLeft:
        case CarryEndMove::BackRight: {
            // The same stride along a diagonal.
            const bool fwd = move == CarryEndMove::ForwardLeft || move == CarryEndMove::ForwardRight;
            const bool left = move == CarryEndMove::ForwardLeft || move == CarryEndMove::BackLeft;
            const double c = stride * std::sqrt(0.5);
            local = dvec3(left ? c : -c, 0.0, fwd ? c : -c);
            name = fwd ? (left ? "carry_end_forward_left" : "carry_end_forward_right") : (left ? "carry_end_back_left" : "carry_end_back_right");
            lead = left ? 0 : 1;
            break;
        }
        case CarryEndMove::Hold: break;
    }
    const dvec3 p1 = p0 + rotY(h0) * local;
    const double h1 = h0 + turn;
    b.moveBase(t0, t1, p1, h1);
    if (move == CarryEndMove::Hold) {
        Pose s = carryEndPose();
        b.pose(t0, t1, s);
    } else {
        // Two short steps, the leading foot first, each to the end stance.
        const double T = t1 - t0;
        const int other = 1 - lead;
        b.step(lead, t0 + 0.06 * T, t0 + 0.50 * T, Builder::plantAt(p1, h1, sideSign(lead) * kFootWidth, 0.0, 0.0), 0.05);
        b.step(other, t0 + 0.46 * T, t0 + 0.92 * T, Builder::plantAt(p1, h1, sideSign(other) * kFootWidth, 0.0, 0.0), 0.05);
        b.pose(t0, t1, carryEndPose());
    }
    b.mode = Mode::Carry;
    b.finish(name, t1);
}

}  // namespace fray::demo::detail
