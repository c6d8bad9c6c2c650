#include "retarget_export.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "fray/core/body_mesh.h"
#include "fray/core/ik.h"
#include "fray/core/joint_guess.h"
#include "fray/core/kinematics.h"

namespace fray::exporter {

std::optional<RootMotion> parseRootMotion(std::string_view name) {
    if (name == "none") return RootMotion::None;
    if (name == "floor") return RootMotion::Floor;
    if (name == "in-place") return RootMotion::InPlace;
    return std::nullopt;
}

Status retargetCharacters(SampledScene& scene, const RetargetTarget& rig, std::vector<std::string>& notes,
                          std::vector<char>* retargeted) {
    if (retargeted) retargeted->assign(scene.characters.size(), 0);
    int done = 0;
    std::string firstRefusal;
    for (CharacterTake& c : scene.characters) {
        // A creature without feet (a rat, a bag) keeps its own skeleton.
        if (auto st = checkRetargetable(c.motion.skeleton(), "character '" + c.name + "'"); !st) {
            notes.push_back(st.error().message + "; it keeps its own skeleton");
            if (firstRefusal.empty()) firstRefusal = st.error().message;
            continue;
        }
        Motion source = c.motion;
        source.source().path = "character '" + c.name + "'";
        RetargetReport report;
        auto out = retarget(source, rig, {}, &report);
        if (!out) return out.error();
        // Keep quaternions in one hemisphere from frame to frame (importers interpolate component-wise).
        for (int f = 1; f < out->frameCount(); ++f) {
            auto q = out->rotations(f);
            const auto prev = out->rotations(f - 1);
            for (std::size_t j = 0; j < q.size(); ++j)
                if (glm::dot(q[j], prev[j]) < 0.0f) q[j] = -q[j];
        }
        c.motion = std::move(*out);
        notes.push_back(report.text());
        if (retargeted) (*retargeted)[static_cast<std::size_t>(&c - scene.characters.data())] = 1;
        ++done;
    }
    if (done == 0) return makeError("--rig " + rig.name + ": no character of the scene can be retargeted: " + firstRefusal);
    return {};
}

namespace {

// Closest point to p on the segment a-b.
glm::vec3 closestOnSegment(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b) {
    const glm::vec3 d = b - a;
    const float len2 = glm::dot(d, d);
    const float t = len2 > 1e-12f ? std::clamp(glm::dot(p - a, d) / len2, 0.0f, 1.0f) : 0.0f;
    return a + t * d;
}

}  // namespace

int landHits(SampledScene& sampled, const sim::Scene& scene, const std::vector<char>& retargeted) {
    int moved = 0;
    const int frames = sampled.frames;
    const int window = std::max(1, static_cast<int>(std::ceil(0.2 * sampled.fps)));
    for (const sim::HitEvent& h : scene.hits) {
        const auto ai = static_cast<std::size_t>(h.attacker), di = static_cast<std::size_t>(h.defender);
        if (ai >= sampled.characters.size() || di >= sampled.characters.size() || !retargeted[ai]) continue;
        Motion& a = sampled.characters[ai].motion;
        const Motion& d = sampled.characters[di].motion;
        const StandardJoints sj = guessStandardJoints(a.skeleton());
        int upper = -1, mid = -1, end = -1, tip = -1;
        switch (h.effector) {
            case sim::kLeftForearm: upper = sj.leftShoulder, mid = sj.leftElbow, end = tip = sj.leftHand; break;
            case sim::kRightForearm: upper = sj.rightShoulder, mid = sj.rightElbow, end = tip = sj.rightHand; break;
            case sim::kLeftShin: upper = sj.leftHip, mid = sj.leftKnee, end = tip = sj.leftFoot; break;
            case sim::kRightShin: upper = sj.rightHip, mid = sj.rightKnee, end = tip = sj.rightFoot; break;
            case sim::kLeftFoot: upper = sj.leftHip, mid = sj.leftKnee, end = sj.leftFoot, tip = sj.leftToe >= 0 ? sj.leftToe : sj.leftFoot; break;
            case sim::kRightFoot: upper = sj.rightHip, mid = sj.rightKnee, end = sj.rightFoot, tip = sj.rightToe >= 0 ? sj.rightToe : sj.rightFoot; break;
            default: break;
        }
        if (upper < 0 || mid < 0 || end < 0 || tip < 0) continue;
        // The hit's frame: the sample nearest the hit time.
        int fh = 0;
        for (int f = 1; f < frames; ++f)
            if (std::abs(sampled.time(f) - h.time) < std::abs(sampled.time(fh) - h.time)) fh = f;
        std::vector<glm::vec3> ap(static_cast<std::size_t>(a.jointCount())), dp(static_cast<std::size_t>(d.jointCount()));
        std::vector<glm::quat> ar(ap.size()), dr(dp.size());
        worldTransforms(a, fh, ap, ar);
        worldTransforms(d, fh, dp, dr);
        // The nearest point of the defender's body surface (its capsules).
        const glm::vec3 t = ap[static_cast<std::size_t>(tip)];
        float best = 1e30f;
        glm::vec3 onSurface = t;
        for (const BodyCapsule& c : bodyCapsules(d.skeleton())) {
            const glm::vec3 q = closestOnSegment(t, dp[c.joint] + dr[c.joint] * c.a, dp[c.joint] + dr[c.joint] * c.b);
            const float dist = glm::length(t - q) - c.radius;
            if (dist < best) {
                best = dist;
                onSurface = dist > 0.0f ? q + (t - q) * (c.radius / glm::length(t - q)) : t;
            }
        }
        const glm::vec3 delta = onSurface - t;
        if (glm::length(delta) < 1e-4f) continue;
        ++moved;
        for (int f = std::max(0, fh - window); f <= std::min(frames - 1, fh + window); ++f) {
            const float w = 1.0f - static_cast<float>(std::abs(f - fh)) / static_cast<float>(window + 1);
            const float smooth = w * w * (3.0f - 2.0f * w);
            worldTransforms(a, f, ap, ar);
            const glm::quat endWorld = ar[static_cast<std::size_t>(end)];
            applyTwoBoneIk(a.skeleton(), a.rotations(f), ap, ar, upper, mid, end,
                           ap[static_cast<std::size_t>(end)] + smooth * delta, &endWorld);
        }
    }
    return moved;
}

void addRootBone(Motion& motion, RootMotion mode) {
    if (mode == RootMotion::None || motion.jointCount() == 0) return;
    const Skeleton& old = motion.skeleton();
    std::string name(kRootBoneName);
    if (old.find(name) >= 0) name = "fray_root";
    for (int k = 2; old.find(name) >= 0; ++k) name = "fray_root" + std::to_string(k);
    Skeleton sk;
    sk.addJoint(name, -1, glm::vec3(0), {Channel::Xposition, Channel::Yposition, Channel::Zposition, Channel::Zrotation,
                                         Channel::Xrotation, Channel::Yrotation},
                RotationOrder::ZXY);
    for (int j = 0; j < old.jointCount(); ++j) {
        const auto u = static_cast<std::size_t>(j);
        std::vector<Channel> channels = old.channels[u];
        if (j == 0 && !old.hasPositionChannels(0))
            channels.insert(channels.begin(), {Channel::Xposition, Channel::Yposition, Channel::Zposition});
        // The old root's rest offset: where it stands above the floor at the
        // start (a bone of length zero would confuse importers).
        glm::vec3 rest = old.offsets[u];
        if (j == 0) rest = motion.frameCount() > 0 ? glm::vec3(0.0f, motion.translations(0)[0].y, 0.0f) : glm::vec3(0);
        sk.addJoint(old.names[u], old.parents[u] < 0 ? 0 : old.parents[u] + 1, rest, std::move(channels),
                    old.rotationOrders[u]);
        sk.endSites.back() = old.endSites[u];
    }
    const StandardJoints sj = guessStandardJoints(old);
    const bool hips = sj.leftHip >= 0 && sj.rightHip >= 0 && sj.leftHip != sj.rightHip;
    Motion out(sk, motion.fps(), motion.frameCount());
    out.source() = motion.source();
    const auto jc = static_cast<std::size_t>(old.jointCount());
    std::vector<glm::vec3> pos(jc);
    std::vector<glm::quat> rot(jc);
    glm::quat prevRoot(1, 0, 0, 0);
    for (int f = 0; f < motion.frameCount(); ++f) {
        worldTransforms(motion, f, pos, rot);
        // Heading: perpendicular to the hip line on the floor (or the root's own forward).
        glm::vec3 forward = hips ? glm::cross(pos[static_cast<std::size_t>(sj.leftHip)] - pos[static_cast<std::size_t>(sj.rightHip)],
                                              glm::vec3(0, 1, 0))
                                 : rot[0] * glm::vec3(0, 0, 1);
        forward.y = 0.0f;
        const float yaw = glm::length(forward) > 1e-6f ? std::atan2(forward.x, forward.z) : 0.0f;
        glm::quat heading = glm::angleAxis(yaw, glm::vec3(0, 1, 0));
        if (glm::dot(heading, prevRoot) < 0.0f) heading = -heading;
        prevRoot = heading;
        const glm::vec3 floor(pos[0].x, 0.0f, pos[0].z);
        auto T = out.translations(f);
        auto R = out.rotations(f);
        const auto src = motion.translations(f);
        const auto srq = motion.rotations(f);
        T[0] = mode == RootMotion::Floor ? floor : glm::vec3(0);
        R[0] = mode == RootMotion::Floor ? heading : glm::quat(1, 0, 0, 0);
        // The old root relative to the trajectory (the same in both modes).
        T[1] = glm::inverse(heading) * (pos[0] - floor);
        R[1] = glm::normalize(glm::inverse(heading) * srq[0]);
        if (f > 0 && glm::dot(R[1], out.rotations(f - 1)[1]) < 0.0f) R[1] = -R[1];
        for (std::size_t j = 1; j < jc; ++j) {
            T[j + 1] = src[j];
            R[j + 1] = srq[j];
        }
    }
    motion = std::move(out);
}

}  // namespace fray::exporter
