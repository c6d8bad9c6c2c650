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

// Standing pelvis height of a take: the 90th percentile of the pelvis height
// (0 when the signals have no posture). Computed once per take.
double standingPelvisHeight(const MotionSignals& signals) {
    std::vector<float> heights;
    for (int f = 0; f < signals.frameCount && !signals.posture.empty(); f += std::max(1, signals.frameCount / 400)) {
        heights.push_back(signals.posture[static_cast<std::size_t>(f)][0]);
    }
    if (heights.empty()) return 0.0;
    std::sort(heights.begin(), heights.end());
    return double(heights[heights.size() * 9 / 10]);
}

Proposal propose(const Motion& motion, const StandardJoints& joints, double standing, int first, int last,
                 const ProposalParams& params) {
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

    // Effector peak speeds: hands -> punch, feet -> kick (relative to the pelvis,
    // so running legs do not read as kicks).
    struct Effector {
        int joint;
        const char* word;
    };
    const Effector effectors[] = {{joints.leftHand, "punch"},
                                  {joints.rightHand, "punch"},
                                  {joints.leftFoot, "kick"},
                                  {joints.rightFoot, "kick"}};
    double best = 0.0;
    int bestJoint = -1;
    const char* bestWord = nullptr;
    for (const auto& e : effectors) {
        if (e.joint < 0) continue;
        for (int f = 1; f < frames; ++f) {
            const glm::vec3 rel1 = at(f, e.joint) - at(f, joints.pelvis);
            const glm::vec3 rel0 = at(f - 1, e.joint) - at(f - 1, joints.pelvis);
            const double v = double(glm::length(rel1 - rel0)) * motion.fps();
            if (v > best) best = v, bestJoint = e.joint, bestWord = e.word;
        }
    }

    // Pelvis travel and height.
    const glm::vec3 p0 = at(0, joints.pelvis), p1 = at(frames - 1, joints.pelvis);
    const double seconds = std::max(1e-6, (frames - 1) / motion.fps());
    const double travelSpeed = double(glm::length(glm::vec2(p1.x - p0.x, p1.z - p0.z))) / seconds;
    float minPelvis = p0.y;
    for (int f = 0; f < frames; ++f) minPelvis = std::min(minPelvis, at(f, joints.pelvis).y);
    const bool falling = standing > 0.0 && double(minPelvis) < params.fallHeightRatio * standing;

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
    if (!falling && best >= params.attackSpeed && bestWord) {
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
    return propose(motion, joints, standingPelvisHeight(signals), first, last, params);
}

void proposeAll(MotionActions& doc, const Motion& motion, const StandardJoints& joints, const MotionSignals& signals,
                const ProposalParams& params) {
    const double standing = standingPelvisHeight(signals);
    for (int a = 0; a < doc.actionCount(); ++a) {
        auto& info = doc.actions[static_cast<std::size_t>(a)];
        const Proposal p = propose(motion, joints, standing, doc.firstFrame(a), doc.lastFrame(a), params);
        info.proposed.clear();
        for (const auto& w : p.annotations) {
            if (!info.has(w)) info.proposed.push_back(w);
        }
        if (info.joints.empty()) info.joints = p.joints;
    }
}

}  // namespace fray::prep
