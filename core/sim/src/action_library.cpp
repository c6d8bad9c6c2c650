#include "fray/sim/action_library.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <glm/geometric.hpp>

#include "fray/core/kinematics.h"
#include "fray/sim/action_catalogue.h"
#include "fray/sim/segment_boxes.h"
#include "interaction.h"

namespace fray::sim {

namespace {

struct SegmentDef {
    int Segment;
    float halfSide, halfDepth, pad;
};

// Cross-section half sizes and end padding (m) of each segment's box: a lean
// adult body, a little generous at the fists and feet.
constexpr SegmentDef kSegmentDefs[kSegmentCount] = {
    {kPelvis, 0.16f, 0.11f, 0.04f},     {kTorso, 0.17f, 0.11f, 0.02f},       {kHead, 0.09f, 0.10f, 0.06f},
    {kLeftUpperArm, 0.05f, 0.05f, 0.02f}, {kLeftForearm, 0.045f, 0.045f, 0.08f},
    {kRightUpperArm, 0.05f, 0.05f, 0.02f}, {kRightForearm, 0.045f, 0.045f, 0.08f},
    {kLeftThigh, 0.075f, 0.075f, 0.02f},  {kLeftShin, 0.055f, 0.055f, 0.02f}, {kLeftFoot, 0.045f, 0.05f, 0.04f},
    {kRightThigh, 0.075f, 0.075f, 0.02f}, {kRightShin, 0.055f, 0.055f, 0.02f}, {kRightFoot, 0.045f, 0.05f, 0.04f},
};

}  // namespace

glm::vec3 segmentTip(const Obb& box, int segment) {
    return box.centre + box.axes[0] * (box.half.x - kSegmentDefs[segment].pad);
}

std::pair<int, int> segmentJoints(int segment, const StandardJoints& j);

std::array<Obb, kSegmentCount> segmentBoxes(std::span<const glm::vec3> world, const StandardJoints& j) {
    auto at = [&](int joint) { return world[static_cast<std::size_t>(joint)]; };
    const glm::vec3 right = at(j.rightHip) - at(j.leftHip);
    std::array<Obb, kSegmentCount> boxes;
    for (int seg = 0; seg < kSegmentCount; ++seg) {
        const auto [j0, j1] = segmentJoints(seg, j);
        const auto& d = kSegmentDefs[seg];
        if (j0 >= 0 && j1 >= 0) {
            boxes[static_cast<std::size_t>(seg)] = segmentBox(at(j0), at(j1), d.halfSide, d.halfDepth, d.pad, right);
        } else {
            // A missing joint (e.g. no toe): a small box at the near joint.
            const int jj = j0 >= 0 ? j0 : (j1 >= 0 ? j1 : j.pelvis);
            boxes[static_cast<std::size_t>(seg)] =
                segmentBox(at(jj), at(jj) + glm::vec3(0, 0.01f, 0), d.halfSide, d.halfDepth, d.pad, right);
        }
    }
    return boxes;
}

namespace {

std::uint32_t flagsOf(const std::vector<std::string>& annotations) { return actionFlags(annotations); }

}  // namespace

// The two joints a segment's box spans (-1 when the skeleton lacks one).
std::pair<int, int> segmentJoints(int segment, const StandardJoints& j) {
    switch (segment) {
        case kPelvis: return {j.pelvis, j.spine >= 0 && j.spine != j.pelvis ? j.spine : j.chest};
        case kTorso: return {j.spine >= 0 ? j.spine : j.pelvis, j.neck >= 0 ? j.neck : j.head};
        case kHead: return {j.neck >= 0 ? j.neck : j.head, j.head};
        case kLeftUpperArm: return {j.leftShoulder, j.leftElbow};
        case kLeftForearm: return {j.leftElbow, j.leftHand};
        case kRightUpperArm: return {j.rightShoulder, j.rightElbow};
        case kRightForearm: return {j.rightElbow, j.rightHand};
        case kLeftThigh: return {j.leftHip, j.leftKnee};
        case kLeftShin: return {j.leftKnee, j.leftFoot};
        case kLeftFoot: return {j.leftFoot, j.leftToe};
        case kRightThigh: return {j.rightHip, j.rightKnee};
        case kRightShin: return {j.rightKnee, j.rightFoot};
        case kRightFoot: return {j.rightFoot, j.rightToe};
        default: return {-1, -1};
    }
}

namespace {

// The segment an attack lands with, from a "joints used" name.
int effectorFromJoint(int joint, const StandardJoints& j) {
    if (joint < 0) return -1;
    if (joint == j.leftHand || joint == j.leftElbow) return kLeftForearm;
    if (joint == j.rightHand || joint == j.rightElbow) return kRightForearm;
    if (joint == j.leftFoot || joint == j.leftToe) return kLeftShin;
    if (joint == j.rightFoot || joint == j.rightToe) return kRightShin;
    if (joint == j.leftKnee) return kLeftThigh;
    if (joint == j.rightKnee) return kRightThigh;
    return -1;
}

// The far joint of an effector segment: its speed is the attack's speed.
int effectorTip(int segment, const StandardJoints& j) {
    switch (segment) {
        case kLeftForearm: return j.leftHand;
        case kRightForearm: return j.rightHand;
        case kLeftShin: return j.leftFoot;
        case kRightShin: return j.rightFoot;
        case kLeftThigh: return j.leftKnee;
        case kRightThigh: return j.rightKnee;
        default: return -1;
    }
}

}  // namespace

const char* segmentName(int segment) {
    static const char* const names[kSegmentCount] = {"pelvis",     "torso",      "head",      "left_upper_arm", "left_forearm",
                                                     "right_upper_arm", "right_forearm", "left_thigh", "left_shin",
                                                     "left_foot",  "right_thigh", "right_shin", "right_foot"};
    return segment >= 0 && segment < kSegmentCount ? names[segment] : "?";
}

std::string LibraryAction::label() const {
    if (!name.empty()) return name;
    return motionId + ":" + std::to_string(firstFrame) + "-" + std::to_string(lastFrame);
}

bool LibraryAction::has(const std::string& annotation) const {
    return std::find(annotations.begin(), annotations.end(), annotation) != annotations.end();
}

int ActionLibrary::sampleAt(int action, double t) const {
    const auto& a = actions_[static_cast<std::size_t>(action)];
    const int s = static_cast<int>(std::floor(t * kSampleRate + 1e-9));
    return std::clamp(s, 0, a.sampleCount - 1);
}

RootXf ActionLibrary::rootAt(int action, double t) const {
    const auto& a = actions_[static_cast<std::size_t>(action)];
    const double x = std::clamp(t * kSampleRate, 0.0, static_cast<double>(a.sampleCount - 1));
    const int s0 = static_cast<int>(x);
    const int s1 = std::min(s0 + 1, a.sampleCount - 1);
    const auto& r0 = roots_[static_cast<std::size_t>(a.sampleBegin + s0)];
    const auto& r1 = roots_[static_cast<std::size_t>(a.sampleBegin + s1)];
    return lerp(r0, r1, x - s0);
}

int ActionLibrary::frameAt(int action, double t) const {
    const auto& a = actions_[static_cast<std::size_t>(action)];
    const double fps = motions_[static_cast<std::size_t>(a.motion)]->motion.fps();
    const int f = a.firstFrame + static_cast<int>(std::lround(t * fps));
    return std::clamp(f, a.firstFrame, a.lastFrame);
}

bool ActionLibrary::continuesInto(int from, int to) const {
    const auto f = static_cast<std::size_t>(from), t = static_cast<std::size_t>(to);
    if (startNode_[t] == endNode_[f]) return true;
    for (int n : next_[f]) {
        const auto k = static_cast<std::size_t>(n);
        if (n == to || (variantClass_[k] == variantClass_[t] && startNode_[k] == startNode_[t])) return true;
    }
    return false;
}

std::vector<int> ActionLibrary::select(const std::string& key) const {
    std::vector<int> out;
    const bool annotation = !key.empty() && key[0] == '@';
    const std::string word = annotation ? key.substr(1) : key;
    for (int i = 0; i < size(); ++i) {
        const auto& a = actions_[static_cast<std::size_t>(i)];
        const bool hit = annotation ? std::find(a.annotations.begin(), a.annotations.end(), word) != a.annotations.end()
                                    : a.name == word;
        if (hit) out.push_back(i);
    }
    return out;
}

ActionLibrary ActionLibrary::catalogue(std::vector<LibraryAction> actions, std::vector<std::string> vocabulary) {
    ActionLibrary lib;
    lib.actions_ = std::move(actions);
    lib.vocabulary_ = std::move(vocabulary);
    lib.reactionMemo_ = std::make_shared<detail::ReactionMemo>();
    return lib;
}

std::vector<prep::ActionRef> projectActionRefs(const prep::Project& project) {
    std::vector<prep::ActionRef> refs;
    for (std::size_t m = 0; m < project.motions.size(); ++m) {
        const auto& doc = project.motions[m].actions;
        for (int k = 0; k < doc.actionCount(); ++k) refs.push_back({static_cast<int>(m), doc.firstFrame(k), doc.lastFrame(k)});
    }
    return refs;
}

Result<ActionLibrary> buildActionLibrary(const prep::Project& project, std::span<const prep::LoadedMotion> motions,
                                         const prep::MotionGraph& graph, const ProgressFn& progress) {
    std::vector<std::shared_ptr<const prep::LoadedMotion>> shared;
    shared.reserve(motions.size());
    for (const auto& m : motions) shared.push_back(std::make_shared<const prep::LoadedMotion>(m));
    return buildActionLibrary(project, std::move(shared), graph, progress);
}

Result<ActionLibrary> buildActionLibrary(const prep::Project& project, std::vector<std::shared_ptr<const prep::LoadedMotion>> motions,
                                         const prep::MotionGraph& graph, const ProgressFn& progress) {
    for (std::size_t m = 0; m < motions.size(); ++m) {
        if (!motions[m]) return makeError("action library: motion " + std::to_string(m + 1) + " is missing (not loaded)");
    }
    if (motions.size() != project.motions.size()) {
        return makeError("action library: " + std::to_string(motions.size()) + " motions loaded for a project of " +
                         std::to_string(project.motions.size()));
    }
    const auto refs = projectActionRefs(project);
    if (refs.empty()) return makeError("action library: the project has no actions (import and segment motions first)");
    if (graph.startNode.size() != refs.size() || graph.next.size() != refs.size()) {
        return makeError("action library: the motion graph covers " + std::to_string(graph.startNode.size()) +
                         " actions, the project has " + std::to_string(refs.size()) + " (rebuild the graph)");
    }
    ActionLibrary lib;
    lib.motions_ = motions;  // shared: frameAt reads them while building
    lib.reactionMemo_ = std::make_shared<detail::ReactionMemo>();
    lib.vocabulary_ = project.vocabulary;
    lib.next_ = graph.next;
    lib.inLargestScc_ = graph.inLargestScc;
    lib.startNode_ = graph.startNode;
    lib.endNode_ = graph.endNode;
    lib.actions_.reserve(refs.size());

    for (std::size_t m = 0; m < motions.size(); ++m) {
        const auto& lm = *motions[m];
        const auto& motion = lm.motion;
        const auto& j = lm.joints;
        if (!j.complete()) {
            return makeError("action library: motion '" + lm.id + "' lacks standard joints (" + j.missing() + ")");
        }
        const auto& doc = project.motions[m].actions;
        if (doc.frameCount != motion.frameCount()) {
            return makeError("action library: motion '" + lm.id + "' has " + std::to_string(motion.frameCount()) +
                             " frames but its cuts were made for " + std::to_string(doc.frameCount) + " (segment it again)");
        }
        const auto jc = static_cast<std::size_t>(motion.jointCount());
        const auto world = worldPositions(motion, 0, motion.frameCount() - 1);
        auto at = [&](int frame, int joint) { return world[static_cast<std::size_t>(frame) * jc + static_cast<std::size_t>(joint)]; };
        auto span = [&](int frame) { return std::span<const glm::vec3>(world.data() + static_cast<std::size_t>(frame) * jc, jc); };
        auto placement = [&](int frame) {
            const glm::vec3 p = at(frame, j.pelvis);
            return RootXf{{p.x, p.z}, prep::headingOf(span(frame), j)};
        };
        const double fps = motion.fps();

        for (int k = 0; k < doc.actionCount(); ++k) {
            if (!reportProgress(progress, static_cast<double>(lib.actions_.size()) / static_cast<double>(refs.size()),
                                "action library")) {
                return cancelled();
            }
            const auto& info = doc.actions[static_cast<std::size_t>(k)];
            LibraryAction a;
            a.motion = static_cast<int>(m);
            a.firstFrame = doc.firstFrame(k);
            a.lastFrame = doc.lastFrame(k);
            a.motionId = lm.id;
            a.name = info.name;
            a.annotations = info.annotations;
            a.flags = flagsOf(info.annotations);
            const int frames = a.lastFrame - a.firstFrame + 1;
            a.duration = frames / fps;
            a.sampleBegin = static_cast<int>(lib.roots_.size());
            a.sampleCount = static_cast<int>(std::floor(a.duration * kSampleRate)) + 1;

            const RootXf start = placement(a.firstFrame);
            a.source = start;
            const RootXf toLocal = start.inverse();
            auto localOf = [&](int frame) { return toLocal * placement(frame); };
            // The next action starts one frame after the last: extrapolate.
            const RootXf last = localOf(a.lastFrame);
            if (frames >= 2) {
                const RootXf prev = localOf(a.lastFrame - 1);
                a.end = {last.pos + (last.pos - prev.pos), wrapAngle(last.heading + wrapAngle(last.heading - prev.heading))};
            } else {
                a.end = last;
            }

            // Effector of attacks: from "joints used", else the fastest limb.
            auto tipSpeed = [&](int tip, int frame) {
                const int f0 = std::max(frame - 1, 0), f1 = std::min(frame + 1, motion.frameCount() - 1);
                if (f1 == f0) return 0.0;
                return static_cast<double>(glm::length(at(f1, tip) - at(f0, tip))) * fps / (f1 - f0);
            };
            if (a.is(kAttack)) {
                for (const auto& name : info.joints) {
                    a.effector = effectorFromJoint(motion.skeleton().find(name), j);
                    if (a.effector >= 0) break;
                }
                if (a.effector < 0) {
                    // A punch lands with an arm and a kick with a leg: a real
                    // lunge punch steps forward, and its stepping ankle can
                    // move faster than the fist (CMU oi-zuki). Other attacks
                    // (tackle, both) take the fastest limb.
                    double best = -1;
                    std::vector<int> candidates;
                    if (a.is(kPunch) != a.is(kKick)) {
                        candidates = a.is(kPunch) ? std::vector<int>{kLeftForearm, kRightForearm} : std::vector<int>{kLeftShin, kRightShin};
                    } else {
                        candidates = {kLeftForearm, kRightForearm, kLeftShin, kRightShin};
                    }
                    for (int seg : candidates) {
                        const int tip = effectorTip(seg, j);
                        for (int f = a.firstFrame; f <= a.lastFrame; ++f) {
                            const double v = tipSpeed(tip, f);
                            if (v > best) best = v, a.effector = seg;
                        }
                    }
                }
            }
            if (a.is(kBlock) && info.defendedPart) {
                a.defended = *info.defendedPart == "torso" ? kTorso : kHead;
            } else if (a.is(kBlock)) {
                a.defended = kHead;
            }

            const int tip = a.effector >= 0 ? effectorTip(a.effector, j) : -1;
            std::vector<double> extension;
            for (int s = 0; s < a.sampleCount; ++s) {
                const int f = std::clamp(a.firstFrame + static_cast<int>(std::lround(s / kSampleRate * fps)), a.firstFrame,
                                         a.lastFrame);
                lib.roots_.push_back(localOf(f));
                const glm::vec3 origin(start.pos.x, 0.0f, start.pos.y);
                for (Obb box : segmentBoxes(span(f), j)) {
                    box.centre -= origin;
                    lib.boxes_.push_back(box.placed(RootXf{{0.0f, 0.0f}, toLocal.heading}));
                }
                const double v = tip >= 0 ? tipSpeed(tip, f) : 0.0;
                lib.effectorSpeed_.push_back(static_cast<float>(v));
                if (tip >= 0) {
                    const glm::vec3 e = at(f, tip) - at(f, j.pelvis);
                    extension.push_back(std::sqrt(e.x * e.x + e.z * e.z));
                }
            }
            if (tip >= 0) {
                // Active window: the run of fast samples around the peak,
                // extended to full extension (where a blow usually lands).
                const float* sp = &lib.effectorSpeed_[static_cast<std::size_t>(a.sampleBegin)];
                int peak = 0;
                for (int s = 1; s < a.sampleCount; ++s) {
                    if (sp[s] > sp[peak]) peak = s;
                }
                a.peakSpeed = sp[peak];
                const float floorSpeed = static_cast<float>(std::max(0.4 * a.peakSpeed, 1.0));
                int b = peak, e = peak;
                while (b > 0 && sp[b - 1] >= floorSpeed) --b;
                while (e + 1 < a.sampleCount && sp[e + 1] >= floorSpeed) ++e;
                int reach = peak;
                for (int s = peak; s < a.sampleCount && s <= e + static_cast<int>(0.2 * kSampleRate); ++s) {
                    if (extension[static_cast<std::size_t>(s)] > extension[static_cast<std::size_t>(reach)]) reach = s;
                }
                a.activeBegin = b;
                a.activeEnd = std::max(e, reach) + 1;
                for (int sk = a.activeBegin; sk < a.activeEnd; ++sk) {
                    const Obb& box = lib.boxes_[static_cast<std::size_t>(a.sampleBegin + sk) * kSegmentCount +
                                               static_cast<std::size_t>(a.effector)];
                    const double front = box.centre.z + box.half.x * std::fabs(box.axes[0].z);
                    a.reach = std::max(a.reach, front);
                }
            }
            lib.actions_.push_back(std::move(a));
        }
    }
    // Variant classes (see the header): unnamed, unannotated actions are their own class.
    {
        std::map<std::pair<std::string, int>, int> classes;
        lib.variantClass_.resize(lib.actions_.size());
        for (int i = 0; i < lib.size(); ++i) {
            const auto& a = lib.actions_[static_cast<std::size_t>(i)];
            std::string key = a.name;
            if (key.empty()) {
                for (const auto& w : a.annotations) key += "@" + w;
            }
            if (key.empty()) key = "#" + std::to_string(i);
            const auto [it, inserted] =
                classes.emplace(std::make_pair(key, lib.endNode_[static_cast<std::size_t>(i)]), static_cast<int>(classes.size()));
            lib.variantClass_[static_cast<std::size_t>(i)] = it->second;
        }
    }
    // Reactive clips: pose features of their first part for matching.
    for (int i = 0; i < lib.size(); ++i) {
        const auto& a = lib.actions_[static_cast<std::size_t>(i)];
        if (!a.is(kReactive)) continue;
        const auto& lm = *motions[static_cast<std::size_t>(a.motion)];
        const int upto = std::max(1, static_cast<int>(0.35 * a.sampleCount));
        for (int s = 0; s < upto; s += 2) {
            lib.reactions_.push_back({i, s, prep::poseFeature(lm.motion, lm.joints, lib.frameAt(i, s / kSampleRate))});
            lib.reactionPoses_.add(lib.reactions_.back().feature);
        }
    }
    reportProgress(progress, 1.0, "action library");
    return lib;
}

}  // namespace fray::sim
