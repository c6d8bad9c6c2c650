// Football moves for the American-football scene (SPEC 4.5, {run, TACKLE,
// avoid}): a running cut (juke) that carries the runner sideways past a
// tackle, and the tackle itself, a dive from a run that lands face down.
#include <algorithm>
#include <cmath>

#include "actions.h"
#include "rig.h"

namespace fray::demo::detail {

using glm::dvec3;

namespace {

dvec3 forwardOf(double heading) { return {std::sin(heading), 0.0, std::cos(heading)}; }

}  // namespace

void juke(Builder& b, int side) {
    const double sg = sideSign(side);
    const double speed = std::max(b.gait.speed, 2.6);
    // Plant and push across, then land on the new line still leaning in.
    // One action of two steps: the second starts where the first ends.
    const int first = b.frame;
    const double tMid = locoStepKeys(b, Gait::Run, speed * 0.92, 0.0, sg * b.rng.uniform(0.30, 0.36), sg * 0.16);
    b.frame = static_cast<int>(std::lround(tMid * kDemoFps));
    const double t1 = locoStepKeys(b, Gait::Run, speed, 0.0, sg * b.rng.uniform(0.28, 0.34), sg * 0.07);
    b.frame = first;
    b.finish(side == 0 ? "juke_left" : "juke_right", t1);
}

void tackle(Builder& b) {
    // The approach: one driving run step.
    const double t1 = locoStepKeys(b, Gait::Run, 3.4 * b.rng.jitter(0.04), 0.0, 0.0, 0.0);
    const double k = b.rng.jitter(0.06);
    const double h = b.heading(t1);
    const dvec3 fwd = forwardOf(h);
    const dvec3 p1 = b.base(t1);
    const double v = b.gait.speed;
    const int A = b.gait.nextSwing;  // in the air at t1
    const int B = 1 - A;             // lands in the approach step: the take-off foot
    // The foot in the air leaves its last plant when its stance ended; the
    // take-off foot pushes off a little after it lands.
    b.liftFree(A, std::min(b.gait.liftTime[static_cast<std::size_t>(A)], t1), t1 + 0.10);
    const double tOff = t1 + 0.20 * k;
    b.liftFree(B, tOff, tOff + 0.12);
    const double tDown = tOff + 0.42 * k;  // chest meets the floor
    const double tStop = tDown + 0.38 * k;  // done sliding
    // Free feet trail behind and above the floor while the body stretches out.
    const double liftA = std::min(b.gait.liftTime[static_cast<std::size_t>(A)], t1);
    for (int side = 0; side < 2; ++side) {
        const dvec3 trail(sideSign(side) * 0.12, -0.32, -0.72);
        const double from = side == A ? liftA : tOff;
        const dvec3 rest(sideSign(side) * 0.12, -0.02, -0.88);  // lying: toes on the floor behind
        for (int a = 0; a < 3; ++a) {
            b.ease(footCh(side, a), from, tOff + 0.30 * k, trail[a]);
            b.ease(footCh(side, a), tOff + 0.30 * k, tStop, rest[a]);
        }
    }
    const dvec3 pOff = p1 + fwd * (v * (tOff - t1));
    const dvec3 pDown = pOff + fwd * 1.40;
    const dvec3 pStop = pDown + fwd * 0.40;
    for (Ch c : {BaseX, BaseZ, Heading}) b.hold(c, t1);
    b.key(BaseX, tOff, pOff.x, v * fwd.x);
    b.key(BaseZ, tOff, pOff.z, v * fwd.z);
    b.key(BaseX, tDown, pDown.x, 1.8 * fwd.x);
    b.key(BaseZ, tDown, pDown.z, 1.8 * fwd.z);
    b.key(BaseX, tStop, pStop.x);
    b.key(BaseZ, tStop, pStop.z);
    b.key(Heading, tStop, h);
    // Crouch and drive, then stretch out flat with the arms reaching ahead.
    Pose drive, dive, land, prone;
    drive.set(ShiftX, 0).set(ShiftZ, 0.05).set(Height, 0.86).set(PelvisYaw, 0).set(PelvisPitch, 0.35).set(PelvisRoll, 0);
    drive.set(SpinePitch, 0.30).set(SpineYaw, 0).set(SpineRoll, 0).set(HeadPitch, -0.35).set(HeadYaw, 0).set(HeadRoll, 0);
    drive.set(Gaze, 0.9);
    drive.setHand(0, {0.22, -0.05, 0.35}).setHand(1, {-0.22, -0.05, 0.35});
    drive.setPole(0, {0.6, -1.0, 0.0}).setPole(1, {-0.6, -1.0, 0.0});
    dive.set(ShiftZ, 0.15).set(Height, 0.62).set(PelvisPitch, 1.05).set(SpinePitch, 0.30).set(HeadPitch, -0.75);
    dive.setHand(0, {0.20, -0.02, 0.62}).setHand(1, {-0.20, -0.02, 0.62});
    dive.setPole(0, {0.8, -0.6, 0.0}).setPole(1, {-0.8, -0.6, 0.0});
    // Chest and thighs meet the floor: the legs lie behind (thighs back).
    land.set(ShiftZ, 0.18).set(Height, 0.36).set(PelvisPitch, 1.40).set(SpinePitch, 0.05).set(HeadPitch, -0.45);
    land.setHand(0, {0.24, -0.10, 0.50}).setHand(1, {-0.24, -0.10, 0.50});
    for (int side = 0; side < 2; ++side) {
        land.set(floorCh(side), 1.0).set(floorDirCh(side), -1.0);
        land.set(footYawCh(side), 0).set(footPitchCh(side), 0.0);
    }
    prone.set(ShiftZ, 0.20).set(Height, 0.11).set(PelvisPitch, 1.50).set(SpinePitch, -0.05).set(HeadPitch, -0.25);
    prone.set(HeadYaw, 0.9 * sideSign(b.rng.below(2)));
    prone.setHand(0, {0.26, -0.08, 0.45}).setHand(1, {-0.26, -0.08, 0.45});
    prone.setPole(0, {1.0, 0.0, -0.3}).setPole(1, {-1.0, 0.0, -0.3});
    b.pose(t1, tOff, drive);
    b.pose(tOff, tOff + 0.26 * k, dive);
    b.pose(tOff + 0.26 * k, tDown, land);
    b.pose(tDown, tStop, prone);
    b.gait = GaitState{};
    b.mode = Mode::Prone;
    b.finish("tackle", b.endOf(tStop + 0.10));
}

}  // namespace fray::demo::detail
