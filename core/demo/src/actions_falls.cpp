// Falls and getting up. Falls start standing (Stand or Guard) and end lying
// on the floor: on the back with the knees up and the feet planted (Supine) or
// face down (Prone). Getting up returns to Stand (or Guard for knocked_down).
#include <cmath>

#include "actions.h"
#include "rig.h"

namespace fray::demo::detail {

using glm::dvec3;

namespace {

// Foot position in the heading frame relative to the base (x left, z forward).
dvec3 footH(const Builder& b, int side, double t) {
    const FootPlant& p = b.tl.feet[static_cast<std::size_t>(side)].last();
    return glm::inverse(rotY(b.heading(t))) * (p.ankle - b.base(t));
}

// Lying on the back, relative to the base: pelvis at (x, z), knees up.
Pose supinePose(double x, double z) {
    Pose p;
    p.set(ShiftX, x).set(ShiftZ, z).set(Height, 0.11).set(PelvisYaw, 0).set(PelvisPitch, -1.40).set(PelvisRoll, 0);
    p.set(SpinePitch, 0.05).set(SpineYaw, 0).set(SpineRoll, 0).set(HeadPitch, 0.30).set(HeadYaw, 0).set(HeadRoll, 0);
    p.set(Gaze, 0);
    p.setHand(0, {0.26, -0.11, 0.28}).setHand(1, {-0.26, -0.11, 0.28});
    p.setPole(0, {1.0, 0.0, 0.0}).setPole(1, {-1.0, 0.0, 0.0});
    return p;
}

// Legs with the knees on the floor (the solver places them from the hips):
// dir +1 kneeling (thighs forward of the hips), -1 lying prone (thighs behind).
void floorLegs(Pose& p, double dir) {
    for (int side = 0; side < 2; ++side) {
        p.set(floorCh(side), 1.0).set(floorDirCh(side), dir);
        p.set(footYawCh(side), 0).set(footPitchCh(side), 0.0);
    }
}

}  // namespace

double sitFallBackward(Builder& b, double t0, double k) {
    const double h = b.heading(t0);
    dvec3 fl = footH(b, 0, t0), fr = footH(b, 1, t0);
    // A staggered stance first brings the lead foot back (a stumbling step).
    for (int side = 0; side < 2; ++side) {
        dvec3& me = side == 0 ? fl : fr;
        const dvec3& other = side == 0 ? fr : fl;
        if (me.z - other.z > 0.2) {
            me.z = other.z + 0.05;
            const auto plant = Builder::plantAt(b.base(t0), h, me.x, me.z, sideSign(side) * 0.15);
            b.step(side, t0 + 0.04 * k, t0 + 0.28 * k, plant, 0.04, 0.1);
        }
    }
    const double zf = 0.5 * (fl.z + fr.z), xf = 0.5 * (fl.x + fr.x);
    Pose lose, sit;
    lose.set(ShiftX, xf).set(ShiftZ, zf - 0.14).set(Height, 0.82).set(PelvisYaw, 0).set(PelvisPitch, 0.10);
    lose.set(SpinePitch, -0.18).set(SpineYaw, 0).set(SpineRoll, 0).set(HeadPitch, 0.25).set(HeadYaw, 0).set(Gaze, 0.3);
    lose.setHand(0, {0.22, 0.10, 0.38}).setHand(1, {-0.22, 0.08, 0.36});
    lose.setPole(0, {0.6, -1.0, 0.0}).setPole(1, {-0.6, -1.0, 0.0});
    sit.set(ShiftX, xf).set(ShiftZ, zf - 0.42).set(Height, 0.13).set(PelvisPitch, -0.15).set(SpinePitch, 0.25);
    sit.set(HeadPitch, 0.30).set(Gaze, 0.0);
    sit.setHand(0, {0.28, -0.36, -0.22}).setHand(1, {-0.28, -0.36, -0.22});
    sit.setPole(0, {0.5, 0.0, -1.0}).setPole(1, {-0.5, 0.0, -1.0});
    b.pose(t0, t0 + 0.32 * k, lose);
    b.pose(t0 + 0.32 * k, t0 + 0.66 * k, sit);
    b.pose(t0 + 0.66 * k, t0 + 1.10 * k, supinePose(xf, zf - 0.52));
    b.mode = Mode::Supine;
    return t0 + 1.15 * k;
}

double getUpFromSupine(Builder& b, double t0, double k, Mode endMode) {
    const double h = b.heading(t0);
    const dvec3 base = b.base(t0);
    const dvec3 fl = footH(b, 0, t0), fr = footH(b, 1, t0);
    const dvec3 mid = 0.5 * (fl + fr);
    const dvec3 newBase = base + rotY(h) * dvec3(mid.x, 0, mid.z);
    Pose sitUp, squat;
    sitUp.set(PelvisPitch, -0.25).set(SpinePitch, 0.45).set(Height, 0.13).set(HeadPitch, 0.15).set(Gaze, 0.5);
    sitUp.set(ShiftZ, mid.z - 0.45).set(ShiftX, mid.x);
    sitUp.setHand(0, {0.26, -0.32, -0.22}).setHand(1, {-0.26, -0.32, -0.22});
    sitUp.setPole(0, {0.5, 0.0, -1.0}).setPole(1, {-0.5, 0.0, -1.0});
    squat.set(ShiftZ, -0.10).set(ShiftX, 0).set(Height, 0.46).set(PelvisPitch, 0.35).set(SpinePitch, 0.50);
    squat.set(HeadPitch, 0.0).set(Gaze, 0.8);
    squat.setHand(0, {0.16, -0.05, 0.42}).setHand(1, {-0.16, -0.05, 0.42});
    squat.setPole(0, {0.5, -1.0, 0.0}).setPole(1, {-0.5, -1.0, 0.0});
    b.pose(t0, t0 + 0.50 * k, sitUp);
    // Base to the feet and the shift back to zero together: the pelvis path stays smooth.
    b.ease(BaseX, t0 + 0.50 * k, t0 + 1.05 * k, newBase.x);
    b.ease(BaseZ, t0 + 0.50 * k, t0 + 1.05 * k, newBase.z);
    b.pose(t0 + 0.50 * k, t0 + 1.05 * k, squat);
    const double tStand = t0 + 1.75 * k;
    Pose stand = b.modePose(Mode::Stand);
    b.pose(t0 + 1.05 * k, tStand, stand);
    b.mode = Mode::Stand;
    // Feet into the standing stance (they are close already), then into the guard if asked.
    const auto feet = b.stanceFeet(Mode::Stand, newBase, h);
    b.step(0, t0 + 1.45 * k, t0 + 1.70 * k, feet[0], 0.03, 0.05);
    b.step(1, t0 + 1.62 * k, t0 + 1.88 * k, feet[1], 0.03, 0.05);
    double tEnd = t0 + 1.92 * k;
    if (endMode == Mode::Guard) {
        const auto guard = b.stanceFeet(Mode::Guard, newBase, h);
        b.mode = Mode::Guard;
        b.step(0, tEnd, tEnd + 0.28, guard[0], 0.05, 0.15);
        b.step(1, tEnd + 0.22, tEnd + 0.52, guard[1], 0.05, 0.15);
        b.pose(tStand, tEnd + 0.52, b.guardPose());
        tEnd += 0.56;
    }
    return tEnd;
}

namespace {

double getUpFromProne(Builder& b, double t0, double k) {
    const double h = b.heading(t0);
    Pose push, fours, kneel, stand = b.modePose(Mode::Stand);
    push.set(PelvisPitch, 1.25).set(SpinePitch, -0.35).set(Height, 0.15).set(HeadYaw, 0).set(HeadPitch, -0.2);
    push.setHand(0, {0.25, -0.12, 0.02}).setHand(1, {-0.25, -0.12, 0.02});
    push.setPole(0, {0.3, 0.0, -1.0}).setPole(1, {-0.3, 0.0, -1.0});
    fours.set(PelvisPitch, 0.85).set(SpinePitch, 0.30).set(Height, 0.52).set(HeadPitch, -0.3);
    fours.set(ShiftZ, b.val(ShiftZ, t0) - 0.30);
    fours.setHand(0, {0.22, -0.30, 0.18}).setHand(1, {-0.22, -0.30, 0.18});
    floorLegs(fours, -1.0);  // thighs swing forward only once the hips are up (kneel below)
    kneel.set(PelvisPitch, 0.15).set(SpinePitch, 0.15).set(Height, 0.56).set(HeadPitch, 0.0).set(Gaze, 0.8);
    kneel.set(ShiftZ, b.val(ShiftZ, t0) - 0.30);
    kneel.setHand(0, {0.20, -0.35, 0.15}).setHand(1, {-0.20, -0.35, 0.15});
    kneel.setPole(0, {0.3, 0.0, -1.0}).setPole(1, {-0.3, 0.0, -1.0});
    floorLegs(kneel, 1.0);
    b.pose(t0, t0 + 0.50 * k, push);
    b.pose(t0 + 0.50 * k, t0 + 1.10 * k, fours);
    b.pose(t0 + 1.10 * k, t0 + 1.55 * k, kneel);
    // Right foot forward into a half kneel, then stand up onto both feet.
    const double tK = t0 + 1.55 * k;
    const dvec3 pelvis = b.base(tK) + rotY(h) * dvec3(b.val(ShiftX, tK), 0, b.val(ShiftZ, tK));
    const dvec3 newBase = pelvis + rotY(h) * dvec3(0, 0, 0.22);
    const auto feet = b.stanceFeet(Mode::Stand, newBase, h);
    const double tS0 = tK + 0.25 * k, tS1 = tK + 0.95 * k;
    b.ease(BaseX, tS0, tS1, newBase.x);
    b.ease(BaseZ, tS0, tS1, newBase.z);
    stand.set(ShiftZ, 0).set(ShiftX, 0);
    Pose lunge;
    lunge.set(Height, 0.60).set(PelvisPitch, 0.30).set(SpinePitch, 0.25);
    lunge.setHand(0, {0.18, -0.30, 0.30}).setHand(1, {-0.18, -0.30, 0.30});
    b.pose(tK, tS0, lunge);
    b.pose(tS0, tS1, stand);
    // Feet: the free targets move toward the plants while the free weight drops.
    b.plantFree(1, tK, tK + 0.30 * k, feet[1]);
    b.plantFree(0, tK + 0.45 * k, tK + 0.80 * k, feet[0]);
    b.mode = Mode::Stand;
    return tS1 + 0.05 * k;
}

}  // namespace

void fallBackward(Builder& b) {
    const double t0 = b.now(), k = b.rng.jitter(0.08);
    const double tDown = sitFallBackward(b, t0, 1.1 * k);
    b.finish("fall_backward", b.endOf(tDown + 0.10));
}

void fallForward(Builder& b) {
    const double t0 = b.now(), k = b.rng.jitter(0.08);
    const double h = b.heading(t0);
    const dvec3 base = b.base(t0);
    const dvec3 newBase = base + rotY(h) * dvec3(0, 0, 0.25);
    // Stumble: the right foot steps forward, the body pitches over it.
    const dvec3 fr = footH(b, 1, t0), fl = footH(b, 0, t0);
    const double zStep = std::max(fl.z, fr.z) + 0.30;
    b.step(1, t0 + 0.02 * k, t0 + 0.28 * k, Builder::plantAt(base, h, -0.10, zStep, -0.1), 0.05, 0.15);
    b.moveBase(t0, t0 + 0.35 * k, newBase, h);
    Pose stumble, knees, catchPose, prone;
    stumble.set(ShiftX, 0).set(ShiftZ, 0.0).set(Height, 0.88).set(PelvisYaw, 0).set(PelvisPitch, 0.15).set(PelvisRoll, 0);
    stumble.set(SpinePitch, 0.35).set(SpineYaw, 0).set(SpineRoll, 0).set(HeadPitch, -0.2).set(HeadYaw, 0).set(Gaze, 0.4);
    stumble.setHand(0, {0.20, 0.02, 0.42}).setHand(1, {-0.20, 0.02, 0.42});
    stumble.setPole(0, {0.5, -1.0, 0.0}).setPole(1, {-0.5, -1.0, 0.0});
    knees.set(Height, 0.55).set(PelvisPitch, 0.25).set(SpinePitch, 0.35).set(ShiftZ, 0.05);
    knees.setHand(0, {0.20, -0.10, 0.42}).setHand(1, {-0.20, -0.10, 0.42});
    floorLegs(knees, 1.0);
    catchPose.set(Height, 0.52).set(PelvisPitch, 0.95).set(SpinePitch, 0.25).set(ShiftZ, 0.12).set(Gaze, 0);
    catchPose.setHand(0, {0.24, -0.34, 0.16}).setHand(1, {-0.24, -0.34, 0.16});
    catchPose.setPole(0, {0.3, 0.0, -1.0}).setPole(1, {-0.3, 0.0, -1.0});
    floorLegs(catchPose, -1.0);
    prone.set(Height, 0.11).set(PelvisPitch, 1.50).set(SpinePitch, -0.05).set(ShiftZ, 0.45);
    prone.set(HeadYaw, 1.1).set(HeadPitch, -0.25).set(HeadRoll, 0);
    prone.setHand(0, {0.30, -0.07, 0.15}).setHand(1, {-0.30, -0.07, 0.15});
    prone.setPole(0, {1.0, 0.0, -0.3}).setPole(1, {-1.0, 0.0, -0.3});
    b.pose(t0, t0 + 0.32 * k, stumble);
    const double tK0 = t0 + 0.32 * k, tK1 = t0 + 0.62 * k;
    b.pose(tK0, tK1, knees);
    b.liftFree(0, tK0, tK0 + 0.16 * k);
    b.liftFree(1, tK0 + 0.04 * k, tK0 + 0.20 * k);
    // Toes up while the ankles are still low, tucked once kneeling.
    for (int side = 0; side < 2; ++side) {
        b.key(footPitchCh(side), tK0 + 0.16 * k, -0.3);
        b.key(footPitchCh(side), tK1, 0.0);
    }
    b.pose(tK1, t0 + 0.95 * k, catchPose);
    b.pose(t0 + 0.95 * k, t0 + 1.45 * k, prone);
    b.mode = Mode::Prone;
    b.finish("fall_forward", b.endOf(t0 + 1.52 * k));
}

void fallSideways(Builder& b) {
    const double t0 = b.now(), k = b.rng.jitter(0.08);
    const int side = b.rng.below(2);
    const double sg = sideSign(side);
    const dvec3 fl = footH(b, 0, t0), fr = footH(b, 1, t0);
    const double xf = 0.5 * (fl.x + fr.x), zf = 0.5 * (fl.z + fr.z);
    Pose buckle, down;
    buckle.set(ShiftX, xf + 0.10 * sg).set(ShiftZ, zf).set(Height, 0.80).set(PelvisRoll, -0.25 * sg).set(PelvisYaw, 0);
    buckle.set(PelvisPitch, 0.05).set(SpinePitch, 0.1).set(SpineRoll, 0.10 * sg).set(SpineYaw, 0).set(Gaze, 0.3);
    buckle.set(HeadPitch, 0.1).set(HeadYaw, 0).set(HeadRoll, 0);
    buckle.setHand(side, {sg * 0.35, -0.05, 0.15}).setHand(1 - side, {-sg * 0.20, 0.05, 0.30});
    buckle.setPole(0, {0.6, -1.0, 0.0}).setPole(1, {-0.6, -1.0, 0.0});
    down.set(ShiftX, xf + 0.40 * sg).set(ShiftZ, zf - 0.15).set(Height, 0.15).set(PelvisRoll, -0.55 * sg);
    down.set(PelvisPitch, -0.10).set(SpinePitch, 0.20).set(SpineRoll, 0.15 * sg).set(Gaze, 0.0).set(HeadPitch, 0.2);
    down.setHand(side, {sg * 0.42, -0.34, -0.05}).setHand(1 - side, {-sg * 0.05, -0.15, 0.30});
    b.pose(t0, t0 + 0.32 * k, buckle);
    b.pose(t0 + 0.32 * k, t0 + 0.72 * k, down);
    Pose lie = supinePose(xf + 0.32 * sg, zf - 0.45);
    b.pose(t0 + 0.72 * k, t0 + 1.30 * k, lie);
    b.mode = Mode::Supine;
    b.finish("fall_sideways", b.endOf(t0 + 1.38 * k));
}

void fallPushed(Builder& b) {
    const double t0 = b.now(), k = b.rng.jitter(0.08);
    const double h = b.heading(t0);
    const dvec3 base = b.base(t0);
    const dvec3 back = base + rotY(h) * dvec3(0, 0, -0.55);
    const auto feet = b.stanceFeet(Mode::Stand, back, h);
    Pose hit;
    hit.set(ShiftX, 0).set(ShiftZ, -0.08).set(Height, 0.95).set(PelvisYaw, 0).set(PelvisPitch, -0.05).set(PelvisRoll, 0);
    hit.set(SpinePitch, -0.25).set(SpineYaw, 0).set(SpineRoll, 0).set(HeadPitch, 0.3).set(HeadYaw, 0).set(Gaze, 0.4);
    hit.setHand(0, {0.26, 0.12, 0.30}).setHand(1, {-0.26, 0.10, 0.30});
    hit.setPole(0, {0.8, -1.0, 0.0}).setPole(1, {-0.8, -1.0, 0.0});
    b.pose(t0, t0 + 0.12, hit);
    b.moveBase(t0, t0 + 0.55 * k, back, h);
    b.step(1, t0 + 0.05, t0 + 0.30 * k, Builder::plantAt(back, h, -0.10, 0.20, -0.1), 0.04, 0.1);
    b.step(0, t0 + 0.28 * k, t0 + 0.52 * k, feet[0], 0.04, 0.1);
    const double tDown = sitFallBackward(b, t0 + 0.50 * k, 0.95 * k);
    b.finish("fall_pushed", b.endOf(tDown + 0.08));
}

void getUp(Builder& b) {
    const double t0 = b.now(), k = b.rng.jitter(0.08);
    const double tEnd = b.mode == Mode::Prone ? getUpFromProne(b, t0, k) : getUpFromSupine(b, t0, k, Mode::Stand);
    b.finish("get_up", b.endOf(tEnd));
}

}  // namespace fray::demo::detail
