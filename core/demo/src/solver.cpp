#include "solver.h"

#include <algorithm>
#include <cmath>

#include <glm/gtx/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include "fray/demo/demo_actor.h"

namespace fray::demo::detail {

using glm::dquat;
using glm::dvec3;

// ---- footstep schedule -------------------------------------------------------

void FootSchedule::swing(double t0, double t1, const FootPlant& to, double lift, double toeOff, double heelStrike) {
    FootSwing s;
    s.t0 = std::max(t0, lastTime());
    s.t1 = std::max(t1, s.t0);
    s.from = last();
    s.to = to;
    s.lift = lift;
    s.toeOff = toeOff;
    s.heelStrike = heelStrike;
    swings_.push_back(s);
}

FootSample FootSchedule::at(double t) const {
    const auto it = std::upper_bound(swings_.begin(), swings_.end(), t,
                                     [](double x, const FootSwing& s) { return x < s.t0; });
    FootSample out;
    if (it == swings_.begin()) {
        out.ankle = initial_.ankle;
        out.yaw = initial_.yaw;
        return out;
    }
    const FootSwing& s = *(it - 1);
    if (t >= s.t1) {
        out.ankle = s.to.ankle;
        out.yaw = s.to.yaw;
        return out;
    }
    const double u = (t - s.t0) / (s.t1 - s.t0);
    const double h = smootherstep(u);
    // Toes down early (toe-off), toes up late (heel strike); the ankle rises by
    // what keeps the toe or heel clear of the floor.
    const double pitch = s.toeOff * pulse(u / 0.45) - s.heelStrike * pulse((u - 0.55) / 0.45);
    const double clear = 0.15 * std::max(pitch, 0.0) + 0.07 * std::max(-pitch, 0.0);
    out.ankle = glm::mix(s.from.ankle, s.to.ankle, h);
    out.ankle.y += s.lift * pulse(u) + clear;
    out.yaw = s.from.yaw + (s.to.yaw - s.from.yaw) * h;
    out.pitch = pitch;
    out.planted = false;
    return out;
}

Timeline::Timeline() {
    auto init = [&](Ch c, double v) { ch[static_cast<std::size_t>(c)] = Curve(v); };
    init(Height, 0.99);
    init(Gaze, 0.8);
    init(LHandX, 0.21), init(LHandY, -0.42), init(LHandZ, 0.03);
    init(RHandX, -0.21), init(RHandY, -0.42), init(RHandZ, 0.03);
    init(LPoleX, 0.3), init(LPoleY, 0.0), init(LPoleZ, -1.0);
    init(RPoleX, -0.3), init(RPoleY, 0.0), init(RPoleZ, -1.0);
    init(LKneeZ, 1.0), init(RKneeZ, 1.0);
    init(LFloorDir, 1.0), init(RFloorDir, 1.0);
    init(LFootX, 0.1), init(LFootY, -0.85), init(RFootX, -0.1), init(RFootY, -0.85);
}

// ---- rotations ---------------------------------------------------------------

dquat rotX(double a) { return glm::angleAxis(a, dvec3(1, 0, 0)); }
dquat rotY(double a) { return glm::angleAxis(a, dvec3(0, 1, 0)); }
dquat rotZ(double a) { return glm::angleAxis(a, dvec3(0, 0, 1)); }
dquat yawPitchRoll(double yaw, double pitch, double roll) { return rotY(yaw) * rotX(pitch) * rotZ(roll); }

dquat chestRotationH(double py, double pp, double pr, double sp, double sy, double sr) {
    const dquat s = yawPitchRoll(sy / 3, sp / 3, sr / 3);
    return yawPitchRoll(py, pp, pr) * s * s * s;
}

dvec3 chestOffsetH(double py, double pp, double pr, double sp, double sy, double sr) {
    const dquat p = yawPitchRoll(py, pp, pr);
    const dquat s = yawPitchRoll(sy / 3, sp / 3, sr / 3);
    return p * restOffset(kSpine) + p * s * restOffset(kSpine1) + p * s * s * restOffset(kSpine2);
}

namespace {

// Rotation taking the orthonormal pair (d0, n0) to (d, n).
dquat frameRotation(const dvec3& d0, const dvec3& n0, const dvec3& d, const dvec3& n) {
    const glm::dmat3 a(d0, n0, glm::cross(d0, n0));
    const glm::dmat3 b(d, n, glm::cross(d, n));
    return glm::normalize(glm::quat_cast(b * glm::transpose(a)));
}

dquat slerpShort(dquat a, dquat b, double w) {
    if (w <= 0) return a;
    if (w >= 1) return b;
    if (glm::dot(a, b) < 0) b = -b;
    return glm::normalize(glm::slerp(a, b, w));
}

struct Limb {
    dquat upper, lower;
    dvec3 bend;  // unit direction the middle joint is displaced to
};

// Two-bone IK: root -> target with bone lengths a, b; the middle joint bends
// toward `pole`. restDir is both bones' rest direction, restNormal the hinge
// axis in the rest pose (the middle joint then rotates about it only).
Limb solveLimb(const dvec3& root, const dvec3& target, const dvec3& pole, double a, double b, const dvec3& restDir,
               const dvec3& restNormal, bool soft) {
    dvec3 v = target - root;
    double d = glm::length(v);
    const dvec3 dir = d > 1e-9 ? v / d : -restNormal;
    // Arms: soft limit well short of straight. Legs: exact up to the reach the
    // pelvis guarantees to supporting legs (RigDims::legReach), soft beyond.
    d = soft ? smin(d, (a + b) * 0.985, 0.05) : smin(d, (a + b) * 0.998, (a + b) * 0.0125);
    d = std::max(d, std::abs(a - b) + 0.14);
    dvec3 perp = pole - glm::dot(pole, dir) * dir;
    if (glm::length(perp) < 1e-6) perp = glm::cross(dir, std::abs(dir.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 0, 1));
    perp = glm::normalize(perp);
    const double cosA = std::clamp((a * a + d * d - b * b) / (2 * a * d), -1.0, 1.0);
    const double sinA = std::sqrt(std::max(0.0, 1 - cosA * cosA));
    const dvec3 mid = root + a * (cosA * dir + sinA * perp);
    const dvec3 end = root + d * dir;
    const dvec3 n = glm::normalize(glm::cross(perp, dir));
    const dvec3 upperDir = glm::normalize(mid - root);
    const dvec3 lowerDir = glm::normalize(end - mid);
    return {frameRotation(restDir, restNormal, upperDir, n), frameRotation(restDir, restNormal, lowerDir, n), perp};
}

}  // namespace

void solveFrame(const Timeline& tl, double t, SolvedFrame& out) {
    using D = RigDims;
    std::array<double, kChannelCount> v;
    for (int c = 0; c < kChannelCount; ++c) v[static_cast<std::size_t>(c)] = tl.ch[static_cast<std::size_t>(c)].value(t);
    auto V = [&](Ch c) { return v[static_cast<std::size_t>(c)]; };

    auto& L = out.local;
    auto& W = out.world;
    std::array<dquat, kJointCount> Q;  // world rotations

    const dquat H = rotY(V(Heading));
    dvec3 pelvis = dvec3(V(BaseX), 0, V(BaseZ)) + H * dvec3(V(ShiftX), 0, V(ShiftZ));
    const dquat pelvisRot = H * yawPitchRoll(V(PelvisYaw), V(PelvisPitch), V(PelvisRoll));

    // Feet: schedule sample, free weight, and the pelvis height the legs allow.
    std::array<FootSample, 2> fs;
    std::array<double, 2> w;
    double y = V(Height);
    for (int side = 0; side < 2; ++side) {
        const auto s = static_cast<std::size_t>(side);
        fs[s] = tl.feet[s].at(t);
        w[s] = clamp01(V(freeCh(side)));
        const dvec3 hip = pelvisRot * restOffset(side == 0 ? kLUpLeg : kRUpLeg);
        const double dx = fs[s].ankle.x - (pelvis.x + hip.x), dz = fs[s].ankle.z - (pelvis.z + hip.z);
        const double vert = std::sqrt(std::max(D::legReach * D::legReach - dx * dx - dz * dz, 0.0025));
        const double maxY = fs[s].ankle.y + vert - hip.y + 4.0 * w[s] * w[s];
        y = smin(y, maxY, 0.08);
    }
    pelvis.y = y;
    out.root = pelvis;

    L[kHips] = pelvisRot;
    Q[kHips] = pelvisRot;
    W[kHips] = pelvis;
    const dquat s = yawPitchRoll(V(SpineYaw) / 3, V(SpinePitch) / 3, V(SpineRoll) / 3);
    for (int j : {kSpine, kSpine1, kSpine2}) {
        const int p = parentOf(j);
        L[j] = s;
        Q[j] = Q[p] * s;
        W[j] = W[p] + Q[p] * restOffset(j);
    }
    const double g = V(Gaze);
    const double hp = V(HeadPitch) - g * (V(PelvisPitch) + V(SpinePitch));
    const double hy = V(HeadYaw) - g * (V(PelvisYaw) + V(SpineYaw));
    const double hr = V(HeadRoll) - g * (V(PelvisRoll) + V(SpineRoll));
    L[kNeck] = yawPitchRoll(0.4 * hy, 0.4 * hp, 0.4 * hr);
    L[kHead] = yawPitchRoll(0.6 * hy, 0.6 * hp, 0.6 * hr);
    for (int j : {kNeck, kHead}) {
        const int p = parentOf(j);
        Q[j] = Q[p] * L[j];
        W[j] = W[p] + Q[p] * restOffset(j);
    }

    // Arms: clavicle follows the hand target (protraction / elevation), then IK.
    for (int side = 0; side < 2; ++side) {
        const double sg = sideSign(side);
        const int clav = side == 0 ? kLClavicle : kRClavicle;
        const int arm = clav + 1, fore = clav + 2, hand = clav + 3, index = clav + 4;
        const dvec3 tc(V(handCh(side, 0)), V(handCh(side, 1)), V(handCh(side, 2)));
        const dvec3 pc(V(poleCh(side, 0)), V(poleCh(side, 1)), V(poleCh(side, 2)));
        const double protract = 0.30 * smoothstep((tc.z - 0.20) / 0.40);
        const double elevate = 0.28 * smoothstep((tc.y - 0.12) / 0.35);
        L[clav] = rotY(-sg * protract) * rotZ(sg * elevate);
        Q[clav] = Q[kSpine2] * L[clav];
        W[clav] = W[kSpine2] + Q[kSpine2] * restOffset(clav);
        W[arm] = W[clav] + Q[clav] * restOffset(arm);
        dvec3 target = W[kSpine2] + Q[kSpine2] * tc;
        target.y = smax(target.y, 0.06, 0.04);  // wrists stay above the floor
        // The authored pole is where the elbow points for a neutral reach d0
        // (forward, down, out); for the actual reach it is swung along with the
        // arm (shortest arc). That is smooth everywhere except for reaches up
        // behind the other shoulder, and gives elbows back when the arms hang
        // and forward when the hands are overhead.
        const dvec3 d0 = glm::normalize(dvec3(sg * 0.3, -0.5, 0.8));
        const dvec3 shoulderC = glm::inverse(Q[kSpine2]) * (W[arm] - W[kSpine2]);
        const dvec3 toHand = tc - shoulderC;
        const dvec3 reach = glm::length(toHand) > 1e-6 ? glm::normalize(toHand) : d0;
        dvec3 p0 = pc - glm::dot(pc, d0) * d0;
        p0 = glm::length(p0) > 1e-6 ? glm::normalize(p0) : glm::normalize(dvec3(sg * 0.3, -0.8, -0.5));
        const dvec3 pole = Q[kSpine2] * (glm::rotation(d0, reach) * p0);
        const Limb limb =
            solveLimb(W[arm], target, pole, D::upperArm, D::foreArm, dvec3(sg, 0, 0), dvec3(0, -sg, 0), true);
        Q[arm] = limb.upper;
        Q[fore] = limb.lower;
        L[arm] = glm::inverse(Q[clav]) * Q[arm];
        L[fore] = glm::inverse(Q[arm]) * Q[fore];
        W[fore] = W[arm] + Q[arm] * restOffset(fore);
        W[hand] = W[fore] + Q[fore] * restOffset(hand);
        // Near the floor the wrist bends the hand flat (away from the elbow, as
        // when pushing on the floor) instead of into the floor.
        const dvec3 foreDir = Q[fore] * dvec3(sg, 0, 0);
        const double flat = smoothstep((0.22 - W[hand].y) / 0.14) * smoothstep(-foreDir.y / 0.5);
        dquat bend(1, 0, 0, 0);
        if (flat > 0) {
            const dvec3 axis = glm::normalize(glm::cross(foreDir, -limb.bend));
            bend = glm::angleAxis(1.2 * flat, axis);
        }
        Q[hand] = bend * Q[fore];
        Q[index] = Q[hand];
        L[hand] = glm::inverse(Q[fore]) * Q[hand];
        L[index] = dquat(1, 0, 0, 0);
        W[index] = W[hand] + Q[hand] * restOffset(index);
    }

    // Legs: planted/swing ankle from the schedule blended with the free target.
    for (int side = 0; side < 2; ++side) {
        const auto si = static_cast<std::size_t>(side);
        const int up = side == 0 ? kLUpLeg : kRUpLeg;
        const int knee = up + 1, foot = up + 2, toe = up + 3;
        W[up] = pelvis + pelvisRot * restOffset(up);
        dvec3 freeTarget = pelvis + H * dvec3(V(footCh(side, 0)), V(footCh(side, 1)), V(footCh(side, 2)));
        dvec3 poleFree = H * dvec3(V(kneeCh(side, 0)), V(kneeCh(side, 1)), V(kneeCh(side, 2)));
        const double floorW = clamp01(V(floorCh(side)));
        if (floorW > 0) {
            // Knee on the floor (7 cm) below/ahead of or behind the hip, shin back, toes tucked (ankle 16 cm).
            const double dirSign = std::clamp(V(floorDirCh(side)), -1.0, 1.0);
            const dvec3 fwd = H * dvec3(0, 0, 1);
            // Thigh cosine softly capped below 1: the knee swings forward at a finite
            // rate as the hips come down past thigh height (it floats a little there).
            const double dy = W[up].y - 0.07;
            const double c = std::clamp(smin(dy / D::thigh, 1.0, 0.1), -1.0, 1.0);
            const dvec3 kneeAt = dvec3(W[up].x, W[up].y - D::thigh * c, W[up].z) +
                                 fwd * (dirSign * 0.998 * D::thigh * std::sqrt(1 - c * c));
            const dvec3 ankle = kneeAt + dvec3(0, 0.09, 0) - fwd * (0.998 * std::sqrt(D::shin * D::shin - 0.09 * 0.09));
            freeTarget = glm::mix(freeTarget, ankle, floorW);
            poleFree = glm::mix(poleFree, H * dvec3(0, 0, 1), floorW);
        }
        const dvec3 target = glm::mix(fs[si].ankle, freeTarget, w[si]);
        // Knee pole: where the knee points for a leg hanging straight down (over
        // the toes of a planted foot, or authored for a free leg), swung along
        // with the leg by the shortest arc: a lifted leg's knee goes up, a leg
        // lying on the floor keeps its knee up. Singular only for a leg pointing
        // straight up.
        const dvec3 polePlant = rotY(fs[si].yaw) * dvec3(0, 0, 1);
        dvec3 pole0 = glm::mix(polePlant, poleFree, w[si]);
        pole0.y = 0;
        pole0 = glm::length(pole0) > 1e-6 ? glm::normalize(pole0) : H * dvec3(0, 0, 1);
        const dvec3 toAnkle = target - W[up];
        const dvec3 legDir = glm::length(toAnkle) > 1e-6 ? glm::normalize(toAnkle) : dvec3(0, -1, 0);
        const dvec3 pole = glm::rotation(dvec3(0, -1, 0), legDir) * pole0;
        const Limb limb = solveLimb(W[up], target, pole, D::thigh, D::shin, dvec3(0, -1, 0), dvec3(1, 0, 0), false);
        Q[up] = limb.upper;
        Q[knee] = limb.lower;
        // Planted / swinging feet are oriented in the world; a free foot keeps
        // its angle to the shin (an ankle locked in a kick, toes tucked when kneeling).
        W[knee] = W[up] + Q[up] * restOffset(knee);
        W[foot] = W[knee] + Q[knee] * restOffset(foot);
        const dquat plantRot = rotY(fs[si].yaw) * rotX(fs[si].pitch);
        const dquat freeRot = Q[knee] * rotX(V(footPitchCh(side))) * rotY(V(footYawCh(side)));
        dquat footRot = slerpShort(plantRot, freeRot, w[si]);
        if (!(fs[si].planted && w[si] <= 1e-9)) {
            // A moving foot never digs its toes into the floor: flex the ankle up
            // (zero correction while the toe is 2 cm or more above the floor).
            const double d = 0.02 - (W[foot].y + (footRot * restOffset(toe)).y);
            if (d > 0) {
                const double raise = d < 0.004 ? d * d / 0.008 : d - 0.002;
                const double slope = smax((footRot * dvec3(0, D::toeZ, -D::toeY)).y, 0.04, 0.02);
                footRot = footRot * rotX(-std::min(1.2, 1.5 * raise / slope));
            }
        }
        Q[foot] = footRot;
        Q[toe] = footRot;
        L[up] = glm::inverse(pelvisRot) * Q[up];
        L[knee] = glm::inverse(Q[up]) * Q[knee];
        L[foot] = glm::inverse(Q[knee]) * footRot;
        L[toe] = dquat(1, 0, 0, 0);
        W[toe] = W[foot] + Q[foot] * restOffset(toe);
        out.contact[si] = fs[si].planted && w[si] <= 1e-9;
    }
}

Motion synthesize(const Timeline& timeline, int frameCount, std::vector<std::uint8_t>& leftContact,
                  std::vector<std::uint8_t>& rightContact) {
    Motion motion(makeDemoSkeleton(), kDemoFps, frameCount);
    leftContact.assign(static_cast<std::size_t>(frameCount), 0);
    rightContact.assign(static_cast<std::size_t>(frameCount), 0);
    SolvedFrame sf;
    for (int f = 0; f < frameCount; ++f) {
        solveFrame(timeline, f / kDemoFps, sf);
        auto T = motion.translations(f);
        auto R = motion.rotations(f);
        T[0] = glm::vec3(sf.root);
        for (int j = 0; j < kJointCount; ++j) {
            dquat q = glm::normalize(sf.local[static_cast<std::size_t>(j)]);
            if (q.w < 0) q = -q;  // one sign per rotation keeps exported values stable
            R[static_cast<std::size_t>(j)] = glm::quat(q);
        }
        leftContact[static_cast<std::size_t>(f)] = sf.contact[0] ? 1 : 0;
        rightContact[static_cast<std::size_t>(f)] = sf.contact[1] ? 1 : 0;
    }
    motion.source().format = "bvh";
    motion.source().normalized = true;
    return motion;
}

}  // namespace fray::demo::detail
