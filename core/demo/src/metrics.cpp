#include "fray/demo/metrics.h"

#include <algorithm>
#include <cmath>

#include "fray/core/kinematics.h"
#include "solver.h"
#include "timeline.h"

namespace fray::demo {

namespace {

constexpr double kRadToDeg = 57.29577951308232;

struct Positions {
    std::vector<glm::vec3> p;
    std::size_t joints = 0;
    glm::dvec3 at(int frame, int joint) const {
        return glm::dvec3(p[static_cast<std::size_t>(frame) * joints + static_cast<std::size_t>(joint)]);
    }
};

Positions positionsOf(const Motion& m) {
    Positions out;
    out.joints = static_cast<std::size_t>(m.jointCount());
    out.p = worldPositions(m, 0, m.frameCount() - 1);
    return out;
}

// Central-difference velocity of a joint (m/s).
glm::dvec3 velocity(const Positions& P, int frames, double fps, int f, int joint) {
    const int a = std::max(0, f - 1), b = std::min(frames - 1, f + 1);
    if (b == a) return glm::dvec3(0.0);
    return (P.at(b, joint) - P.at(a, joint)) * (fps / (b - a));
}

double angularSpeed(const Motion& m, int f, int joint) {
    const glm::dquat q0(m.rotations(f - 1)[static_cast<std::size_t>(joint)]);
    const glm::dquat q1(m.rotations(f)[static_cast<std::size_t>(joint)]);
    const double d = std::min(1.0, std::abs(glm::dot(glm::normalize(q0), glm::normalize(q1))));
    return 2.0 * std::acos(d) * m.fps() * kRadToDeg;
}

bool isAttack(const TruthAction& a) { return a.has("punch") || a.has("kick"); }

struct Peak {
    double speed = 0;
    glm::dvec3 velocity{0.0};
    int frame = -1;
};

// The strike of an attack: fastest frame of the attacking joint before its
// apex (a hand farthest from the chest; a kicking foot or knee at its
// highest), so the retraction and the landing do not count.
Peak strikePeak(const Positions& P, int frames, double fps, const TruthAction& a, int joint, const Skeleton& sk) {
    const bool kick = a.has("kick");
    const int chest = sk.find("Spine2");
    int apex = a.firstFrame;
    double best = -1e30;
    for (int f = a.firstFrame; f <= a.lastFrame; ++f) {
        const double reach = kick ? P.at(f, joint).y : glm::length(P.at(f, joint) - P.at(f, chest));
        if (reach > best) best = reach, apex = f;
    }
    Peak peak;
    for (int f = a.firstFrame; f <= apex; ++f) {
        const glm::dvec3 v = velocity(P, frames, fps, f, joint);
        if (glm::length(v) > peak.speed) peak = {glm::length(v), v, f};
    }
    return peak;
}

}  // namespace

namespace detail {

void measureAttacks(const Motion& motion, const Timeline& tl, std::vector<TruthAction>& actions) {
    if (motion.frameCount() < 2) return;
    const Positions P = positionsOf(motion);
    for (TruthAction& a : actions) {
        if (!isAttack(a) || a.joints.empty()) continue;
        const int j = motion.skeleton().find(a.joints.front());
        if (j < 0) continue;
        const Peak pk = strikePeak(P, motion.frameCount(), motion.fps(), a, j, motion.skeleton());
        const double h = tl[Heading].value(std::max(pk.frame, 0) / motion.fps());
        const glm::dvec3 local = glm::inverse(rotY(h)) * (pk.speed > 0 ? pk.velocity / pk.speed : glm::dvec3(0, 0, 1));
        a.attackVector = std::array<double, 3>{local.x, local.y, local.z};
        a.peakSpeed = pk.speed;
    }
}

}  // namespace detail

TakeMetrics measureTake(const Motion& m, const GroundTruth& truth) {
    TakeMetrics out;
    const int n = m.frameCount();
    if (n < 2) return out;
    const Positions P = positionsOf(m);
    const Skeleton& sk = m.skeleton();
    const int feet[2][2] = {{sk.find("LeftFoot"), sk.find("LeftToe")}, {sk.find("RightFoot"), sk.find("RightToe")}};
    double skateSum = 0;
    int skateCount = 0;
    out.minJointHeight = 1e30;
    for (int f = 0; f < n; ++f) {
        const auto fu = static_cast<std::size_t>(f);
        for (int j = 0; j < m.jointCount(); ++j) out.minJointHeight = std::min(out.minJointHeight, P.at(f, j).y);
        if (truth.leftContact[fu] || truth.rightContact[fu]) ++out.contactFrames;
        if (f == 0) continue;
        for (int side = 0; side < 2; ++side) {
            const auto& c = side == 0 ? truth.leftContact : truth.rightContact;
            if (!c[fu] || !c[fu - 1]) continue;
            for (int joint : feet[side]) {
                if (joint < 0) continue;
                const double d = glm::length(P.at(f, joint) - P.at(f - 1, joint));
                out.maxSkate = std::max(out.maxSkate, d);
                skateSum += d;
                ++skateCount;
            }
        }
        out.maxRootSpeed = std::max(out.maxRootSpeed, glm::length(P.at(f, 0) - P.at(f - 1, 0)) * m.fps());
    }
    out.meanSkate = skateCount ? skateSum / skateCount : 0.0;
    for (const TruthAction& a : truth.actions) {
        ActionMetrics am;
        am.name = a.name;
        am.style = a.style;
        am.seconds = a.frameCount() / truth.fps;
        const int eff = a.joints.empty() ? -1 : sk.find(a.joints.front());
        if (eff >= 0 && isAttack(a))
            am.peakEffectorSpeed = strikePeak(P, n, m.fps(), a, eff, sk).speed;
        for (int f = std::max(1, a.firstFrame); f <= a.lastFrame; ++f) {
            for (int j = 1; j < m.jointCount(); ++j) {
                const double w = angularSpeed(m, f, j);
                if (w > am.maxAngularSpeed) am.maxAngularSpeed = w, am.fastestJoint = sk.names[static_cast<std::size_t>(j)];
            }
        }
        if (am.maxAngularSpeed > out.maxAngularSpeed) out.maxAngularSpeed = am.maxAngularSpeed, out.fastestJoint = am.fastestJoint;
        out.actions.push_back(std::move(am));
    }
    return out;
}

}  // namespace fray::demo
