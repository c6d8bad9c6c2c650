#include "fray/prep/annotations.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fray/core/kinematics.h"

namespace fray::prep {

const std::vector<std::string>& defaultVocabulary() {
    static const std::vector<std::string> words = {"punch", "kick", "avoid", "dodge",   "block", "step",
                                                   "transition", "falling", "pushed", "run", "jump", "tackle",
                                                   "carry", "walk", "hand", "receive", "turn", "idle"};
    return words;
}

bool isValidAnnotation(const std::string& word) {
    if (word.empty() || word.size() > 32) return false;
    return std::all_of(word.begin(), word.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    });
}

namespace {

// Standing heights of a take (pelvis and head, 90th percentiles; 0 when the
// signals have no posture). Computed once per take.
struct Standing {
    double pelvis = 0.0;
    double head = 0.0;
};
Standing standingHeights(const MotionSignals& signals) {
    std::vector<float> pelvis, head;
    for (int f = 0; f < signals.frameCount && !signals.posture.empty(); f += std::max(1, signals.frameCount / 400)) {
        pelvis.push_back(signals.posture[static_cast<std::size_t>(f)][0]);
        head.push_back(signals.posture[static_cast<std::size_t>(f)][1]);
    }
    if (pelvis.empty()) return {};
    std::sort(pelvis.begin(), pelvis.end());
    std::sort(head.begin(), head.end());
    return {double(pelvis[pelvis.size() * 9 / 10]), double(head[head.size() * 9 / 10])};
}

Proposal propose(const Motion& motion, const StandardJoints& joints, const MotionSignals& signals,
                 const Standing& standing, int first, int last, const ProposalParams& params) {
    Proposal out;
    first = std::clamp(first, 0, motion.frameCount() - 1);
    last = std::clamp(last, first, motion.frameCount() - 1);
    if (joints.pelvis < 0) return out;
    const auto world = worldPositions(motion, first, last);
    const auto J = static_cast<std::size_t>(motion.jointCount());
    const int frames = last - first + 1;
    auto at = [&](int f, int j) { return world[static_cast<std::size_t>(f) * J + static_cast<std::size_t>(j)]; };
    auto add = [&](const char* word) {
        if (std::find(out.annotations.begin(), out.annotations.end(), word) == out.annotations.end())
            out.annotations.emplace_back(word);
    };
    const double H = signals.bodyHeight > 0.0 ? signals.bodyHeight : 1.7;
    const double floorY = std::min(signals.ankleFloor[0], signals.ankleFloor[1]);
    // Speed of joint j relative to the pelvis at local frame f (H/s).
    auto relSpeed = [&](int f, int j) {
        const int a = std::max(0, f - 1), b = std::min(frames - 1, f + 1);
        if (a == b) return 0.0;
        const glm::vec3 d = (at(b, j) - at(b, joints.pelvis)) - (at(a, j) - at(a, joints.pelvis));
        return double(glm::length(d)) * motion.fps() / double(b - a) / H;
    };

    // Attacks: the effector with the most decisive attack (highest speed
    // among those that reach out as an attack does).
    double best = 0.0;
    int bestJoint = -1;
    const char* bestWord = nullptr;
    struct Arm {
        int hand, elbow, shoulder;
    };
    for (const Arm arm : {Arm{joints.leftHand, joints.leftElbow, joints.leftShoulder},
                          Arm{joints.rightHand, joints.rightElbow, joints.rightShoulder}}) {
        if (arm.hand < 0 || arm.shoulder < 0) continue;
        // The fast stroke must end where a punch lands: at chest height or
        // above (a jab, a hook, an uppercut), not down by the thigh (a low
        // block) - the stroke ends when the hand slows to half its peak speed.
        double peak = 0.0;
        int peakAt = 0;
        for (int f = 0; f < frames; ++f) {
            const double v = relSpeed(f, arm.hand);
            if (v > peak) peak = v, peakAt = f;
        }
        int end = peakAt;
        while (end + 1 < frames && relSpeed(end, arm.hand) > 0.5 * peak) ++end;
        // ... where the hand comes to a stop: a punch stops at the end of its
        // reach, a low block sweeps on down to the thigh.
        while (end + 1 < frames && relSpeed(end + 1, arm.hand) < relSpeed(end, arm.hand)) ++end;
        // ... and away from the body (a wind-up ends by the head).
        const double length = arm.elbow >= 0 ? double(glm::length(at(0, arm.elbow) - at(0, arm.shoulder)) +
                                                      glm::length(at(0, arm.hand) - at(0, arm.elbow)))
                                             : double(glm::length(at(0, arm.hand) - at(0, arm.shoulder)));
        const bool reaches = double(at(end, arm.hand).y) >= double(at(end, arm.shoulder).y) - params.punchHeight * H &&
                             double(glm::length(at(end, arm.hand) - at(end, arm.shoulder))) >= params.punchReach * length;
        if (reaches && peak >= params.attackSpeed && peak > best) best = peak, bestJoint = arm.hand, bestWord = "punch";
    }
    struct Leg {
        int foot, knee, otherFoot;
    };
    for (const Leg leg : {Leg{joints.leftFoot, joints.leftKnee, joints.rightFoot},
                          Leg{joints.rightFoot, joints.rightKnee, joints.leftFoot}}) {
        if (leg.foot < 0) continue;
        double peak = 0.0;
        bool raised = false;
        for (int f = 0; f < frames; ++f) {
            peak = std::max(peak, relSpeed(f, leg.foot));
            const double footUp = double(at(f, leg.foot).y) - floorY;
            const double otherUp = double(at(f, leg.otherFoot).y) - floorY;
            const bool knee = leg.knee < 0 || standing.pelvis <= 0.0 ||
                              double(at(f, leg.knee).y) - floorY >= params.kickKnee * (standing.pelvis - floorY);
            const bool upright = standing.pelvis <= 0.0 ||
                                 double(at(f, joints.pelvis).y) - floorY >= 0.75 * (standing.pelvis - floorY);
            if (footUp >= params.kickHeight * H && otherUp < footUp && knee && upright) raised = true;
        }
        if (raised && peak >= params.attackSpeed && peak > best) best = peak, bestJoint = leg.foot, bestWord = "kick";
    }

    // Pelvis travel and height.
    const glm::vec3 p0 = at(0, joints.pelvis), p1 = at(frames - 1, joints.pelvis);
    const double seconds = std::max(1e-6, (frames - 1) / motion.fps());
    const double travelSpeed = double(glm::length(glm::vec2(p1.x - p0.x, p1.z - p0.z))) / seconds;
    float minPelvis = p0.y;
    for (int f = 0; f < frames; ++f) minPelvis = std::min(minPelvis, at(f, joints.pelvis).y);
    bool falling = standing.pelvis > 0.0 && double(minPelvis) - floorY < params.fallHeightRatio * (standing.pelvis - floorY);
    if (joints.head >= 0 && standing.head > 0.0) {
        float minHead = at(0, joints.head).y;
        for (int f = 0; f < frames; ++f) minHead = std::min(minHead, at(f, joints.head).y);
        falling = falling || double(minHead) - floorY < params.fallHeadRatio * (standing.head - floorY);
    }

    // Heading change: from the hip line (left hip -> right hip) on the floor.
    double turn = 0.0;
    if (joints.leftHip >= 0 && joints.rightHip >= 0) {
        auto heading = [&](int f) {
            const glm::vec3 d = at(f, joints.rightHip) - at(f, joints.leftHip);
            return std::atan2(double(d.z), double(d.x));
        };
        double prev = heading(0);
        for (int f = 1; f < frames; ++f) {
            const double h = heading(f);
            double d = h - prev;
            while (d > std::numbers::pi) d -= 2 * std::numbers::pi;
            while (d < -std::numbers::pi) d += 2 * std::numbers::pi;
            turn += d;
            prev = h;
        }
    }
    double meanSpeed = 0.0;  // mean joint speed over the action
    for (int f = 1; f < frames; ++f) {
        for (std::size_t j = 0; j < J; ++j) {
            meanSpeed += double(glm::length(at(f, int(j)) - at(f - 1, int(j))));
        }
    }
    meanSpeed = frames > 1 ? meanSpeed * motion.fps() / double((frames - 1) * int(J)) : 0.0;

    if (falling) add("falling");
    if (!falling && bestWord) {
        add(bestWord);
        out.joints.push_back(motion.skeleton().names[static_cast<std::size_t>(bestJoint)]);
    }
    if (travelSpeed >= params.runSpeed) add("run");
    else if (travelSpeed >= params.walkSpeed) add("walk");
    if (std::abs(turn) * 180.0 / std::numbers::pi >= params.turnDegrees) add("turn");
    if (out.annotations.empty() && meanSpeed < params.idleSpeed) add("idle");
    return out;
}

}  // namespace

Proposal proposeAnnotations(const Motion& motion, const StandardJoints& joints, const MotionSignals& signals,
                            int first, int last, const ProposalParams& params) {
    return propose(motion, joints, signals, standingHeights(signals), first, last, params);
}

void proposeAll(MotionActions& doc, const Motion& motion, const StandardJoints& joints, const MotionSignals& signals,
                const ProposalParams& params) {
    const Standing standing = standingHeights(signals);
    for (int a = 0; a < doc.actionCount(); ++a) {
        auto& info = doc.actions[static_cast<std::size_t>(a)];
        const Proposal p = propose(motion, joints, signals, standing, doc.firstFrame(a), doc.lastFrame(a), params);
        info.proposed.clear();
        for (const auto& w : p.annotations) {
            if (!info.has(w)) info.proposed.push_back(w);
        }
        if (info.joints.empty()) info.joints = p.joints;
    }
}

}  // namespace fray::prep
