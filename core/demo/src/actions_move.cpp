// Locomotion: one action per step. Step boundaries sit at the middle of the
// stance of the supporting foot +- half a step, i.e. at double-support centres
// for walks and mid-flight for runs. The base path is keyed at the boundaries
// with matched velocities, so consecutive steps chain without speed jumps. The
// swinging foot lands where the body will be at the middle of its stance.
#include <algorithm>
#include <cmath>

#include "actions.h"
#include "rig.h"

namespace fray::demo::detail {

using glm::dvec3;

namespace {

struct GaitParams {
    double stepTime;   // s per step
    double stance;     // s a foot is planted per stride
    double width;      // lateral foot offset (m)
    double lift, toeOff, heelStrike;
    double height;     // desired Hips height
    double bounce;     // running: Hips dip at mid-stance
    double spinePitch;
    double armSwing;   // hand travel forward/back (m)
    bool bentArms;
};

GaitParams paramsOf(Gait g) {
    switch (g) {
        case Gait::Jog: return {0.37, 0.24, 0.07, 0.10, 0.50, 0.15, 0.965, 0.03, 0.10, 0.16, true};
        case Gait::Run: return {0.34, 0.20, 0.06, 0.13, 0.55, 0.15, 0.965, 0.04, 0.15, 0.20, true};
        case Gait::Backpedal: return {0.50, 0.58, 0.10, 0.04, 0.10, 0.0, 0.96, 0.0, -0.02, 0.05, false};
        case Gait::Carry: return {0.56, 0.62, 0.10, 0.045, 0.28, 0.20, 0.96, 0.0, -0.04, 0.0, false};
        case Gait::Walk: break;
    }
    return {0.53, 0.60, 0.09, 0.05, 0.35, 0.25, 0.965, 0.0, 0.04, 0.13, false};
}

dvec3 dirOf(double heading) { return {std::sin(heading), 0.0, std::cos(heading)}; }

// Arms and torso at a step boundary: the arm on the side of the foot that just
// swung forward goes back.
void stepPosture(Builder& b, const GaitParams& gp, Gait gait, int swung, double t0, double t1, double speed,
                 double yawRate, double lean) {
    const double sgB = sideSign(swung);
    Pose p;
    p.set(PelvisYaw, -sgB * (gait == Gait::Run || gait == Gait::Jog ? 0.12 : 0.07));
    p.set(SpineYaw, sgB * (gait == Gait::Run || gait == Gait::Jog ? 0.18 : 0.09));
    p.set(PelvisRoll, std::clamp(-0.05 * yawRate * std::abs(speed) - lean, -0.25, 0.25));
    p.set(SpinePitch, gp.spinePitch).set(PelvisPitch, 0.5 * gp.spinePitch).set(HeadPitch, 0).set(Gaze, 0.8);
    p.set(ShiftX, 0).set(ShiftZ, 0).set(SpineRoll, -0.5 * lean).set(HeadYaw, 0).set(HeadRoll, 0);
    if (gait == Gait::Carry) {
        const Pose c = b.modePose(Mode::Carry);
        for (int s = 0; s < 2; ++s) p.setHand(s, c.hand[static_cast<std::size_t>(s)]);
        p.setPole(0, {0.5, -1.0, -0.3}).setPole(1, {-0.5, -1.0, -0.3});
    } else {
        for (int s = 0; s < 2; ++s) {
            const double sg = sideSign(s);
            const double fwd = (s == swung ? -1.0 : 1.0) * gp.armSwing;
            if (gp.bentArms)
                p.setHand(s, {sg * 0.17, -0.10 + 0.25 * std::max(fwd, 0.0), 0.08 + fwd});
            else
                p.setHand(s, {sg * 0.21, -0.41 + 0.15 * std::max(fwd, 0.0), 0.03 + fwd});
            p.setPole(s, gp.bentArms ? dvec3(sg * 0.4, -0.3, -1.0) : dvec3(sg * 0.3, 0.0, -1.0));
        }
    }
    b.pose(t0, t1, p);
}

}  // namespace

double locoStepKeys(Builder& b, Gait gait, double speed, double yawRate, double lateral, double lean) {
    const GaitParams gp = paramsOf(gait);
    const double t0 = b.now();
    const double t1 = b.endOf(t0 + gp.stepTime * b.rng.jitter(0.03));
    const double Ts = t1 - t0;
    const bool starting = !b.gait.active;
    const int B = starting ? (yawRate > 0 ? 0 : yawRate < 0 ? 1 : b.rng.below(2)) : b.gait.nextSwing;
    const int A = 1 - B;
    const double v0 = starting ? 0.0 : b.gait.speed, r0 = starting ? 0.0 : b.gait.yawRate;
    const double v1 = std::clamp(speed, v0 - 3.0 * Ts, v0 + 2.6 * Ts);
    const double r1 = yawRate;
    const double h0 = b.heading(t0), h1 = h0 + 0.5 * (r0 + r1) * Ts;
    const dvec3 p0 = b.base(t0);
    // A sidestep (lateral, m to the left) moves the base across within the step.
    const dvec3 p1 = p0 + 0.5 * Ts * (v0 * dirOf(h0) + v1 * dirOf(h1)) + lateral * dvec3(std::cos(h1), 0.0, -std::sin(h1));
    const dvec3 vel1 = v1 * dirOf(h1);
    for (Ch c : {BaseX, BaseZ, Heading}) b.hold(c, t0);
    b.key(BaseX, t1, p1.x, vel1.x);
    b.key(BaseZ, t1, p1.z, vel1.z);
    b.key(Heading, t1, h1, r1);
    // The swing foot lands where the base will be at the middle of its stance.
    const double c = t0 + 0.5 * Ts;
    const double cB = c + Ts;
    const double hB = h1 + r1 * (cB - t1);
    const dvec3 pB = p1 + vel1 * (cB - t1);
    const FootPlant plantB = Builder::plantAt(pB, hB, sideSign(B) * gp.width, 0.0, sideSign(B) * 0.06);
    const double land = cB - 0.5 * gp.stance;
    const auto bi = static_cast<std::size_t>(B);
    // A gait change shortens the stance to the new gait's (a jog stance after a walk one).
    double lift = starting ? t0 + 0.08 : std::min(b.gait.liftTime[bi], b.gait.stanceCentre[bi] + 0.5 * gp.stance);
    lift = std::min(lift, land - 0.22);
    const double backwards = v1 < 0 ? 0.3 : 1.0;
    b.step(B, lift, land, plantB, gp.lift, gp.toeOff * backwards, gp.heelStrike * backwards);
    if (starting) {
        b.gait.liftTime[static_cast<std::size_t>(A)] = c + 0.5 * gp.stance;
        b.gait.stanceCentre[static_cast<std::size_t>(A)] = c;
    }
    b.gait.liftTime[bi] = cB + 0.5 * gp.stance;
    b.gait.stanceCentre[bi] = cB;
    b.gait.active = true;
    b.gait.nextSwing = A;
    b.gait.speed = v1;
    b.gait.yawRate = r1;
    // Pelvis height: walking lets the legs' reach make the bob; running dips at mid-stance.
    if (gp.bounce > 0) {
        b.ease(Height, t0, c, gp.height - gp.bounce);
        b.ease(Height, c, t1, gp.height);
    } else {
        b.ease(Height, t0, t1, gp.height);
    }
    stepPosture(b, gp, gait, B, t0, t1, v1, r1, lean);
    b.mode = gait == Gait::Carry ? Mode::Carry : Mode::Stand;
    return t1;
}

void locoStep(Builder& b, Gait gait, double speed, double yawRate, const char* name) {
    b.finish(name, locoStepKeys(b, gait, speed, yawRate, 0.0, 0.0));
}

void locoStop(Builder& b, Gait gait, const char* name) {
    const GaitParams gp = paramsOf(gait);
    const double t0 = b.now();
    const double t1 = b.endOf(t0 + 1.1 * gp.stepTime);
    const double Ts = t1 - t0;
    const int B = b.gait.nextSwing, A = 1 - B;
    const double h1 = b.heading(t0) + 0.5 * b.gait.yawRate * Ts;
    const FootPlant a = b.tl.feet[static_cast<std::size_t>(A)].last();
    dvec3 pEnd = a.ankle - rotY(h1) * dvec3(sideSign(A) * 0.10, 0, 0);
    pEnd.y = 0;
    for (Ch c : {BaseX, BaseZ, Heading}) b.hold(c, t0);
    b.key(BaseX, t1, pEnd.x);
    b.key(BaseZ, t1, pEnd.z);
    b.key(Heading, t1, h1);
    const FootPlant plantB = Builder::plantAt(pEnd, h1, sideSign(B) * 0.10, 0.0, sideSign(B) * 0.10);
    const double land = t0 + 0.72 * Ts;
    const auto bi = static_cast<std::size_t>(B);
    const double lift = std::min({b.gait.liftTime[bi], b.gait.stanceCentre[bi] + 0.5 * gp.stance, land - 0.25});
    b.step(B, lift, land, plantB, gp.lift, gp.toeOff * 0.6, gp.heelStrike * 0.6);
    const Mode m = gait == Gait::Carry ? Mode::Carry : Mode::Stand;
    b.pose(t0, t1, b.modePose(m));
    b.mode = m;
    b.gait = GaitState{};
    b.finish(name, b.endOf(t1 + 0.05));
}

void idleStand(Builder& b, double seconds) {
    const double t0 = b.now();
    const double tEnd = b.endOf(t0 + seconds);
    const Pose s = b.modePose(b.mode == Mode::Carry ? Mode::Carry : Mode::Stand);
    const double tm = t0 + 0.5 * (tEnd - t0);
    const double shift = b.rng.uniform(-0.025, 0.025);
    const double look = b.rng.uniform(-0.4, 0.4);
    Pose mid = s;
    mid.set(ShiftX, shift).set(HeadYaw, look).set(SpinePitch, s.get(SpinePitch) + 0.015);
    if (b.mode != Mode::Carry) {
        mid.setHand(0, s.hand[0] + dvec3(0.0, 0.0, b.rng.uniform(-0.03, 0.03)));
        mid.setHand(1, s.hand[1] + dvec3(0.0, 0.0, b.rng.uniform(-0.03, 0.03)));
    }
    b.pose(t0, tm, mid);
    b.pose(tm, tEnd - 0.02, s);
    b.finish("idle_stand", tEnd);
}

void turnInPlace(Builder& b, double angle, const char* name) {
    const double t0 = b.now();
    const Mode m = b.mode == Mode::Carry ? Mode::Carry : Mode::Stand;
    const int n = std::max(2, static_cast<int>(std::ceil(std::abs(angle) / 0.55)));
    const double h0 = b.heading(t0), dh = angle / n;
    const dvec3 base = b.base(t0);
    const int first = angle > 0 ? 0 : 1;
    const double per = 0.40 * b.rng.jitter(0.05);
    for (int i = 0; i < n; ++i) {
        const int side = (first + i) % 2;
        const auto feet = b.stanceFeet(m, base, h0 + dh * (i + 1));
        b.step(side, t0 + i * per + 0.02, t0 + i * per + 0.38 * per / 0.40, feet[static_cast<std::size_t>(side)], 0.035, 0.10);
    }
    const int last = (first + n) % 2;
    const auto feet = b.stanceFeet(m, base, h0 + angle);
    b.step(last, t0 + n * per + 0.02, t0 + n * per + 0.34, feet[static_cast<std::size_t>(last)], 0.03, 0.05);
    const double tEnd = b.endOf(t0 + n * per + 0.40);
    b.moveBase(t0, t0 + n * per + 0.2, base, h0 + angle);
    b.pose(t0, tEnd - 0.02, b.modePose(m));
    b.finish(name, tEnd);
}

}  // namespace fray::demo::detail
