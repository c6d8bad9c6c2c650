// Boxing / kickboxing attacks, defences, footwork and hit reactions. Every
// action starts and ends in the guard (orthodox: left foot and hand lead).
// Timings are in seconds scaled by the style's tempo; the fast phase of an
// attack is scaled by `strike` only, because the speed of a punch or kick is
// what makes it one.
#include <cmath>

#include "actions.h"
#include "rig.h"

namespace fray::demo::detail {

using glm::dvec3;

namespace {

double strikeTime(Builder& b, double seconds) { return seconds * b.sp.strike * b.rng.jitter(0.03); }

// Guard hand offset with the style's drop applied.
dvec3 guardHand(const Builder& b, int side) {
    const Pose g = b.guardPose();
    return g.hand[static_cast<std::size_t>(side)];
}

}  // namespace

void jab(Builder& b) {
    const double t0 = b.now(), k = b.sp.tempo * b.rng.jitter(0.03), A = b.sp.amplitude;
    const double tE = t0 + strikeTime(b, 0.12);
    const double tH = tE + 0.03 * k;
    const double tR = tH + 0.20 * k;
    const double tEnd = b.endOf(tR + 0.02 * k);
    const Pose g = b.guardPose();
    Pose p = g;
    p.add(PelvisYaw, -0.15 * A).add(SpineYaw, -0.08 * A).add(ShiftZ, 0.06 * A).add(Height, -0.01);
    p.setHand(0, {0.03, 0.23, 0.64}).setPole(0, {0.25, -1.0, 0.0});
    b.pose(t0, tE, p);
    b.pose(tH, tR, g);
    b.finish("jab", tEnd);
}

void cross(Builder& b) {
    const double t0 = b.now(), k = b.k(), A = b.sp.amplitude;
    const double tE = t0 + strikeTime(b, 0.14);
    const double tH = tE + 0.03 * k;
    const double tR = tH + 0.22 * k;
    const double tEnd = b.endOf(tR + 0.03 * k + b.sp.recovery);
    const Pose g = b.guardPose();
    Pose p = g;
    p.add(PelvisYaw, 0.60 * A).add(SpineYaw, 0.05 * A).add(ShiftZ, 0.08 * A).add(Height, -0.02);
    p.setHand(1, {0.0, 0.22, 0.60}).setPole(1, {-0.25, -1.0, 0.0});
    p.setHand(0, {0.09, 0.22 - b.sp.guardDrop, 0.22});
    b.pose(t0, tE, p);
    b.pose(tH, tR, g);
    b.finish("cross", tEnd);
}

void hook(Builder& b, int side) {
    const double t0 = b.now(), k = b.k(), A = b.sp.amplitude;
    const double sg = sideSign(side);
    const double tW = t0 + 0.11 * k;
    const double tE = tW + strikeTime(b, 0.12);
    const double tH = tE + 0.03 * k;
    const double tR = tH + 0.22 * k;
    const double tEnd = b.endOf(tR + 0.03 * k + b.sp.recovery);
    const Pose g = b.guardPose();
    Pose load = g, hit = g;
    if (side == 0) {
        load.add(PelvisYaw, 0.12 * A).setHand(0, {0.24, 0.21 - 0.5 * b.sp.guardDrop, 0.24});
        hit.add(PelvisYaw, -0.50 * A).add(SpineYaw, -0.15 * A).setHand(0, {-0.07, 0.24, 0.43});
    } else {
        load.add(PelvisYaw, -0.12 * A).setHand(1, {-0.25, 0.20 - 0.5 * b.sp.guardDrop, 0.19});
        hit.add(PelvisYaw, 0.70 * A).add(SpineYaw, 0.10 * A).setHand(1, {0.08, 0.24, 0.43});
        hit.setHand(0, {0.09, 0.22 - b.sp.guardDrop, 0.22});
    }
    load.setPole(side, {sg * 0.8, -0.6, -0.2});
    hit.setPole(side, {sg * 1.0, 0.15, -0.2}).add(ShiftZ, 0.04 * A).add(Height, -0.02);
    b.pose(t0, tW, load);
    b.pose(tW, tE, hit);
    b.pose(tH, tR, g);
    b.finish(side == 0 ? "hook_left" : "hook_right", tEnd);
}

void uppercut(Builder& b, int side) {
    const double t0 = b.now(), k = b.k(), A = b.sp.amplitude;
    const double sg = sideSign(side);
    const double tD = t0 + 0.10 * k;
    const double tE = tD + strikeTime(b, 0.13);
    const double tH = tE + 0.03 * k;
    const double tR = tH + 0.22 * k;
    const double tEnd = b.endOf(tR + 0.03 * k + b.sp.recovery);
    const Pose g = b.guardPose();
    Pose dip = g, hit = g;
    dip.add(Height, -0.05 * A).add(SpineRoll, -0.08 * sg * A);
    dip.add(PelvisYaw, (side == 0 ? 0.10 : -0.10) * A);
    dip.setHand(side, {sg * 0.14, 0.0 - 0.3 * b.sp.guardDrop, side == 0 ? 0.24 : 0.20});
    dip.setPole(side, {sg * 0.2, -1.0, 0.2});
    hit.add(Height, 0.01).add(ShiftZ, 0.04 * A);
    hit.add(PelvisYaw, (side == 0 ? -0.35 : 0.55) * A);
    hit.setHand(side, {sg * 0.01, 0.33, 0.42}).setPole(side, {sg * 0.15, -1.0, -0.3});
    if (side == 1) hit.setHand(0, {0.09, 0.22 - b.sp.guardDrop, 0.22});
    b.pose(t0, tD, dip);
    b.pose(tD, tE, hit);
    b.pose(tH, tR, g);
    b.finish(side == 0 ? "uppercut_left" : "uppercut_right", tEnd);
}

void frontKick(Builder& b) {
    const double t0 = b.now(), k = b.k(), A = b.sp.amplitude;
    const int side = 1;
    const FootPlant home = b.tl.feet[1].last();
    const double tS = t0 + 0.14 * k;
    const double tL0 = t0 + 0.06 * k, tL1 = t0 + 0.20 * k;
    const double tC = t0 + 0.24 * k;
    const double tE = tC + strikeTime(b, 0.14);
    const double tH = tE + 0.03 * k;
    const double tRc = tH + 0.13 * k;
    const double tLand = tRc + 0.15 * k;
    const double tEnd = b.endOf(tLand + 0.08 * k + b.sp.recovery);
    const Pose g = b.guardPose();
    Pose shift = g, ext = g, chamber = g;
    shift.set(ShiftX, 0.06).set(ShiftZ, 0.08).set(PelvisYaw, -0.25).set(PelvisPitch, -0.02);
    chamber.setHandChest(1, {-0.20, -0.10, 0.28}).setPole(1, {-0.5, -1.0, 0.0});
    ext.set(ShiftX, 0.06).set(ShiftZ, 0.06).set(PelvisYaw, -0.10).set(PelvisPitch, -0.22 * A);
    ext.add(SpinePitch, -0.10).setHandChest(1, {-0.26, -0.40, -0.05}).setPole(1, {-0.3, -0.3, -1.0});
    chamber.set(ShiftX, 0.06).set(ShiftZ, 0.07).set(PelvisYaw, -0.20).set(PelvisPitch, -0.05);
    b.pose(t0, tS, shift);
    b.pose(tS, tC, chamber);  // the free arm swings down in front of the body, not past the shoulder
    b.pose(tC, tE, ext);
    b.pose(tH, tRc, chamber);
    b.pose(tRc, tEnd - 0.02, g);
    // The kicking leg.
    b.liftFree(side, tL0, tL1);
    Pose chamberFoot, extFoot;
    chamberFoot.setFoot(side, {-0.08, -0.50, 0.15}).setKnee(side, {0, 0.6, 1.0}).set(RFootPitch, 0.2).set(RFootYaw, 0.0);
    extFoot.setFoot(side, {-0.06, -0.10, 0.80}).setKnee(side, {0, 1.0, 0.3}).set(RFootPitch, -0.2);
    b.pose(tL0, tC, chamberFoot);
    b.pose(tC, tE, extFoot);
    b.pose(tH, tRc, chamberFoot);
    b.plantFree(side, tRc, tLand, home);
    b.finish("front_kick", tEnd);
}

void roundhouse(Builder& b, int side) {
    const double t0 = b.now(), A = b.sp.amplitude;
    const double k = std::min(b.sp.tempo, 1.15) * b.rng.jitter(0.02);
    const double sg = sideSign(side);
    const int support = 1 - side;
    const FootPlant home = b.tl.feet[static_cast<std::size_t>(side)].last();
    const FootPlant supportHome = b.tl.feet[static_cast<std::size_t>(support)].last();
    const double tS = t0 + 0.15 * k;
    const double tL0 = t0 + 0.06 * k, tL1 = t0 + 0.22 * k;
    const double tP0 = t0 + 0.10 * k, tP1 = t0 + 0.26 * k;
    const double tC = t0 + 0.26 * k;
    const double tE = tC + 0.15 * b.sp.strike;
    const double tH = tE + 0.03 * k;
    const double tRc = tH + 0.14 * k;
    const double tQ0 = tRc - 0.05 * k, tQ1 = tQ0 + 0.16 * k;
    const double tLand = tRc + 0.17 * k;
    const double tEnd = b.endOf(tLand + 0.10 * k);
    const Pose g = b.guardPose();
    // Right kick (rear leg): hips turn over to the left; left kick: to the right.
    const double yawHit = side == 1 ? 1.0 : -1.7;
    const double spineHit = side == 1 ? -0.65 : 0.7;
    Pose shift = g, ext = g, chamber = g;
    shift.set(ShiftX, 0.07 * -sg).set(ShiftZ, 0.09).set(PelvisYaw, g.get(PelvisYaw) + 0.25 * (yawHit - g.get(PelvisYaw)));
    chamber.set(ShiftX, 0.06 * -sg).set(ShiftZ, 0.08).set(PelvisYaw, g.get(PelvisYaw) + 0.6 * (yawHit - g.get(PelvisYaw)));
    chamber.set(PelvisRoll, 0.25 * sg * A).set(SpineYaw, 0.5 * spineHit);
    chamber.setHandChest(side, {sg * 0.20, -0.10, 0.28}).setPole(side, {sg * 0.5, -1.0, 0.0});
    ext.set(ShiftX, 0.05 * -sg).set(ShiftZ, 0.06).set(PelvisYaw, yawHit).set(PelvisRoll, 0.45 * sg * A);
    ext.set(SpineRoll, -0.15 * sg * A).set(SpineYaw, spineHit).set(PelvisPitch, 0.0);
    ext.setHandChest(side, {sg * 0.26, -0.40, -0.05}).setPole(side, {sg * 0.4, -0.3, -1.0});
    b.pose(t0, tS, shift);
    b.pose(tS, tC, chamber);
    b.pose(tC, tE, ext);
    b.pose(tH, tRc, chamber);
    b.pose(tRc, tEnd, g);
    // Support foot pivots on its ball to follow the hips, and back.
    const double pivotYaw = supportHome.yaw + (side == 1 ? 1.1 : -1.05);
    b.pivotFoot(support, tP0, tP1, pivotYaw);
    b.pivotFoot(support, tQ0, tQ1, supportHome.yaw);
    // Kicking leg.
    b.liftFree(side, tL0, tL1);
    Pose chamberFoot, extFoot, rechamber;
    const glm::dvec3 chamberAt{sg * 0.45, -0.25, side == 1 ? -0.05 : 0.03}, extAt{-sg * 0.18, 0.10, 0.78};
    chamberFoot.setFoot(side, chamberAt).setKnee(side, {0, 0, 1.0});
    // Back from the kick the foot folds in front of the body, not through the hip.
    rechamber.setFoot(side, {-sg * 0.02, -0.30, 0.36}).setKnee(side, {0, 0, 1.0});
    rechamber.set(footYawCh(side), 0.0).set(footPitchCh(side), 0.6);
    chamberFoot.set(footYawCh(side), 0.0).set(footPitchCh(side), 0.7);
    extFoot.setFoot(side, extAt).setKnee(side, {0, 0, 1.0});
    extFoot.set(footYawCh(side), 0.0).set(footPitchCh(side), 0.9);
    b.pose(tL0, tC, chamberFoot);
    b.pose(tC, tE, extFoot);
    // The foot sweeps round the hip on an arc (a via key in motion), not across it.
    const glm::dvec3 via{sg * 0.30, -0.02, 0.52};
    const glm::dvec3 viaSlope = 1.4 * (extAt - chamberAt) / (tE - tC);
    for (int a = 0; a < 3; ++a) b.key(footCh(side, a), 0.5 * (tC + tE), via[a], viaSlope[a]);
    b.pose(tH, tRc, rechamber);
    b.plantFree(side, tRc, tLand, home);
    b.finish(side == 0 ? "roundhouse_left" : "roundhouse_right", tEnd);
}

void kneeStrike(Builder& b) {
    const double t0 = b.now(), k = b.k(), A = b.sp.amplitude;
    const int side = 1;
    const FootPlant home = b.tl.feet[1].last();
    const double tS = t0 + 0.12 * k;
    const double tL0 = t0 + 0.04 * k, tL1 = t0 + 0.16 * k;
    const double tE = tL1 + strikeTime(b, 0.15);
    const double tH = tE + 0.04 * k;
    const double tRc = tH + 0.10 * k;
    const double tLand = tRc + 0.14 * k;
    const double tEnd = b.endOf(tLand + 0.10 * k + b.sp.recovery);
    const Pose g = b.guardPose();
    Pose clinch = g, hit = g;
    clinch.set(ShiftX, 0.05).set(ShiftZ, 0.06).set(PelvisYaw, -0.30);
    clinch.setHand(0, {0.09, 0.18 - b.sp.guardDrop, 0.42}).setHand(1, {-0.09, 0.18 - b.sp.guardDrop, 0.42});
    hit.set(ShiftX, 0.05).set(ShiftZ, 0.10).set(PelvisYaw, -0.15).set(PelvisPitch, -0.25 * A);
    hit.setHand(0, {0.07, 0.04, 0.36}).setHand(1, {-0.07, 0.04, 0.36});
    b.pose(t0, tS, clinch);
    b.pose(tL1, tE, hit);
    b.pose(tH, tRc, clinch);
    b.pose(tRc, tEnd - 0.02, g);
    b.liftFree(side, tL0, tL1);
    Pose back, up, low;
    back.setFoot(side, {-0.12, -0.62, -0.12}).setKnee(side, {0, 0.2, 1.0}).set(RFootPitch, 0.4).set(RFootYaw, 0.0);
    up.setFoot(side, {-0.09, -0.40, 0.22}).setKnee(side, {0, 0.3, 1.0}).set(RFootPitch, 0.6);
    b.pose(tL0, tL1, back);
    b.pose(tL1, tE, up);
    b.pose(tH, tRc, back);
    b.plantFree(side, tRc, tLand, home);
    b.finish("knee_strike", tEnd);
}

// The shape every defence shares: move into `p` by tIn, hold it until tHold,
// come back to guard by tBack, then recover.
static void holdThenRecover(Builder& b, std::string_view name, const Pose& p, double tIn, double tHold, double tBack,
                     double k) {
    const double t0 = b.now();
    const double tEnd = b.endOf(tBack + 0.03 * k + b.sp.recovery);
    b.pose(t0, tIn, p);
    b.pose(tHold, tBack, b.guardPose());
    b.finish(name, tEnd);
}

void blockHigh(Builder& b) {
    const double t0 = b.now(), k = b.k();
    const double tU = t0 + 0.10 * k, tD0 = tU + 0.22 * k, tD1 = tD0 + 0.18 * k;
    Pose p = b.guardPose();
    p.add(Height, -0.02).add(SpinePitch, 0.08).add(HeadPitch, 0.15);
    p.setHand(0, {0.07, 0.36 - 0.3 * b.sp.guardDrop, 0.22}).setHand(1, {-0.07, 0.36 - 0.3 * b.sp.guardDrop, 0.22});
    p.setPole(0, {0.5, -1.0, -0.2}).setPole(1, {-0.5, -1.0, -0.2});
    holdThenRecover(b, "block_high", p, tU, tD0, tD1, k);
}

void blockLow(Builder& b) {
    const double t0 = b.now(), k = b.k(), A = b.sp.amplitude;
    const double tU = t0 + 0.12 * k, tD0 = tU + 0.20 * k, tD1 = tD0 + 0.20 * k;
    Pose p = b.guardPose();
    p.add(Height, -0.05 * A).add(SpinePitch, 0.18 * A).add(PelvisYaw, -0.10 * A);
    p.setHand(0, {0.12, 0.02, 0.17}).setHand(1, {-0.11, 0.04, 0.17});
    p.setPole(0, {0.1, -1.0, 0.2}).setPole(1, {-0.1, -1.0, 0.2});
    holdThenRecover(b, "block_low", p, tU, tD0, tD1, k);
}

void parry(Builder& b) {
    const double t0 = b.now(), k = b.k();
    const double tP = t0 + strikeTime(b, 0.09), tH = tP + 0.03 * k, tR = tH + 0.20 * k;
    Pose p = b.guardPose();
    p.add(PelvisYaw, 0.08).setHand(1, {0.10, 0.22, 0.36}).setPole(1, {-0.6, -1.0, 0.0});
    holdThenRecover(b, "parry", p, tP, tH, tR, k);
}

void slip(Builder& b, int side) {
    const double t0 = b.now(), k = b.k(), A = b.sp.amplitude, sg = sideSign(side);
    const double tO = t0 + 0.15 * k, tH = tO + 0.08 * k, tB = tH + 0.18 * k;
    Pose p = b.guardPose();
    p.add(Height, -0.04 * A).add(ShiftX, 0.07 * sg * A).add(SpineRoll, -0.22 * sg * A).add(SpineYaw, -0.10 * sg * A);
    holdThenRecover(b, side == 0 ? "slip_left" : "slip_right", p, tO, tH, tB, k);
}

void duck(Builder& b) {
    const double t0 = b.now(), k = b.k(), A = b.sp.amplitude;
    const double tD = t0 + 0.18 * k, tH = tD + 0.12 * k, tU = tH + 0.25 * k;
    Pose p = b.guardPose();
    p.add(Height, -0.22 * A).add(SpinePitch, 0.30 * A).add(PelvisPitch, 0.12 * A).add(ShiftZ, -0.02);
    holdThenRecover(b, "duck", p, tD, tH, tU, k);
}

void swayBack(Builder& b) {
    const double t0 = b.now(), k = b.k(), A = b.sp.amplitude;
    const double tO = t0 + 0.15 * k, tH = tO + 0.10 * k, tB = tH + 0.25 * k;
    Pose p = b.guardPose();
    p.add(ShiftZ, -0.10 * A).add(SpinePitch, -0.32 * A).add(PelvisPitch, -0.12 * A).add(Height, -0.02).add(HeadPitch, 0.10);
    holdThenRecover(b, "sway_back", p, tO, tH, tB, k);
}

void guardStep(Builder& b, int direction) {
    static const char* names[] = {"step_forward", "step_back", "step_left", "step_right"};
    const double t0 = b.now(), k = b.k(), A = b.sp.amplitude;
    const double h = b.heading(t0);
    const dvec3 base = b.base(t0);
    const double fb = 0.30 * A * b.rng.jitter(0.1), lr = 0.25 * A * b.rng.jitter(0.1);
    const dvec3 d[] = {{0, 0, fb}, {0, 0, -fb}, {lr, 0, 0}, {-lr, 0, 0}};
    const int first = (direction == 0 || direction == 2) ? 0 : 1;
    const dvec3 to = base + rotY(h) * d[direction];
    const auto feet = b.stanceFeet(Mode::Guard, to, h);
    const double tEnd = b.endOf(t0 + 0.46 * k + b.sp.recovery);
    const Pose g = b.guardPose();
    b.moveBase(t0, t0 + 0.40 * k, to, h);
    b.ease(Height, t0, t0 + 0.20 * k, g.get(Height) - 0.015);
    b.ease(Height, t0 + 0.20 * k, t0 + 0.42 * k, g.get(Height));
    b.step(first, t0 + 0.04 * k, t0 + 0.26 * k, feet[static_cast<std::size_t>(first)], 0.035, 0.12);
    b.step(1 - first, t0 + 0.20 * k, t0 + 0.42 * k, feet[static_cast<std::size_t>(1 - first)], 0.035, 0.12);
    b.finish(names[direction], tEnd);
}

void pivot(Builder& b, int side) {
    const double t0 = b.now(), k = b.k(), A = b.sp.amplitude;
    const double h = b.heading(t0), to = h + sideSign(side) * 0.75 * A * b.rng.jitter(0.1);
    const dvec3 base = b.base(t0);
    const auto feet = b.stanceFeet(Mode::Guard, base, to);
    const double tEnd = b.endOf(t0 + 0.52 * k + b.sp.recovery);
    b.moveBase(t0, t0 + 0.46 * k, base, to);
    b.step(0, t0 + 0.04 * k, t0 + 0.24 * k, feet[0], 0.02, 0.05);
    b.step(1, t0 + 0.18 * k, t0 + 0.46 * k, feet[1], 0.035, 0.10);
    b.finish(side == 0 ? "pivot_left" : "pivot_right", tEnd);
}

void guardIdle(Builder& b, double seconds) {
    const double t0 = b.now();
    const double tEnd = b.endOf(t0 + seconds);
    const Pose g = b.guardPose();
    const bool tired = b.sp.style == Style::Tired;
    const double half = tired ? 0.8 : 0.26;  // bounce or breathing half-period
    double t = t0;
    int i = 0;
    b.hold(Height, t0);
    while (t + 2 * half < tEnd - 0.05) {
        t += half;
        const double dy = (i % 2 == 0 ? -1.0 : 0.3) * b.sp.bounce;
        b.key(Height, t, g.get(Height) + dy, 0.0, Interp::Cubic);
        if (tired) b.key(SpinePitch, t, g.get(SpinePitch) + (i % 2 == 0 ? 0.03 : -0.01), 0.0, Interp::Cubic);
        ++i;
    }
    // Small hand adjustments, then back exactly to the guard.
    const double tm = t0 + 0.5 * (tEnd - t0);
    for (int side = 0; side < 2; ++side) {
        const dvec3 h = guardHand(b, side) + dvec3(b.rng.uniform(-0.02, 0.02), b.rng.uniform(-0.02, 0.02), b.rng.uniform(-0.02, 0.02));
        b.hand(side, t0, tm, h);
        b.hand(side, tm, tEnd - 0.02, guardHand(b, side));
    }
    b.ease(Height, t, tEnd - 0.02, g.get(Height));
    b.ease(SpinePitch, t, tEnd - 0.02, g.get(SpinePitch));
    b.finish("guard_idle", tEnd);
}

void toGuard(Builder& b) {
    const double t0 = b.now(), k = b.rng.jitter(0.05) * b.sp.tempo;
    const double h = b.heading(t0);
    const auto feet = b.stanceFeet(Mode::Guard, b.base(t0), h);
    b.mode = Mode::Guard;
    const double tEnd = b.endOf(t0 + 0.72 * k);
    b.step(0, t0 + 0.10 * k, t0 + 0.38 * k, feet[0], 0.05, 0.15);
    b.step(1, t0 + 0.30 * k, t0 + 0.62 * k, feet[1], 0.05, 0.15);
    b.pose(t0, t0 + 0.62 * k, b.guardPose());
    b.finish("to_guard", tEnd);
}

void toStand(Builder& b) {
    const double t0 = b.now(), k = b.rng.jitter(0.05) * b.sp.tempo;
    const double h = b.heading(t0);
    const auto feet = b.stanceFeet(Mode::Stand, b.base(t0), h);
    b.mode = Mode::Stand;
    const double tEnd = b.endOf(t0 + 0.80 * k);
    b.step(1, t0 + 0.08 * k, t0 + 0.38 * k, feet[1], 0.05, 0.15);
    b.step(0, t0 + 0.32 * k, t0 + 0.64 * k, feet[0], 0.05, 0.15);
    b.pose(t0, t0 + 0.70 * k, b.modePose(Mode::Stand));
    b.finish("to_stand", tEnd);
}

void headSnap(Builder& b) {
    const double t0 = b.now(), k = b.k();
    const double tHit = t0 + 0.08;
    const double tR0 = tHit + 0.10, tR1 = tR0 + 0.36 * k;
    const double tEnd = b.endOf(tR1 + 0.03 + b.sp.recovery);
    const Pose g = b.guardPose();
    Pose p = g;
    p.add(HeadPitch, -0.45).add(SpinePitch, -0.12).add(ShiftZ, -0.04).set(HeadYaw, b.rng.uniform(-0.25, 0.25));
    b.pose(t0, tHit, p);
    Pose arms;  // the arms react a little slower than the head
    arms.setHand(0, {0.15, 0.30, 0.18}).setHand(1, {-0.15, 0.28, 0.14});
    arms.setPole(0, {0.8, -0.4, 0.4}).setPole(1, {-0.8, -0.4, 0.4});
    b.pose(t0, tHit + 0.10, arms);
    b.pose(tR0, tR1, g);
    b.finish("head_snap", tEnd);
}

void bodyStagger(Builder& b) {
    const double t0 = b.now(), k = b.k();
    const double h = b.heading(t0);
    const dvec3 to = b.base(t0) + rotY(h) * dvec3(0, 0, -0.14);
    const auto feet = b.stanceFeet(Mode::Guard, to, h);
    const double tHit = t0 + 0.10;
    const double tEnd = b.endOf(t0 + 0.62 + 0.30 * k + b.sp.recovery);
    const Pose g = b.guardPose();
    Pose p = g;
    p.add(SpinePitch, 0.35).add(Height, -0.07).add(ShiftZ, -0.05).add(HeadPitch, 0.1);
    p.setHand(0, {0.12, 0.04, 0.20}).setHand(1, {-0.12, 0.02, 0.18});
    b.pose(t0, tHit, p);
    b.moveBase(t0, t0 + 0.60, to, h);
    b.step(1, t0 + 0.08, t0 + 0.34, feet[1], 0.03, 0.1);
    b.step(0, t0 + 0.38, t0 + 0.60, feet[0], 0.03, 0.1);
    b.pose(t0 + 0.32, t0 + 0.62 + 0.28 * k, g);
    b.finish("body_stagger", tEnd);
}

void knockedBack(Builder& b) {
    const double t0 = b.now(), k = b.k();
    const double h = b.heading(t0);
    const dvec3 base = b.base(t0);
    auto back = [&](double z) { return b.stanceFeet(Mode::Guard, base + rotY(h) * dvec3(0, 0, -z), h); };
    const double tEnd = b.endOf(t0 + 1.0 + 0.32 * k + b.sp.recovery);
    const Pose g = b.guardPose();
    Pose hit = g, flail = g;
    hit.add(SpinePitch, -0.28).add(HeadPitch, -0.35).add(ShiftZ, -0.10).add(Height, -0.02);
    hit.hasHand = {false, false};
    flail = hit;
    flail.add(SpinePitch, 0.12).add(HeadPitch, 0.15).set(ShiftZ, -0.06).add(Height, -0.02);
    flail.setHand(0, {0.32, 0.34, 0.14}).setHand(1, {-0.32, 0.32, 0.12});
    flail.setPole(0, {1.0, -0.3, -0.3}).setPole(1, {-1.0, -0.3, -0.3});
    b.pose(t0, t0 + 0.10, hit);
    Pose arms;
    arms.setHand(0, flail.hand[0]).setHand(1, flail.hand[1]).setPole(0, {1.0, -0.3, -0.3}).setPole(1, {-1.0, -0.3, -0.3});
    b.pose(t0, t0 + 0.24, arms);
    flail.hasHand = {false, false};
    b.pose(t0 + 0.10, t0 + 0.55, flail);
    b.pose(t0 + 0.80, t0 + 1.0 + 0.30 * k, g);
    b.moveBase(t0, t0 + 0.92, base + rotY(h) * dvec3(0, 0, -0.75), h);
    b.step(1, t0 + 0.05, t0 + 0.30, back(0.35)[1], 0.04, 0.1);
    b.step(0, t0 + 0.28, t0 + 0.54, back(0.62)[0], 0.04, 0.1);
    b.step(1, t0 + 0.52, t0 + 0.76, back(0.75)[1], 0.035, 0.1);
    b.step(0, t0 + 0.74, t0 + 0.94, back(0.75)[0], 0.03, 0.05);
    b.finish("knocked_back", tEnd);
}

void knockedDown(Builder& b) {
    const double t0 = b.now(), k = b.k(0.03);
    const Pose g = b.guardPose();
    Pose hit = g;
    hit.add(HeadPitch, -0.45).add(SpinePitch, -0.20).add(ShiftZ, -0.06).set(HeadYaw, b.rng.uniform(-0.3, 0.3));
    hit.hasHand = {false, false};  // the arms go up with the fall that follows
    b.pose(t0, t0 + 0.09, hit);
    const double tDown = sitFallBackward(b, t0 + 0.09, 0.9);
    const double tUp = getUpFromSupine(b, tDown + 0.6 * k * b.rng.jitter(0.2), k, Mode::Guard);
    b.finish("knocked_down", b.endOf(tUp + b.sp.recovery));
}

}  // namespace fray::demo::detail
